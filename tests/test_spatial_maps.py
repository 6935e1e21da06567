"""Maps of spatial designs (hexapod, 3-PRS, 3-RPS): slices over any two task coordinates
equal the single-pose analysis point by point, the general batched path (the engine)
equals the dense definition, the slice options are validated, and the files round-trip.

Residuals measured when these tests were written (on this machine):
- engine path against the dense definition (chain springs + bordered inverse, summed
  over legs), length-balanced K relative to its largest entry: 9e-16 (hexapod), 3.4e-14
  (3-PRS), 1.9e-14 (3-RPS), 1.8e-14 (3-RPR), <= 4e-15 for the other planar designs,
  so 1e-12;
- map quantities against ``principal_compliance`` of the single-pose K at the tool
  point, relative to the largest value of their set: <= 1e-15 (hexapod), 2.1e-14
  (3-PRS), 7.8e-15 (3-RPS), so 1e-12;
- the dependent coordinates of the map's grid against ``full_pose``: equal (0).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from helpers import (
    check_entries,
    design_named,
    example_designs,
    flexure_jointed,
    is_spatial,
    poses_around_workspace,
    within_required,
)
from ppm_stiffness.cli import main
from ppm_stiffness.core import solver
from ppm_stiffness.core.conventions import length_balanced
from ppm_stiffness.core.errors import (
    DesignError,
    InputDataError,
    SingularConfigurationError,
    UnreachablePoseError,
)
from ppm_stiffness.core.principal import principal_compliance
from ppm_stiffness.core.refusals import Refusal
from ppm_stiffness.design import Design
from ppm_stiffness.legs.chain import leg_springs
from ppm_stiffness.maps import batch
from ppm_stiffness.maps.result import PRINCIPAL, StiffnessMap, load_npz
from ppm_stiffness.maps.slices import map_slice, slice_bounds
from ppm_stiffness.maps.workspace import stiffness_map
from ppm_stiffness.model import stiffness_at_pose, stiffness_at_tool_point
from ppm_stiffness.poses import full_pose, home_pose, task_indices

ROOT = Path(__file__).parents[1]
SPATIAL = example_designs(is_spatial)
#: (design, axes, fixed [m, rad]) of the slices checked point by point.
SLICES = [
    ("hexapod_6ups", None, {}),
    ("hexapod_6ups", ("rx", "ry"), {"x": 0.01, "z": 0.21}),
    ("hexapod_6ups", ("z", "rz"), {"rx": 0.05}),
    ("3prs", ("rx", "ry"), {"z": 0.38}),
    ("3prs", None, {"ry": 0.1}),
    ("3rps", ("rx", "ry"), {}),
    ("3rps", ("ry", "z"), {"rx": -0.1}),
    ("6rus", None, {"z": 0.215}),
    ("6rus", ("rx", "rz"), {"y": 0.005}),
    ("6rus_flexure", None, {"z": 0.213}),
    ("flexure_3rrr", None, {"rz": 1e-4}),
    ("spherical_3rrr", None, {}),
    ("spherical_3rrr", ("ry", "rz"), {"rx": 0.2}),
    ("tricept", None, {"ry": 0.05}),
    ("tricept", ("rx", "ry"), {"z": 0.56}),
    ("delta", None, {"z": -0.8}),
    ("delta", ("x", "z"), {"y": 0.02}),
]
RTOL = 1e-12


def test_every_spatial_example_has_slices() -> None:
    check_entries([s[0] for s in SLICES], SPATIAL, "SLICES")


def task_pose(design: Design, smap: StiffnessMap, i: int, j: int) -> np.ndarray:
    """The task values of grid point (j, i) of a map."""
    values = dict(smap.fixed) | {smap.axes[0]: smap.u[i], smap.axes[1]: smap.v[j]}
    return np.array([values[name] for name in design.task_coordinates])


def single_values(design: Design, pose: np.ndarray, k_act: np.ndarray | None = None) -> np.ndarray:
    """The six principal stiffnesses (ascending rotational, then translational) at the
    design's tool point by the single-pose API."""
    k = stiffness_at_pose(design, pose, k_act)
    k_t = stiffness_at_tool_point(k, full_pose(design, pose), design.tool_point)
    pc = principal_compliance(k_t)
    return np.concatenate([np.sort(pc.rotational_values), np.sort(pc.translational_values)])


