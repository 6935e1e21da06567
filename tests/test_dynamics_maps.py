"""The first natural frequency as a map quantity (``map --quantities f1``): point by
point the single-pose modal analysis, the map's masks, its files and its errors.

Residuals measured when these tests were written (on this machine), f1 of the map
against ``modal_analysis`` (``scipy.linalg.eigh``) at the same task coordinates,
relative: <= 5e-15 locked (paper's 3-PPR on the reduced path, 3-RRR on the planar
engine, hexapod on the general engine) and under a wrench; 2.5e-13 for the 3-PRS, whose
f6/f1 = 30 (two eigensolvers' round-off of the lowest eigenvalue, eps (f6/f1)^2 ~ 1e-13);
so 1e-12.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from helpers import design_named, example_designs, flexure_jointed, within_required
from ppm_stiffness.cli import main
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.core.refusals import Refusal
from ppm_stiffness.design import Design, design_from_dict, design_to_dict, dump_design
from ppm_stiffness.dynamics import batch as dyn_batch
from ppm_stiffness.dynamics.analysis import modal_analysis
from ppm_stiffness.maps.result import StiffnessMap, load_npz
from ppm_stiffness.maps.workspace import stiffness_map

#: Largest relative difference of the map's f1 to the single-pose analysis (the legs
#: condensed here, ``link_modes=0``; with link modes: tests/test_link_modes_maps.py).
AGREEMENT = 1e-12


def _task(design: Design, smap: StiffnessMap, i: int, j: int) -> np.ndarray:
    values = {smap.axes[0]: smap.u[i], smap.axes[1]: smap.v[j], **smap.fixed}
    return np.array([values[n] for n in design.task_coordinates])


def _agreement(design: Design, smap: StiffnessMap, wrench: Any = None) -> float:
    """Largest relative difference of f1 to ``modal_analysis`` over the valid points."""
    worst = 0.0
    f1 = smap.quantities["f1"]
    for j, i in zip(*np.nonzero(smap.reachable), strict=True):
        single = modal_analysis(
            design, _task(design, smap, i, j), wrench=wrench, link_modes=0
        ).to_dict()
        ref = single["frequencies"][0]
        worst = max(worst, abs(float(f1[j, i]) - ref) / ref)
    return worst


@pytest.mark.parametrize(
    ("name", "axes", "actuators"),
    [
        ("paper", None, "max"),
        ("3rrr", None, "min"),
        ("hexapod_6ups", None, "max"),
        ("hexapod_6ups", ("rx", "rz"), "max"),
        ("3prs", ("rx", "ry"), "max"),
    ],
)
def test_f1_map_equals_the_single_pose_modal_analysis(
    name: str, axes: tuple[str, str] | None, actuators: str
) -> None:
    design = design_named(name)
    smap = stiffness_map(
        design, grid=5, axes=axes, actuators=actuators, quantities=["f1"], link_modes=0
    )
    assert smap.reachable.sum() >= 9
    if actuators == "min":  # the "min" actuators: compare with them given to the analysis
        k_min = smap.actuator_stiffness[0]
        worst = 0.0
        for j, i in zip(*np.nonzero(smap.reachable), strict=True):
            from ppm_stiffness.dynamics.mass import mass_matrix_at_pose
            from ppm_stiffness.dynamics.modes import mode_shapes
            from ppm_stiffness.model import stiffness_at_pose

            p = _task(design, smap, i, j)
            ref = mode_shapes(
                stiffness_at_pose(design, p, k_min), mass_matrix_at_pose(design, p, k_min)
            ).frequencies[0]
            worst = max(worst, abs(float(smap.quantities["f1"][j, i]) - ref) / ref)
    else:
        worst = _agreement(design, smap)
    assert worst <= AGREEMENT


def test_f1_map_under_a_wrench_uses_the_loaded_tangent_k() -> None:
    """As ``modes --wrench``: the loaded tangent K and the tangent actuator stiffnesses
    (the paper's soft actuators make the difference to the locked map visible)."""
    design = design_named("paper")
    wrench = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])
    loaded = stiffness_map(
        design, grid=4, actuators="wrench", wrench=wrench, quantities=["f1"], link_modes=0
    )
    locked = stiffness_map(design, grid=4, quantities=["f1"], link_modes=0)
    assert loaded.reachable.sum() >= 8
    assert _agreement(design, loaded, wrench) <= AGREEMENT
    ok = loaded.reachable & locked.reachable
    diff = np.abs(loaded.quantities["f1"][ok] - locked.quantities["f1"][ok])
    assert np.max(diff / locked.quantities["f1"][ok]) > 1e-3


