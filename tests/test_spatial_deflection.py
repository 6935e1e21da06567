"""Deflection curves of every design, spatial included: a load along any wrench
direction (``deflection_curve(..., "direction")``, ``deflect --direction``), the
tool point, the integrated path against the exact equilibrium, 6-D poses in the
outputs."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from helpers import check_entries, design_named, example_designs, is_spatial
from ppm_stiffness.cli import main
from ppm_stiffness.core.conventions import BALANCE, wrench_b_from_wrench_a
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.pose import rotation, rotation_exp
from ppm_stiffness.design import Design
from ppm_stiffness.legs.joint_kinds import joint_kind
from ppm_stiffness.model import stiffness_at_pose, stiffness_at_tool_point, tool_offset
from ppm_stiffness.poses import full_pose
from ppm_stiffness.statics.deflection import (
    deflection_curve,
    deflection_path,
    direction_wrench,
    mode_wrench,
)
from ppm_stiffness.statics.equilibrium import equilibrium
from ppm_stiffness.statics.measurements import read_measurements, rms_differences

SPATIAL = tuple(example_designs(is_spatial))
#: A reachable pose off home of each spatial example, in its task coordinates [m, rad].
TASK = {
    "hexapod_6ups": [0.01, -0.005, 0.21, 0.05, -0.03, 0.08],
    "3prs": [0.38, 0.08, -0.05],
    "3rps": [0.36, 0.08, -0.05],
    "6rus": [0.008, -0.005, 0.218, 0.04, -0.03, 0.05],
    "6rus_flexure": [0.0008, -0.0005, 0.2130, 0.004, -0.003, 0.005],
    "spherical_3rrr": [0.25, -0.15, 0.2],
    "tricept": [0.56, 0.05, -0.04],
    "delta": [0.03, -0.02, -0.79],
    "flexure_3rrr": [5e-6, -4e-6, 1e-4],
}


def test_every_spatial_example_has_a_task_pose() -> None:
    check_entries(TASK, SPATIAL, "TASK")


#: A nonlinear actuator law (the examples' are linear): locked below G_th = k_a
#: delta_th^q = 100 N, the power law above.
POWERED = {"actuator.q": 0.5, "actuator.threshold_displacement": 1e-6, "actuator.k_a": 1e5}
TOOL = np.array([0.01, -0.02, 0.05])


def _powered(name: str) -> tuple[Design, np.ndarray]:
    design = design_named(name).with_parameters(POWERED)
    return design, full_pose(design, TASK[name])


def _direction(seed: int) -> np.ndarray:
    """A random wrench direction (m, f), unit force, moments of about 0.1 m x force."""
    w = np.random.default_rng(seed).normal(size=6)
    w[:3] *= 0.1
    return np.asarray(w / np.linalg.norm(w[3:]))


def _balanced_error(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |b|, rotations length-balanced (times 0.1 m)."""
    return float(np.max(np.abs((a - b) * BALANCE)) / np.max(np.abs(b * BALANCE)))


@pytest.mark.parametrize("name", SPATIAL)
def test_a_small_load_deflects_the_tool_point_by_the_compliance(name: str) -> None:
    """1 N along 8 random directions at a tool point (10, -20, 50) mm, every actuator
    locked (forces below its 100 N threshold): the tool point's twist is
    K_T^-1 w, K_T the unloaded K moved to the tool point by eq. (16) (the load and the
    twist are carried between T and P by the deflection; K by the frame change).
    Length-balanced, to 5e-13 of the largest component (measured: 3.6e-15 hexapod,
    1.1e-13 3-PRS, 7.9e-15 3-RPS; cond of the balanced K_T up to 2.3e6)."""
    design, pose = _powered(name)
    k_tool = stiffness_at_tool_point(stiffness_at_pose(design, pose), pose, TOOL)
    for seed in range(8):
        w = _direction(seed)
        curve = deflection_path(design, w, [0.0, 1.0], pose, tool_point=TOOL)
        assert np.max(np.abs(curve.actuator_forces)) < 100.0  # locked
        expected = np.linalg.solve(k_tool, w)
        assert _balanced_error(curve.twists[-1], expected) < 5e-13