def wide(design: Design, sl_axes: tuple[str, str] | None, fixed: dict[str, float]) -> np.ndarray:
    """The slice's bounds widened by 15 % each side (so that joint limits refuse)."""
    box = slice_bounds(design, map_slice(design, sl_axes, fixed))
    pad = 0.15 * np.array([box[1] - box[0], box[3] - box[2]])
    return box + np.array([-pad[0], pad[0], -pad[1], pad[1]])


# ------------------------------------------------------------ the general path
def dense_stiffness(design: Design, poses: np.ndarray, k_act: np.ndarray) -> np.ndarray:
    """The definition: every leg's chain springs and bordered inverse, summed."""
    total = np.zeros((poses.shape[0], 6, 6))
    for i, leg in enumerate(design.legs):
        springs = leg_springs(leg.chain(leg.solve(poses)), k_act[:, i])
        total += solver.leg_stiffness(springs)
    return total


def random_task_poses(design: Design, n: int, seed: int) -> np.ndarray:
    """Task values around the home pose: +-24 mm and +-0.18 rad for a
    hexapod, +-60 mm and +-0.45 rad for a tripod, +-1.2 rad for a wrist (orientation
    only: beyond its drives' strokes), +-0.25 m for a Delta (translations only),
    a twentieth of these for a flexure-jointed design
    (planar: the helpers')."""
    if design.planar:
        return poses_around_workspace(design, n, seed, pad=0.1, phi_max=0.3)
    idx = list(task_indices(design))
    rng = np.random.default_rng(seed)
    half = np.array([0.04 if i < 3 else 0.3 for i in idx]) * (0.6 if len(idx) == 6 else 1.5)
    if min(idx) >= 3:
        half[:] = 1.2
    if max(idx) < 3:  # translations only (a Delta): +-0.25 m, beyond its arms' strokes
        half[:] = 0.25
    if flexure_jointed(design):  # its flexures' range: +-1.2 mm, +-9 mrad; a piezo
        # stage's: twice its required region (beyond it, its drives' strokes refuse)
        half = within_required(design, half * 0.05, widen=2.0)
    return home_pose(design)[idx] + rng.uniform(-1.0, 1.0, (n, len(idx))) * half


@pytest.mark.parametrize("name", example_designs(paper=True))
def test_general_path_equals_the_dense_definition(name: str) -> None:
    design = design_named(name)
    poses = random_task_poses(design, 120, 4)
    rng = np.random.default_rng(9)
    k_lock = np.array([leg.locked_stiffness() for leg in design.legs])  # inf: passive
    k_act = k_lock * rng.uniform(0.05, 1.0, (len(poses), len(design.legs)))
    res = batch.evaluate_poses(design, poses, k_act, matrices=True, path="general", chunk_size=29)
    assert res.path == "general" and res.stiffness is not None
    v = res.valid
    assert 30 <= v.sum() < len(poses) or name == "redundant_4ppr"
    ref = dense_stiffness(design, res.poses[v], k_act[v])
    a, b = length_balanced(res.stiffness[v]), length_balanced(ref)
    worst = np.max(np.max(np.abs(a - b), axis=(1, 2)) / np.max(np.abs(b), axis=(1, 2)))
    assert worst <= RTOL


