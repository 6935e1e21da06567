"""Helpers shared by the tests."""

from __future__ import annotations

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