#: Designs whose actuators are linear (the powered law's 100 N threshold and 1500 N
#: load are forces; a rotary drive's would be torques of another scale).
LINEAR = tuple(
    n
    for n in SPATIAL
    if all(joint_kind(leg.actuated_kind()).linear for leg in design_named(n).legs)
)


@pytest.mark.parametrize("name", LINEAR)
def test_the_integrated_path_ends_at_the_exact_equilibrium(name: str) -> None:
    """1500 N along 8 random directions (the actuators powered beyond 100 N): the
    tangent model integrated along the load (DOP853, rtol 1e-10, an event where an
    actuator leaves its locked branch) ends at the equilibrium solved directly
    (statics.equilibrium: Newton on the actuator forces). Twists to 2e-13 of the
    largest (balanced; measured 7.7e-14), forces to 3e-12 of the largest (measured
    1.0e-12 on the 3-PRS with numpy 2.4, 3.1e-13 before: the integrator's rtol 1e-10
    carried to the forces)."""
    design, pose = _powered(name)
    offset = tool_offset(pose, TOOL)
    loads = np.linspace(0.0, 1500.0, 4)
    for seed in range(8):
        w = _direction(seed)
        curve = deflection_path(design, w, loads, pose, tool_point=TOOL)
        exact = equilibrium(design, wrench_b_from_wrench_a(np.eye(3), offset) @ (1500.0 * w), pose)
        assert np.max(np.abs(exact.actuator_forces)) > 100.0  # powered
        assert _balanced_error(curve.twists_at_p()[-1], exact.twist) < 2e-13
        forces = curve.actuator_forces[-1]
        scale = np.max(np.abs(exact.actuator_forces))
        assert np.max(np.abs(forces - exact.actuator_forces)) < 3e-12 * scale


def test_the_loaded_pose_moves_the_tool_point_by_its_twist() -> None:
    """The loaded pose is the unloaded one moved by the twist of P (R' = exp(hat(phi))
    R, p' = p + v; core.pose.displaced_pose). The tool point then moves by its own
    twist's displacement to second order in the rotation: |p' + R' t - (p + R t) -
    v_T| <= |phi|^2 |R t| (here |phi| = 3e-3 rad: 1e-5 of the 50 mm offset)."""
    design, pose = _powered("hexapod_6ups")
    curve = deflection_curve(
        design,
        "direction",
        [0.0, 300.0],
        pose,
        tool_point=TOOL,
        direction=[0, 0, 4.0, 10.0, -5.0, 2.0],
    )
    loaded = curve.loaded_poses()[-1]
    phi, v_p = curve.twists_at_p()[-1, :3], curve.twists_at_p()[-1, 3:]
    np.testing.assert_allclose(rotation(loaded), rotation_exp(phi) @ rotation(pose), atol=1e-15)
    np.testing.assert_allclose(loaded[:3], pose[:3] + v_p, rtol=0, atol=1e-17)
    moved = loaded[:3] + rotation(loaded) @ TOOL - (pose[:3] + rotation(pose) @ TOOL)
    bound = np.linalg.norm(phi) ** 2 * np.linalg.norm(TOOL)
    assert 1e-3 < np.linalg.norm(phi) < 1e-2
    assert np.linalg.norm(moved - curve.twists[-1, 3:]) <= bound


# ------------------------------------------------------------------ the direction
def test_a_direction_is_normalised_by_its_force_or_its_moment() -> None:
    """The load is the force's magnitude (the moment in proportion), or a pure
    moment's; its unit follows."""
    w = direction_wrench([0.0, 0.0, 1.0, 3.0, 4.0, 0.0])  # m = (0, 0, 1), f = (3, 4, 0)
    np.testing.assert_allclose(w, [0, 0, 0.2, 0.6, 0.8, 0], rtol=1e-15)
    np.testing.assert_allclose(direction_wrench([0, 0.3, 0.4, 0, 0, 0]), [0, 0.6, 0.8, 0, 0, 0])
    design = design_named("3rps")
    force = deflection_curve(design, "direction", [0.0, 10.0], direction=[0, 0, 0, 0, 0, -7.0])
    moment = deflection_curve(design, "direction", [0.0, 2.0], direction=[3, 0, 0, 0, 0, 0])
    assert (force.load_unit, moment.load_unit) == ("N", "N·m")
    np.testing.assert_allclose(force.wrenches[-1], [0, 0, 0, 0, 0, -10.0])
    np.testing.assert_allclose(moment.wrenches[-1], [2.0, 0, 0, 0, 0, 0])


