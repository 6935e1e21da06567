"""Helpers shared by the tests."""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from ppm_stiffness.design import Design, default_design, design_from_dict, load_design
from ppm_stiffness.maps.workspace import workspace_bounds

ROOT = Path(__file__).parents[1]


def design_named(name: str) -> Design:
    """The built-in design ("paper") or ``examples/<name>.toml``."""
    return default_design() if name == "paper" else load_design(ROOT / "examples" / f"{name}.toml")


def poses_around_workspace(
    design: Design, n: int, seed: int, pad: float, phi_max: float
) -> np.ndarray:
    """Seeded random poses (n, 3) over the workspace's box at phi = 0 widened by ``pad``
    of its size on each side, phi uniform in [-phi_max, phi_max]."""
    box = workspace_bounds(design, 0.0)
    margin = pad * np.array([box[1] - box[0], box[3] - box[2]])
    rng = np.random.default_rng(seed)
    return np.column_stack(
        [
            rng.uniform(box[0] - margin[0], box[1] + margin[0], n),
            rng.uniform(box[2] - margin[1], box[3] + margin[1], n),
            rng.uniform(-phi_max, phi_max, n),
        ]
    )


def wide_design(design: Design | None = None) -> Design:
    """The design (built-in by default) with strokes and rod ranges opened, so that
    poses far from the centre count as reachable."""
    data = (design or default_design()).model_dump()
    for leg in data["legs"]:
        leg["stroke"] = (-1.0, 1.0)
        leg["rod_length_range"] = (1e-4, 1.0)
    return design_from_dict(data)


def colour_count(img: np.ndarray) -> int:
    """Number of distinct colours of an image (h, w, 3 or 4): 8-bit channels (or floats
    k/255 as matplotlib reads a PNG) packed into one uint32 per pixel, so that
    ``np.unique`` sorts a 1-D array (0.02 s for a 1500 x 1000 picture, where
    ``np.unique(..., axis=0)`` over the pixel rows takes 1.1-1.6 s)."""
    a = np.asarray(img)
    if a.dtype != np.uint8:
        a = np.round(a * 255.0).astype(np.uint8)
    channels = a.reshape(-1, a.shape[-1]).astype(np.uint32)
    packed = np.zeros(channels.shape[0], dtype=np.uint32)
    for c in range(channels.shape[1]):
        packed |= channels[:, c] << np.uint32(8 * c)
    return int(np.unique(packed).size)


def capture_saved_figures(monkeypatch: pytest.MonkeyPatch) -> list[Any]:
    """Make ``ppm_stiffness.visuals.save_figure`` (which every figure command calls)
    also append each figure it saves to the returned list, in order, so that a test
    reads the plotted data of the figure a command wrote."""
    import ppm_stiffness.visuals as visuals

    figures: list[Any] = []
    save = visuals.save_figure

    def recording(fig: Any, path: str | Path, dpi: int = 150) -> Path:
        figures.append(fig)
        return save(fig, path, dpi)

    monkeypatch.setattr(visuals, "save_figure", recording)
    return figures


def lines_by_gid(fig: Any, prefix: str) -> dict[int, np.ndarray]:
    """3-D lines of ``fig`` whose gid is ``prefix`` + an index: index -> (n, 3) [mm]."""
    out = {}
    for ax in fig.axes:
        for line in ax.get_lines():
            gid = line.get_gid() or ""
            if gid.startswith(prefix):
                out[int(gid[len(prefix) :])] = np.array(line.get_data_3d()).T
    return out


def half_unit(text: str) -> float:
    """Half a unit of the last printed digit of a number as printed (e.g. '1.25e+03' -> 5)."""
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 0.5 * 10.0 ** (int(exponent or 0) - decimals)


# --- the examples, discovered ---------------------------------------------------------
#: The shipped example designs (``examples/*.toml``).
EXAMPLES_DIR = ROOT / "examples"


@functools.cache
def _load(path: Path) -> Design:
    return load_design(path)


def example_designs(
    where: Callable[[Design], bool] | None = None, *, paper: bool = False
) -> list[str]:
    """Names (file stems, sorted) of the designs in ``examples/*.toml`` that satisfy
    ``where`` (all if None), for ``pytest.mark.parametrize`` and :func:`design_named`:
    discovered, so that a new example file is tested by every test that applies to it.
    ``paper``: the built-in design ("paper") first, when it satisfies ``where``."""
    paths = {p.stem: p for p in sorted(EXAMPLES_DIR.glob("*.toml"))}
    names = (["paper"] if paper else []) + list(paths)
    if where is None:
        return names
    return [n for n in names if where(default_design() if n == "paper" else _load(paths[n]))]


def is_planar(design: Design) -> bool:
    """A planar design (task coordinates x, y, rz and planar legs)."""
    return design.planar


def is_spatial(design: Design) -> bool:
    """A spatial design (not :func:`is_planar`)."""
    return not design.planar


def has_reduced_form(design: Design) -> bool:
    """Every leg offers an exact reduced form (the maps' reduced path: P-P-R legs)."""
    return all(leg.reduced_form() is not None for leg in design.legs)