# ------------------------------------------------- maps = the single-pose analysis
@pytest.mark.parametrize(("name", "axes", "fixed"), SLICES)
def test_spatial_maps_equal_the_single_pose_analysis(
    name: str, axes: tuple[str, str] | None, fixed: dict[str, float]
) -> None:
    design = design_named(name)
    bounds = wide(design, axes, fixed)
    smap = stiffness_map(design, axes=axes, fixed=fixed, grid=(7, 6), bounds=bounds)
    assert list(smap.quantities) == list(PRINCIPAL)
    assert 0 < smap.reachable.sum() < smap.reachable.size
    assert set(smap.dependent) == {"x", "y", "z", "rx", "ry", "rz"} - set(design.task_coordinates)
    for j in range(smap.v.size):
        for i in range(smap.u.size):
            pose = task_pose(design, smap, i, j)
            try:
                ref = single_values(design, pose)
            except (UnreachablePoseError, SingularConfigurationError):
                assert not smap.reachable[j, i]
                assert all(q.mask[j, i] for q in smap.quantities.values())
                continue
            assert smap.reachable[j, i] and smap.refusal is not None and smap.refusal[j, i] == 0
            got = np.array([smap.quantities[q][j, i] for q in PRINCIPAL])
            for part in (slice(0, 3), slice(3, 6)):
                assert np.max(np.abs(got[part] - ref[part])) <= RTOL * np.max(ref[part])
            full = full_pose(design, pose)
            for coordinate, values in smap.dependent.items():
                index = ["x", "y", "z", "rx", "ry", "rz"].index(coordinate)
                assert values[j, i] == pytest.approx(full[index], abs=1e-12)


def test_a_spatial_map_without_bounds_spans_the_reachable_samples() -> None:
    """The default extent is the box of the reachable samples of a 101 x 101 grid: an
    inner box within one coarse cell (1 % of its span) of the box of a 401 x 401 sweep
    of a window 30 % wider (measured: 0.9 % of the span on the rx side of the 3-PRS,
    less elsewhere), every edge of the map's grid with a reachable point."""
    from ppm_stiffness.maps.slices import slice_reachable

    design = design_named("3prs")
    sl = map_slice(design, ("rx", "ry"))
    box = slice_bounds(design, sl)
    span = np.array([box[1] - box[0], box[3] - box[2]])
    u = np.linspace(box[0] - 0.15 * span[0], box[1] + 0.15 * span[0], 401)
    v = np.linspace(box[2] - 0.15 * span[1], box[3] + 0.15 * span[1], 401)
    sweep = slice_reachable(design, sl, u[None, :], v[:, None])
    assert not (sweep[0].any() or sweep[-1].any() or sweep[:, 0].any() or sweep[:, -1].any())
    cols, rows = np.flatnonzero(sweep.any(axis=0)), np.flatnonzero(sweep.any(axis=1))
    outer = np.array([u[cols[0]], u[cols[-1]], v[rows[0]], v[rows[-1]]])
    step = np.array([u[1] - u[0], v[1] - v[0]]).repeat(2)
    gap = np.array([box[0] - outer[0], outer[1] - box[1], box[2] - outer[2], outer[3] - box[3]])
    assert np.all(gap >= -step) and np.all(gap <= 0.01 * span.repeat(2) + step)
    smap = stiffness_map(design, axes=("rx", "ry"), grid=(41, 41))
    r = smap.refusal
    assert r is not None
    assert (r[:, 0] != Refusal.UNREACHABLE).any() and (r[:, -1] != Refusal.UNREACHABLE).any()
    assert (r[0] != Refusal.UNREACHABLE).any() and (r[-1] != Refusal.UNREACHABLE).any()


