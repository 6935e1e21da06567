"""Identification on spatial designs: 6-D pose rows, predictions through the loaded
model at full poses, noise-free recovery on the hexapod and the 3-RPS, and the
command on the shipped synthetic 3-RPS data."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from helpers import design_named
from ppm_stiffness.cli import main
from ppm_stiffness.design import Design, load_design
from ppm_stiffness.fit.identify import MeasurementRows, identify, measurement_rows, predict_twists
from ppm_stiffness.poses import full_poses, home_pose, task_values
from ppm_stiffness.statics.deflection import deflection_path
from ppm_stiffness.statics.measurements import read_measurements

ROOT = Path(__file__).parents[1]
DATA = ROOT / "examples/identification/3rps_measurements.csv"
#: Forces [N] along x, y, z and moments [N·m] about x, y, z, as (m, f) rows.
WRENCHES = np.array(
    [
        [0, 0, 0, 100.0, 0, 0],
        [0, 0, 0, 0, 100.0, 0],
        [0, 0, 0, 0, 0, 300.0],
        [10.0, 0, 0, 0, 0, 0],
        [0, 10.0, 0, 0, 0, 0],
        [0, 0, 10.0, 0, 0, 0],
    ]
)


def _rows(design: Design, truth: Design, offsets: list[list[float]]) -> MeasurementRows:
    """Noise-free rows of ``truth`` (six twist components) at the design's home task
    coordinates + offsets, each pose under every wrench, as full poses."""
    task = task_values(design, home_pose(design))
    poses, ok = full_poses(design, np.array([task + o for o in offsets for _ in WRENCHES]))
    assert ok.all()
    w = np.tile(WRENCHES, (len(offsets), 1))
    sigma = np.tile([1e-7] * 3 + [1e-8] * 3, (len(poses), 1))
    return MeasurementRows(poses, w, predict_twists(truth, poses, w), sigma)


def _recovered(name: str, factors: dict[str, float], offsets: list[list[float]]) -> float:
    design = design_named(name)
    truth = design.with_parameters({n: design.parameter(n) * f for n, f in factors.items()})
    result = identify(design, _rows(design, truth, offsets), list(factors))
    expected = np.array([design.parameter(n) * factors[n] for n in result.names])
    assert result.weighted_rms < 1e-6
    return float(np.max(np.abs(result.values / expected - 1)))


def test_noise_free_recovery_on_the_hexapod() -> None:
    """Three actuators, the tied rod modulus and the tied base U-joints' axial
    stiffness, changed by 10-20 %, at three poses: recovered to 1e-10 relative
    (measured 3.1e-11, the rod modulus, whose relative 1-sigma is 3 % with these
    sigmas; the others below 6e-12). The hexapod's legs are two-force members, its
    forces statically determinate: the twist is linear in the compliances and the
    linear start is the solution."""
    factors = {
        "leg1.actuator.k_a": 1.2,
        "leg2.actuator.k_a": 0.85,
        "leg4.actuator.k_a": 1.1,
        "leg*.rod.young_modulus": 0.9,
        "leg*.base_joint.axial": 1.15,
    }
    offsets = [[0.0] * 6, [0.01, 0, 0.02, 0.05, 0, 0], [-0.01, 0.01, -0.01, 0, 0.05, 0.1]]
    assert _recovered("hexapod_6ups", factors, offsets) < 1e-10


def test_noise_free_recovery_on_the_3rps() -> None:
    """Three actuators, the tied base revolutes' tilt and the tied rod bushings'
    lateral stiffness at three poses (z, rx, ry offsets; x, y, rz completed): recovered
    to 1e-10 relative (measured 3.5e-11, the lateral bushing: relative 1-sigma 2 %;
    the others below 4e-13). Each leg transmits two wrenches (its actuator and its
    revolute's constraint), so the twist is not linear in the compliances (the linear
    model misses by 1.5e-9 of the residuals): the nonlinear stage runs. With the
    earlier LINEARITY_TOLERANCE of 1e-7 it was skipped, and the start was 3.9e-8 off."""
    factors = {
        "leg1.actuator.k_a": 1.2,
        "leg2.actuator.k_a": 0.85,
        "leg3.actuator.k_a": 1.1,
        "leg*.base_revolute.tilt": 0.9,
        "leg*.guide.lateral": 1.15,
    }
    offsets = [[0.0, 0, 0], [0.02, 0.08, 0], [-0.02, -0.05, 0.08]]
    assert _recovered("3rps", factors, offsets) < 1e-10


def test_a_prediction_is_deflects_at_the_full_pose() -> None:
    """One row of the 3-PRS at a tilted pose, under a load that is given as task
    coordinates or as the full pose: the same twist, and the one deflect's integrated
    path ends at (to 1e-12 of the largest component, balanced; measured 3.4e-14)."""
    design = design_named("3prs")
    task = np.array([0.39, math.radians(6), math.radians(-3)])
    full = full_poses(design, task)[0]
    w = np.array([1.0, -2.0, 0.5, 50.0, -20.0, 300.0])
    by_task = predict_twists(design, task[None, :], w[None, :])[0]
    by_pose = predict_twists(design, full[None, :], w[None, :])[0]
    np.testing.assert_array_equal(by_task, by_pose)
    curve = deflection_path(design, w, [0.0, 1.0], full, tool_point=np.zeros(3))
    balance = np.array([0.1] * 3 + [1.0] * 3)
    err = np.max(np.abs((by_pose - curve.twists[-1]) * balance))
    assert err <= 1e-12 * np.max(np.abs(by_pose * balance))


def test_rows_of_a_spatial_file_have_full_poses() -> None:
    """The shipped 3-RPS data: six pose columns (task and completed), every row's pose
    is the full pose of its task coordinates."""
    design = load_design(ROOT / "examples/3rps.toml")
    meas = read_measurements(DATA)
    rows = measurement_rows(design, meas)
    assert rows.poses.shape == (24, 6)
    completed, ok = full_poses(design, task_values(design, meas.poses))
    assert ok.all()
    np.testing.assert_array_equal(rows.poses, completed)
    # the file's x, y, rz are those poses' to its 10 printed digits
    np.testing.assert_allclose(meas.poses, completed, rtol=1e-9, atol=1e-15)


# ------------------------------------------------------------------ the command
#: The shipped data's prototype (scripts/synthetic_identification_data.py).
TRUE = {
    "leg1.actuator.k_a": 0.85 * 60e6,
    "leg2.actuator.k_a": 1.10 * 60e6,
    "leg3.actuator.k_a": 0.95 * 60e6,
    "leg*.base_revolute.tilt": 1.20 * 5e4,
    "leg*.guide.lateral": 0.90 * 3e7,
}


def test_identify_on_the_shipped_3rps_data(capsys: pytest.CaptureFixture[str]) -> None:
    """24 rows, noise 1e-4 deg / 1e-4 mm: every estimate within 3 standard errors of
    the prototype's value (measured: within 1.0), weighted RMS near 1 (1.02)."""
    argv = ["identify", "--design", str(ROOT / "examples/3rps.toml"), "--measurements"]
    assert main([*argv, str(DATA), "--free", ",".join(TRUE), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    for p in doc["parameters"]:
        assert abs(p["estimate"] - TRUE[p["name"]]) <= 3 * p["standard_error"]
    assert 0.8 < doc["weighted_rms"] < 1.25 and doc["n_rows"] == 24


def test_identify_names_the_line_of_an_unreachable_spatial_row(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "far.csv"
    path.write_text(
        "# far\npose_z_mm,pose_rx_deg,pose_ry_deg,fz_N,z_mm,sigma_z_mm\n"
        "350,0,0,100,0,0.001\n900,0,0,100,0,0.001\n",
        encoding="utf-8",
    )
    argv = ["identify", "--design", str(ROOT / "examples/3rps.toml"), "--measurements"]
    assert main([*argv, str(path), "--free", "leg1.actuator.k_a"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{path}, line 4: leg 1: leg length" in err[0]