@pytest.mark.parametrize("name", SPATIAL)
def test_the_papers_modes_are_the_same_wrenches_for_a_spatial_design(name: str) -> None:
    """planar-force, moment and vertical-force act on any design as the wrenches of
    their definition (axes of F_b): each equals the direction along that wrench."""
    design = design_named(name)
    loads = [0.0, 5.0, 10.0]
    for mode in ("planar-force", "moment", "vertical-force"):
        w = mode_wrench(mode, math.radians(30))
        by_mode = deflection_curve(design, mode, loads, alpha=math.radians(30))
        by_direction = deflection_curve(design, "direction", loads, direction=w)
        np.testing.assert_array_equal(by_mode.twists, by_direction.twists)
        assert by_mode.load_unit == by_direction.load_unit
        assert not by_mode.planar and by_mode.pose.shape == (6,)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"direction": [0.0] * 6}, "must not be zero"),
        ({"direction": [1.0, 0.0, 0.0]}, "6 components"),
        ({"direction": [0.0, 0.0, 0.0, 1.0, np.nan, 0.0]}, "finite"),
        ({"mode": "moment", "direction": [0, 0, 0, 1.0, 0, 0]}, "goes with mode 'direction'"),
        ({"direction": None}, "needs a direction"),
        ({"mode": "sideways", "direction": None}, "unknown loading mode 'sideways'"),
    ],
)
def test_bad_directions(kwargs: dict[str, object], match: str) -> None:
    args: dict[str, object] = {"mode": "direction", "loads": [0.0, 1.0]}
    args.update(kwargs)
    with pytest.raises(InputDataError, match=match):
        deflection_curve(design_named("hexapod_6ups"), **args)  # type: ignore[arg-type]


def test_deflection_path_refuses_an_unknown_mode_label() -> None:
    with pytest.raises(InputDataError, match="unknown loading mode 'twist'"):
        deflection_path(design_named("3prs"), [0, 0, 0, 1.0, 0, 0], [0, 1.0], mode="twist")