def test_the_map_at_a_tool_point_moves_k_there() -> None:
    """The hexapod x-y map at a tool point 50 mm above P: translational values of K at
    the tool point; rotational ones do not depend on the point (same as at P)."""
    design = design_named("hexapod_6ups")
    tool = np.array([0.0, 0.01, 0.05])
    at_p = stiffness_map(design, grid=5)
    at_t = stiffness_map(design, grid=5, tool_point=tool)
    ok = at_p.reachable
    assert ok.any()
    for name in ("rotational_min", "rotational_mid", "rotational_max"):
        np.testing.assert_allclose(at_t.quantities[name][ok], at_p.quantities[name][ok], rtol=1e-12)
    j, i = np.argwhere(ok)[0]
    k = stiffness_at_pose(design, task_pose(design, at_t, i, j))
    k_t = stiffness_at_tool_point(k, task_pose(design, at_t, i, j), tool)
    ref = np.sort(principal_compliance(k_t).translational_values)
    got = [at_t.quantities[n][j, i] for n in PRINCIPAL[3:]]
    np.testing.assert_allclose(got, ref, rtol=1e-12)
    assert abs(got[0] - at_p.quantities["translational_min"][j, i]) > 1e-3 * got[0]


def test_wrench_maps_of_a_tripod_with_a_tool_point_are_the_loaded_state() -> None:
    """The 3-PRS tool point is 150 mm below P: the wrench acts there, moved to P at each
    grid pose's orientation (every pose its own group)."""
    from ppm_stiffness.statics.loading import loaded_state

    design = design_named("3prs")
    w_tool = np.array([1.0, -2.0, 0.5, 300.0, -100.0, -2000.0])
    smap = stiffness_map(design, axes=("rx", "ry"), grid=(4, 3), actuators="wrench", wrench=w_tool)
    tool = np.asarray(design.tool_point)
    assert smap.reachable.sum() >= 6
    for j, i in np.argwhere(smap.reachable):
        pose = task_pose(design, smap, i, j)
        full = full_pose(design, pose)
        from ppm_stiffness.model import tool_offset

        r = tool_offset(full, tool)
        w_p = w_tool.copy()
        w_p[:3] += np.cross(r, w_tool[3:])
        state = loaded_state(design, w_p, pose)
        k_t = stiffness_at_tool_point(state.stiffness_matrix, full, tool)
        pc = principal_compliance(k_t)
        ref = np.concatenate([np.sort(pc.rotational_values), np.sort(pc.translational_values)])
        got = np.array([smap.quantities[q][j, i] for q in PRINCIPAL])
        for part in (slice(0, 3), slice(3, 6)):
            assert np.max(np.abs(got[part] - ref[part])) <= 1e-11 * np.max(ref[part])


# ------------------------------------------------------------- evaluate_poses
def test_evaluate_poses_of_a_tripod_completes_the_poses_and_refuses_k_phi() -> None:
    design = design_named("3rps")
    poses = random_task_poses(design, 20, 3)
    res = batch.evaluate_poses(design, poses)
    assert res.rotational is not None and res.translational is not None and res.paper is None
    for n in np.flatnonzero(res.valid)[:5]:
        np.testing.assert_allclose(res.poses[n], full_pose(design, poses[n]), rtol=0, atol=1e-12)
        ref = single_values(design, poses[n])
        np.testing.assert_allclose(res.rotational[n], ref[:3], rtol=1e-12)
    with pytest.raises(DesignError, match="not planar; use rotational and translational"):
        _ = res.k_phi
    full = batch.evaluate_poses(design, res.poses[res.valid])
    np.testing.assert_array_equal(full.rotational, res.rotational[res.valid])


def test_the_spatial_values_of_a_planar_design_on_request() -> None:
    """The planar fast paths give the spatial principal stiffnesses too (principal=True),
    equal to core.principal at each pose."""
    design = design_named("3rrr")
    poses = random_task_poses(design, 30, 5)
    for path in ("planar", "general"):
        res = batch.evaluate_poses(design, poses, principal=True, path=path)
        assert res.translational is not None and res.rotational is not None
        for n in np.flatnonzero(res.valid)[:6]:
            pc = principal_compliance(stiffness_at_pose(design, poses[n]))
            np.testing.assert_allclose(res.rotational[n], np.sort(pc.rotational_values), rtol=1e-12)
            np.testing.assert_allclose(
                res.translational[n], np.sort(pc.translational_values), rtol=1e-12
            )
    smap = stiffness_map(design, grid=4, quantities="all")
    assert list(smap.quantities) == ["k_phi", "k_x", "k_y", *PRINCIPAL]