def test_f1_masks_are_the_maps_refusals_and_with_the_stiffnesses() -> None:
    """f1 next to the principal stiffnesses: the same masks and codes as without it,
    and the stiffnesses unchanged; masked points NaN, valid ones finite."""
    design = design_named("hexapod_6ups")
    both = stiffness_map(design, grid=12, quantities=["f1", "translational_min"], link_modes=0)
    alone = stiffness_map(design, grid=12, quantities=["translational_min"])
    assert (~both.reachable).any() and both.reachable.any()
    assert both.refusal is not None and alone.refusal is not None
    assert np.array_equal(both.refusal, alone.refusal)
    assert np.array_equal(
        both.quantities["translational_min"].filled(np.nan),
        alone.quantities["translational_min"].filled(np.nan),
        equal_nan=True,
    )
    f1 = both.quantities["f1"]
    assert np.array_equal(f1.mask, ~both.reachable)
    assert np.all(np.isnan(f1.data[~both.reachable]))
    assert np.all(np.isfinite(f1.data[both.reachable]) & (f1.data[both.reachable] > 0))


def test_a_pose_where_the_mass_matrix_fails_is_refused_not_a_nan(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """M not finite at one accepted pose: that pose is refused as singular (what
    ``modal_analysis`` raises there), the others keep their values."""
    design = design_named("hexapod_6ups")
    real = dyn_batch.mass_matrix

    def broken(design: Design, poses: np.ndarray, k_act: Any = None) -> np.ndarray:
        m = real(design, poses, k_act)
        m[0, 0, 0] = np.nan
        return m

    good = stiffness_map(design, grid=6, quantities=["f1"], link_modes=0)
    monkeypatch.setattr(dyn_batch, "mass_matrix", broken)
    smap = stiffness_map(design, grid=6, quantities=["f1"], link_modes=0)
    first = np.flatnonzero(good.reachable.ravel())[0]
    assert smap.refusal is not None and good.refusal is not None
    assert smap.refusal.ravel()[first] == Refusal.SINGULAR
    assert not smap.reachable.ravel()[first]
    rest = good.reachable.copy()
    rest.ravel()[first] = False
    assert np.array_equal(smap.reachable, rest)
    assert np.array_equal(smap.quantities["f1"][rest], good.quantities["f1"][rest])


def _massless(tmp_path: Path) -> Path:
    data = design_to_dict(design_named("paper"))
    del data["platform"]
    for table in data["parts"].values():
        for key in ("mass", "mass_centre", "mass_centre_from", "inertia_transverse"):
            table.pop(key, None)
        table.pop("carriage_mass", None)
    path = tmp_path / "massless.toml"
    path.write_text(dump_design(design_from_dict(data)), encoding="utf-8")
    return path


def test_f1_without_a_mass_model_names_the_platform_table(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _massless(tmp_path)
    from ppm_stiffness.design import load_design

    with pytest.raises(DesignError, match=r"no mass model: add a \[platform\] table"):
        stiffness_map(load_design(path), grid=3, quantities=["f1"], link_modes=0)
    out_file = tmp_path / "m.csv"
    code = main(
        ["map", "--design", str(path), "--quantities", "f1", "--grid", "4", "--data", str(out_file)]
    )
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "[platform]" in err and not out_file.exists()
    assert main(["map", "--design", str(path), "--grid", "4", "--quiet"]) == 0  # as before


def test_f1_in_the_files_and_the_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """NPZ round trip, the CSV column f1_Hz, the JSON summary in Hz, and a figure."""
    hexapod = str(Path(__file__).parent.parent / "examples" / "hexapod_6ups.toml")
    npz, csv, png = tmp_path / "m.npz", tmp_path / "m.csv", tmp_path / "m.png"
    args = ["map", "--design", hexapod, "--grid", "5", "--quantities", "f1,translational_min"]
    args += ["--link-modes", "0"]
    assert main([*args, "--data", str(npz), "--out", str(png), "--quiet"]) == 0
    capsys.readouterr()
    assert main([*args, "--data", str(csv), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["quantities"] == {"f1": "Hz", "translational_min": "N/m"}
    smap = load_npz(npz)
    assert list(smap.quantities) == ["f1", "translational_min"]
    f1 = smap.quantities["f1"]
    assert doc["summary"]["f1"]["min"] == pytest.approx(float(f1.min()), rel=1e-15)
    header = next(line for line in csv.read_text().splitlines() if not line.startswith("#"))
    assert header.split(",")[-2:] == ["f1_Hz", "translational_min_N_per_m"]
    assert png.stat().st_size > 0


# --- the batched mass matrix ----------------------------------------------------------

SHIPPED = tuple(example_designs(paper=True))


@pytest.mark.parametrize("name", SHIPPED)
def test_batched_mass_matrix_equals_the_single_pose_one_on_every_shipped_example(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each shipped example with its own mass model, at poses over its workspace (a
    twentieth of the size for a flexure-jointed design), in
    chunks smaller than the batch (their seams included): relative to the largest
    entry, <= 1e-12 (measured: <= 9e-16; the batched and single paths run the same
    arithmetic on stacks of different lengths)."""
    from ppm_stiffness.dynamics import mass as dyn_mass
    from ppm_stiffness.poses import full_poses, home_pose, task_values

    design = design_named(name)
    rng = np.random.default_rng(11)
    scale = np.array([0.05 if n in ("rx", "ry", "rz") else 0.01 for n in design.task_coordinates])
    if flexure_jointed(design):  # its flexures' range
        scale = within_required(design, scale * 0.05)
    tasks = task_values(design, home_pose(design)) + scale * rng.uniform(-1, 1, (7, scale.size))
    poses, ok = full_poses(design, tasks)
    poses = poses[ok]
    assert poses.shape[0] >= 5
    monkeypatch.setattr(dyn_mass, "MASS_CHUNK", 3)
    batched = dyn_mass.mass_matrix(design, poses)
    for i, pose in enumerate(poses):
        single = dyn_mass.mass_matrix_at_pose(design, pose)
        assert np.max(np.abs(batched[i] - single)) <= 1e-12 * np.max(np.abs(single))


def test_the_stacked_cholesky_solve_against_lapack_and_its_refusals() -> None:
    """``condensation._solve`` (the legs' small SPD systems, vectorised): equal to
    ``numpy.linalg.solve`` on SPD stacks of every size a leg has (r, p <= 6; measured
    residual <= 2e-15 relative), NaN for a singular, indefinite or non-finite matrix."""
    from ppm_stiffness.dynamics.condensation import _solve

    rng = np.random.default_rng(3)
    for r in range(1, 7):
        g = rng.normal(size=(50, r, r))
        a = g @ np.swapaxes(g, 1, 2) + 0.1 * np.eye(r)
        b = rng.normal(size=(50, r, 6))
        ref = np.linalg.solve(a, b)
        assert np.max(np.abs(_solve(a, b) - ref)) <= 1e-12 * np.max(np.abs(ref))
    bad = np.stack([np.diag([1.0, 0.0]), np.diag([1.0, -1.0]), np.full((2, 2), np.nan), np.eye(2)])
    x = _solve(bad, np.ones((4, 2, 3)))
    assert np.all(np.isnan(x[:3])) and np.allclose(x[3], 1.0)


# --- the public API -----------------------------------------------------------------------

DYNAMICS_API = (
    "mass_matrix",
    "mass_matrix_at_pose",
    "natural_frequencies",
    "mode_shapes",
    "Modes",
    "modal_analysis",
    "first_frequencies",
)


def test_every_public_name_imports_and_the_dynamics_ones_are_public() -> None:
    """Every name of ``__all__`` imports from the package (``from ppm_stiffness import
    name``), and the dynamics names the docs use are among them, the same objects as in
    their modules; the documented example runs on the hexapod."""
    import importlib

    import ppm_stiffness as pps

    for name in pps.__all__:
        assert getattr(importlib.import_module("ppm_stiffness"), name) is not None
        exec(f"from ppm_stiffness import {name}", {})
    assert set(DYNAMICS_API) <= set(pps.__all__)
    for name in DYNAMICS_API:
        module, attr = pps._API[name]
        assert getattr(pps, name) is getattr(importlib.import_module(module), attr)
    design = pps.load_design(Path(__file__).parent.parent / "examples" / "hexapod_6ups.toml")
    modes = pps.mode_shapes(pps.stiffness_at_pose(design), pps.mass_matrix_at_pose(design))
    assert isinstance(modes, pps.Modes)
    assert modes.frequencies[0] == pytest.approx(
        pps.modal_analysis(design, link_modes=0).to_dict()["frequencies"][0], rel=1e-12
    )


def test_f1_with_moving_geometry_is_refused_and_the_load_margin_can_join_it() -> None:
    """f1 is not mapped with moving geometry (its M would be the unloaded pose's): one
    InputDataError naming the frozen alternative; with frozen geometry f1 and the load
    margin are mapped together, f1 equal to the f1-only map's."""
    from ppm_stiffness.core.errors import InputDataError

    design = design_named("paper")
    wrench = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])
    common: dict[str, Any] = {"actuators": "wrench", "wrench": wrench, "grid": 3}
    with pytest.raises(InputDataError, match="geometry 'frozen'"):
        stiffness_map(design, geometry="moving", quantities=["f1"], link_modes=0, **common)
    both = stiffness_map(design, quantities="f1,load-margin", link_modes=0, **common)
    alone = stiffness_map(design, quantities=["f1"], link_modes=0, **common)
    assert both.quantities.keys() == {"f1", "load_margin"}
    np.testing.assert_array_equal(
        np.ma.filled(both.fields()["f1"], np.nan), np.ma.filled(alone.fields()["f1"], np.nan)
    )