# ------------------------------------------------------------------ the command
def _run(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


def test_deflect_json_carries_the_full_pose(capsys: pytest.CaptureFixture[str]) -> None:
    """Review finding: the pose was printed and written as (x, y, phi) = pose[0:3], so
    a planar pose's phi was z (0) and a spatial pose's 'phi' its height."""
    doc = json.loads(_run(["deflect", "--json", "--phi", "3", "--max", "1", "--step", "1"], capsys))
    assert doc["pose"]["phi"] == pytest.approx(math.radians(3), rel=1e-15)
    assert doc["pose"]["rz"] == doc["pose"]["phi"] and doc["pose"]["z"] == 0.0
    out = _run(["deflect", "--phi", "3", "--max", "1", "--step", "1"], capsys)
    assert "phi = 3.000 deg" in out
    hexapod = str(Path(__file__).parents[1] / "examples/hexapod_6ups.toml")
    argv = ["deflect", "--json", "--design", hexapod, "--z", "210", "--rx", "2", "--max", "100"]
    doc = json.loads(_run([*argv, "--direction", "10,0,0,0,0,1"], capsys))
    design = design_named("hexapod_6ups")
    expected = full_pose(design, [0, 0, 0.21, math.radians(2), 0, 0])
    pose = [doc["pose"][k] for k in ("x", "y", "z", "rx", "ry", "rz")]
    np.testing.assert_allclose(pose, expected, rtol=1e-15, atol=1e-18)
    assert doc["mode"] == "direction" and doc["load_unit"] == "N"
    np.testing.assert_allclose(doc["load_direction"], [0, 0, 0.1, 1, 0, 0], rtol=1e-15)
    curve = deflection_curve(
        design, "direction", doc["loads"], expected, direction=[0, 0, 1, 10, 0, 0]
    )
    np.testing.assert_allclose(doc["twists"], curve.twists, rtol=1e-12, atol=1e-20)
    np.testing.assert_allclose(doc["loaded_poses"], curve.loaded_poses(), rtol=1e-12, atol=1e-18)
    assert doc["task_coordinates"] == ["x", "y", "z", "rx", "ry", "rz"]


def test_a_direction_csv_reads_back_as_its_measurements(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """deflect --direction --csv writes a '# direction:' line: the file is a
    measurement file of its own curve (zero RMS difference), it gives deflect its mode
    and direction, and a curve along another direction is refused against it."""
    rps = str(Path(__file__).parents[1] / "examples/3rps.toml")
    csv = tmp_path / "d.csv"
    argv = ["deflect", "--design", rps, "--direction", "5,0,-10,0,1,0", "--max", "40"]
    _run([*argv, "--csv", str(csv)], capsys)
    meas = read_measurements(csv)
    assert meas.mode == "direction"
    np.testing.assert_allclose(meas.unit_wrench(), direction_wrench([0, 1, 0, 5, 0, -10]))
    curve = deflection_curve(
        design_named("3rps"), "direction", meas.load_values(), direction=[0, 1, 0, 5, 0, -10]
    )
    rms = rms_differences(curve, meas)
    assert rms["orientation_deg"] < 1e-8 and rms["position_mm"] < 1e-8
    doc = json.loads(
        _run(["deflect", "--design", rps, "--measurements", str(csv), "--json"], capsys)
    )
    assert doc["mode"] == "direction" and doc["rms_differences"]["position_mm"] < 1e-8
    code = main(
        ["deflect", "--design", rps, "--measurements", str(csv), "--direction", "1,0,0,0,0,0"]
    )
    err = capsys.readouterr().err
    assert code == 2 and "the measurements are for the load per unit" in err


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["--direction", "1,2,3"], "--direction must be 6 numbers FX,FY,FZ,MX,MY,MZ"),
        (["--direction", "0,0,0,0,0,0"], "--direction must not be zero"),
        (["--direction", "1,0,0,0,0,nan"], "--direction components must be finite"),
        (
            ["--direction", "1,0,0,0,0,0", "--mode", "moment"],
            "--direction goes with --mode direction",
        ),
        (["--mode", "direction"], "--mode direction needs --direction"),
        (["--mode", "wrench"], "--mode wrench needs --wrench"),
        (
            ["--direction", "1,0,0,0,0,0", "--wrench", "1,0,0,0,0,0"],
            "--wrench goes with --mode wrench",
        ),
    ],
)
def test_deflect_direction_errors(
    args: list[str], match: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    csv = tmp_path / "d.csv"
    assert main(["deflect", *args, "--csv", str(csv)]) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert out == "" and len(lines) == 1 and match in lines[0]
    assert not csv.exists()


def test_the_picture_of_a_spatial_design_shows_all_six_components() -> None:
    """A planar design's planar-force picture keeps Fig. 10's components (phi_z; x,
    y); a spatial design's shows the three rotations and the three displacements."""
    from ppm_stiffness.visuals.deflection import plot_deflection_curves

    def labels(curve: object) -> list[list[str]]:
        fig = plot_deflection_curves(curve)  # type: ignore[arg-type]
        return [[ln.get_label().split()[0] for ln in ax.get_lines()] for ax in fig.axes]

    planar = deflection_curve(design_named("paper"), "planar-force", [0.0, 5.0])
    assert labels(planar) == [["φz"], ["x", "y"]]
    spatial = deflection_curve(design_named("3prs"), "planar-force", [0.0, 5.0])
    assert labels(spatial) == [["φx", "φy", "φz"], ["x", "y", "z"]]


def test_measurements_at_another_pose_are_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Review finding: deflect ignored a measurement file's pose columns, comparing a
    curve at the home pose with rows measured elsewhere. Now the file's pose must be
    the curve's (the pose options give it)."""
    path = tmp_path / "m.csv"
    path.write_text(
        "# mode: moment\npose_x_mm,pose_y_mm,pose_phi_deg,load,phi_z_deg\n2,0,3,0.1,0.5\n",
        encoding="utf-8",
    )
    assert main(["deflect", "--measurements", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}, line 3: the measurements are at pose (x = 2.00 mm" in err
    assert "the model curve at (x = 0.00 mm" in err
    _run(["deflect", "--measurements", str(path), "--x", "2", "--phi", "3"], capsys)