# ---------------------------------------------------------------- validation
@pytest.mark.parametrize(
    ("name", "kwargs", "error", "match"),
    [
        ("3rps", {"axes": ("x", "ry")}, InputDataError, "map axis 'x' is not a task coordinate"),
        ("3rps", {"axes": ("rx", "rx")}, InputDataError, "the two axes of a map must differ"),
        ("3rps", {"axes": ("rx",)}, InputDataError, "a map has two axes"),
        ("3rps", {"fixed": {"x": 0.0}}, InputDataError, "fixed coordinate 'x' is not a task"),
        ("3rps", {"phi": 0.1}, InputDataError, "fixed coordinate 'rz' is not a task"),
        ("3rps", {"axes": ("rx", "ry"), "fixed": {"ry": 0.1}}, InputDataError, "ry is an axis"),
        ("3rps", {"fixed": {"ry": float("nan")}}, InputDataError, "ry must be finite"),
        ("hexapod_6ups", {"fixed": {"rz": 0.1}, "phi": 0.1}, InputDataError, "rz given twice"),
        ("3rps", {"quantities": "paper"}, InputDataError, "is not planar"),
        ("3rps", {"quantities": ["k_z"]}, InputDataError, "unknown map quantity k_z"),
        ("3rps", {"axes": ("rx", "ry"), "bounds": [1, 0, 0, 1]}, InputDataError, "rx_min < rx_max"),
        ("3prs", {"fixed": {"ry": 1.5}}, UnreachablePoseError, "no reachable pose of the z-rx"),
    ],
)
def test_bad_slices_are_refused(name: str, kwargs: dict, error: type, match: str) -> None:
    with pytest.raises(error, match=match):
        stiffness_map(design_named(name), grid=3, **kwargs)


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["--axes", "x,ry"], "map axis 'x' is not a task coordinate"),
        (["--axes", "rx"], "--axes must be two task coordinates"),
        (["--x", "3"], "--x: x is not a task coordinate of this design; give --ry (the other"),
        (["--axes", "rx,ry", "--rx", "3"], "--rx: rx is an axis of the map"),
        (["--axes", "rx,ry", "--bounds", "1,2,3"], "--bounds must be 4 numbers rx_min"),
        (["--quantities", "paper"], "is not planar"),
    ],
)
def test_bad_map_options_are_one_line_and_exit_2(
    argv: list[str], match: str, capsys: pytest.CaptureFixture[str]
) -> None:
    design = str(ROOT / "examples" / "3rps.toml")
    assert main(["map", "--design", design, "--grid", "4", "--quiet", *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("ppm-stiffness: error:") and match in err[0]


# --------------------------------------------------------------------- files
def test_npz_and_csv_of_a_tripod_map_round_trip(tmp_path: Path) -> None:
    design = design_named("3prs")
    smap = stiffness_map(design, axes=("rx", "ry"), fixed={"z": 0.39}, grid=(5, 4))
    assert not smap.reachable.all() and smap.reachable.any()
    back = load_npz(smap.to_npz(tmp_path / "m.npz"))
    assert back.axes == ("rx", "ry") and back.fixed == {"z": 0.39}
    assert list(back.quantities) == list(smap.quantities)
    np.testing.assert_array_equal(back.u, smap.u)
    np.testing.assert_array_equal(back.v, smap.v)
    np.testing.assert_array_equal(back.tool_point, design.tool_point)
    assert back.refusal is not None and smap.refusal is not None
    np.testing.assert_array_equal(back.refusal, smap.refusal)
    for name, values in smap.quantities.items():
        np.testing.assert_array_equal(back.quantities[name].mask, values.mask)
        np.testing.assert_array_equal(back.quantities[name].compressed(), values.compressed())
    for name, values in smap.dependent.items():
        np.testing.assert_array_equal(back.dependent[name], values)
    with pytest.raises(AttributeError, match="x is not an axis"):
        _ = back.x
    with pytest.raises(AttributeError, match="rz is not fixed"):
        _ = back.phi
    lines = [ln for ln in smap.to_csv(tmp_path / "m.csv").open(encoding="utf-8")]
    comments = [ln for ln in lines if ln.startswith("#")]
    assert "# z_m: 0.39\n" in comments
    rows = [ln.rstrip("\n").split(",") for ln in lines if not ln.startswith("#")]
    assert rows[0][:6] == ["rx_rad", "ry_rad", "reachable", "x_m", "y_m", "rz_rad"]
    assert rows[0][6:] == [f"{n}_{'Nm_per_rad' if n[0] == 'r' else 'N_per_m'}" for n in PRINCIPAL]
    for n, cells in enumerate(rows[1:]):
        j, i = divmod(n, 5)
        assert float(cells[0]) == pytest.approx(smap.u[i], rel=1e-11)
        if smap.reachable[j, i]:
            assert float(cells[3]) == pytest.approx(smap.dependent["x"][j, i], rel=1e-11)
            assert float(cells[6]) == pytest.approx(float(smap.quantities[PRINCIPAL[0]][j, i]))
        else:
            assert cells[2:] == ["0"] + [""] * 9


def test_cli_spatial_map_json_figure_and_data(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    fig, data = tmp_path / "m.png", tmp_path / "m.npz"
    argv = ["map", "--design", str(ROOT / "examples/hexapod_6ups.toml"), "--axes", "rx,ry"]
    argv += ["--z", "210", "--x", "5", "--grid", "9", "--json", "--out", str(fig)]
    assert main([*argv, "--data", str(data)]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [a["name"] for a in doc["axes"]] == ["rx", "ry"]
    assert [a["unit"] for a in doc["axes"]] == ["rad", "rad"]
    assert doc["fixed"] == pytest.approx({"x": 0.005, "y": 0.0, "z": 0.21, "rz": 0.0})
    assert doc["phi"] == 0.0 and list(doc["quantities"]) == list(PRINCIPAL)
    assert set(doc["summary"]["rotational_min"]) >= {"rx_at_min", "ry_at_max", "ratio"}
    smap = load_npz(data)
    assert smap.fixed == pytest.approx(doc["fixed"])
    assert fig.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_tolerance_bands_on_a_spatial_map(tmp_path: Path) -> None:
    """map_output over a hexapod map's grid (its grid_arguments) is the map's quantities;
    the bands of a 2 % tied actuator tolerance contain the nominal values."""
    from ppm_stiffness.fit.band_outputs import MAP_FAILED_VALUE, map_output
    from ppm_stiffness.fit.tolerances import parse_tolerances, tolerance_variables
    from ppm_stiffness.fit.uncertainty import propagate

    design = design_named("hexapod_6ups")
    smap = stiffness_map(design, axes=("rx", "ry"), grid=(5, 4))
    output = map_output(**smap.grid_arguments())
    values = output(design)
    assert values.shape == (6, 4, 5)
    expected = np.stack([q.filled(np.nan) for q in smap.quantities.values()])
    np.testing.assert_array_equal(values, expected)
    text = '["leg*.actuator.locked_stiffness"]\nsigma = "2%"\ntied = true\n'
    variables = tolerance_variables(design, parse_tolerances(text))
    bands = propagate(design, variables, output, "first-order", failed_value=MAP_FAILED_VALUE)
    ok = smap.reachable
    assert np.all(bands.lower[:, ok] <= expected[:, ok]) and np.all(
        bands.upper[:, ok] >= expected[:, ok]
    )
    assert np.any(bands.upper[:, ok] > bands.lower[:, ok])