def has_moving_geometry(design: Design) -> bool:
    """The loaded mode's moving geometry models every leg (a leg type may decline it:
    :meth:`~ppm_stiffness.legs.base.LegModel.moving_geometry_gap`)."""
    return all(leg.moving_geometry_gap() is None for leg in design.legs)


def flexure_jointed(design: Design) -> bool:
    """A leg of the design has an elastic joint or a notch hinge (a flexure: a small range
    of motion, and joint stiffnesses orders of magnitude below its structure's)."""
    return any(
        getattr(e, "elastic", None) is not None or getattr(e, "hinge", None) is not None
        for leg in design.legs
        for e in getattr(leg, "elements", [])
    )


def within_required(design: Design, spans: Any, widen: float = 1.0) -> np.ndarray:
    """Half-spans of random poses around home, one per task coordinate: ``spans``, but
    for a flexure-jointed design no wider than ``widen`` times the half-widths of its
    required region where it states one (the range its flexures and drives give: a
    piezo-driven stage's is microns, not the millimetres the tests draw for linkages)."""
    out = np.array(spans, dtype=float)
    region = design.workspace.required
    if not flexure_jointed(design) or region is None:
        return out
    ranges = region.ranges()
    for i, name in enumerate(design.task_coordinates):
        if name in ranges:
            lo, hi = ranges[name]
            out[..., i] = np.minimum(out[..., i], widen * (hi - lo) / 2.0)
    return out


def check_entries(table: Iterable[str], names: Iterable[str], what: str) -> None:
    """Fail naming every discovered example without an entry in a table of per-example
    reference values (its keys, or the names it lists): a new example must get its
    values, not be skipped."""
    missing = sorted(set(names) - set(table))
    assert not missing, f"{what}: no entry for the example(s) {missing}; add one"


def rotational_symmetry(design: Design) -> int:
    """The largest n >= 2 such that turning the design by 2 pi / n about the z axis
    through P at its workspace centre maps its legs onto its legs (their joints' kinds,
    points, axes and springs, their links' ends and sections, their actuators), else 1:
    an n-fold symmetric design (n >= 3) is decoupled there, with repeated eigenvalues."""
    from ppm_stiffness.legs.chain import Joint
    from ppm_stiffness.model import solve_legs, workspace_centre
    from ppm_stiffness.poses import full_pose

    pose = full_pose(design, workspace_centre(design))
    legs = list(zip(design.legs, solve_legs(design, pose), strict=True))

    def signature(i: int, turn: float) -> list[Any]:
        leg, leg_pose = legs[i]
        c, s = np.cos(turn), np.sin(turn)
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        out: list[Any] = [leg.actuator]
        for e in leg.chain(leg_pose):
            if isinstance(e, Joint):
                springs = None if e.springs is None else tuple(np.asarray(e.springs).tolist())
                elastic = None if e.elastic is None else tuple(np.asarray(e.elastic).tolist())
                out += [e.kind, springs, elastic, rot @ np.ravel(e.point), rot @ np.ravel(e.axis)]
            else:
                out += [e.section, rot @ np.ravel(e.start), rot @ np.ravel(e.end)]
        return out

    def same(a: list[Any], b: list[Any]) -> bool:
        return len(a) == len(b) and all(
            np.allclose(x, y, rtol=0.0, atol=1e-12) if isinstance(x, np.ndarray) else x == y
            for x, y in zip(a, b, strict=True)
        )

    for n in range(len(legs), 1, -1):
        turned = [signature(i, 2.0 * np.pi / n) for i in range(len(legs))]
        plain = [signature(i, 0.0) for i in range(len(legs))]
        if all(any(same(t, p) for p in plain) for t in turned):
            return n
    return 1


#: Pages whose ``python`` code blocks are run as written (tests/conftest.py's doc_runs).
DOC_PAGES = ("docs/api.md", "README.md")


@dataclass(frozen=True)
class DocRun:
    """A page's Python blocks run in order: how many, what they printed, and the error
    that stopped them (``"Type: message"``; None if every block ran)."""

    blocks: int
    out: str
    error: str | None


def run_doc_blocks(page: str) -> DocRun:
    """Run the ``python`` blocks of ``page`` (relative to the top folder) from the top
    folder, each in a fresh namespace, with a DeprecationWarning of the package
    (deprecated since 0.3) an error."""
    import contextlib
    import io
    import os
    import re
    import warnings

    text = (ROOT / page).read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    out = io.StringIO()
    error = None
    cwd = os.getcwd()
    try:
        os.chdir(ROOT)
        with warnings.catch_warnings(), contextlib.redirect_stdout(out):
            warnings.filterwarnings("error", message=".*deprecated since 0.3")
            for block in blocks:
                exec(compile(block, page, "exec"), {})
    except Exception as exc:  # reported by the tests that read the run
        error = f"{type(exc).__name__}: {exc}"
    finally:
        os.chdir(cwd)
    return DocRun(len(blocks), out.getvalue(), error)
