"""The loaded mode (moving geometry) of a Delta robot's parallelogram forearms (issue 28,
items 1 and 6): the bars as two-force members that swing under their axial loads, checked
against an independent large-displacement model of the same Delta written here from its
geometry alone (rigid arms turning about their drive axes against linear drives, each
bar an axial spring between its corners), solved by scipy's root finder.
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy.optimize import root

from ppm_stiffness.core.pose import rotation
from ppm_stiffness.design.io import design_from_dict
from ppm_stiffness.legs.screw_chain import rotation_log
from ppm_stiffness.model import full_pose, stiffness_at_pose
from ppm_stiffness.statics.moving import moving_loaded_state, relative_difference

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "delta.toml"
#: A drive stiffness [N·m/rad] (linear: the same locked and above the threshold).
K_THETA = 2e4


def _data() -> dict[str, Any]:
    with open(EXAMPLE, "rb") as f:
        return tomllib.load(f)


def _truss_delta() -> Any:
    """The shipped Delta with rigid arms and drive bearings and linear drives: the arm's
    angle and the bars' axial springs (bar and corner springs) are its only compliances."""
    data = _data()
    leg = data["legs"][0]
    drive, arm, forearm = leg["elements"]
    drive.pop("springs")
    arm["link"] = "rigid"
    forearm["parallelogram"].pop("mass")
    leg["actuator"] = {
        "locked_stiffness": K_THETA,
        "k_a": K_THETA,
        "q": 1.0,
        "threshold_displacement": 0.0,
    }
    return design_from_dict(data)


def _rotvec(phi: np.ndarray) -> np.ndarray:
    """The rotation of rotation vector phi (3,) [rad]."""
    angle = float(np.linalg.norm(phi))
    return np.eye(3) if angle == 0.0 else _turn(phi / angle, angle)


def _turn(axis: np.ndarray, angle: float) -> np.ndarray:
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


class IndependentDelta:
    """The truss Delta at a reference pose (module doc): unknowns the drives' angles
    from there (3) [rad], the platform's rotation vector (3) [rad] and P's displacement
    (3) [m]; a force at P of fixed direction and a couple of fixed direction."""

    def __init__(self, design: Any, pose: np.ndarray) -> None:
        self.p0 = pose[:3]
        self.r0 = rotation(pose)
        self.legs = []
        for leg in design.legs:
            drive, _, forearm = leg.elements
            width = forearm.width
            half = 0.5 * width * np.asarray(forearm.crossbar)
            a, c = np.asarray(drive.axis, dtype=float), np.asarray(drive.point, dtype=float)
            theta = float(leg.solve(pose).coordinates["actuated"])
            near_home = [np.asarray(forearm.near) + s * half for s in (1, -1)]
            near = [c + _turn(a, theta) @ (e - c) for e in near_home]
            home = design.workspace.start()
            far = [
                self.r0 @ rotation(home).T @ (np.asarray(forearm.far) + s * half - home[:3])
                for s in (1, -1)
            ]  # platform points relative to P, axes of F_b
            section = forearm.parallelogram
            length = float(np.linalg.norm(np.subtract(forearm.far, forearm.near)))
            compliance = length / (section.young_modulus * section.area)
            compliance += 2.0 / forearm.springs.axial
            rest = [float(np.linalg.norm(self.p0 + f - e)) for e, f in zip(near, far, strict=True)]
            self.legs.append((a, c, near, far, 1.0 / compliance, rest))

        self.prestress = np.zeros((3, 3))  # per leg: the drive's torque, two bar forces

    def prestress_for(self, wrench: np.ndarray) -> None:
        """Forces in the bars and drives at the reference geometry that carry
        ``wrench`` (its statics: six bar forces from the platform's balance, then each
        drive's torque from its arm's), so that the reference is an equilibrium under
        it: the tangent there is the loaded tangent on the unloaded geometry (P-Delta)."""
        lines, arms = [], []
        for a, c, near, far, _, _ in self.legs:
            for e, f in zip(near, far, strict=True):
                n = (self.p0 + f - e) / np.linalg.norm(self.p0 + f - e)
                lines.append(np.concatenate([np.cross(f, n), n]))
                arms.append(a @ np.cross(e - c, n))
        forces = np.linalg.solve(np.array(lines).T, wrench)
        torques = (np.array(arms) * forces).reshape(3, 2).sum(axis=1)
        self.prestress = np.column_stack([torques, forces.reshape(3, 2)])

    def residual(self, z: np.ndarray, wrench: np.ndarray) -> np.ndarray:
        """Drive torque balances (N·m) and the platform's (moment about P', force)."""
        theta, phi, dp = z[:3], z[3:6], z[6:]
        turn = _rotvec(phi)
        p = self.p0 + dp
        out = np.zeros(9)
        total = wrench.copy()
        for i, (a, c, near, far, k_bar, rest) in enumerate(self.legs):
            arm = _turn(a, theta[i])
            torque = -K_THETA * theta[i] - self.prestress[i, 0]
            for j, (e0, f0, length) in enumerate(zip(near, far, rest, strict=True)):
                e = c + arm @ (e0 - c)
                f = p + turn @ f0
                n = (f - e) / np.linalg.norm(f - e)
                tension = self.prestress[i, 1 + j] + k_bar * (np.linalg.norm(f - e) - length)
                torque += a @ np.cross(e - c, tension * n)
                total -= np.concatenate([np.cross(f - p, tension * n), tension * n])
            out[i] = torque
        out[3:] = total
        return out

    def solve(self, wrench: np.ndarray, start: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The platform's rotation (3, 3) and P's displacement (3,) under ``wrench``."""
        sol = root(self.residual, start, args=(wrench,), method="hybr", tol=1e-15)
        assert np.max(np.abs(self.residual(sol.x, wrench))) < 1e-9 * np.abs(wrench).max()
        return _rotvec(sol.x[3:6]), sol.x[6:]

    def tangent(self, wrench: np.ndarray, start: np.ndarray, h: np.ndarray) -> np.ndarray:
        """The inverse of the central differences (steps h (6,)) of the platform's
        twist (R -> exp(phi) R, P moved) around the equilibrium under ``wrench``."""
        rot, dp = self.solve(wrench, start)
        columns = []
        for j in range(6):
            moved = []
            for sign in (1.0, -1.0):
                r, d = self.solve(wrench + sign * h[j] * np.eye(6)[j], start)
                moved.append(np.concatenate([rotation_log(r @ rot.T), d - dp]))
            columns.append((moved[0] - moved[1]) / (2 * h[j]))
        return np.asarray(np.linalg.inv(np.stack(columns, axis=1)))


@pytest.fixture(scope="module")
def truss() -> Any:
    return _truss_delta()


WRENCH = np.array([0.4, -0.3, 0.2, 30.0, -50.0, -200.0])


def test_the_equilibrium_is_the_independent_models(truss: Any) -> None:
    """Under a wrench the platform's displacement equals the independent model's (to
    1e-11 of it, measured 2.6e-12; the chain of two P joints and a U in place of the
    bars is off by 6e-3) and the legs' wrenches sum to the load (measured 7e-15 N of
    200 N)."""
    pose = full_pose(truss, np.array([0.05, -0.03, -0.78]))
    state = moving_loaded_state(truss, WRENCH, pose)
    model = IndependentDelta(truss, pose)
    rot, dp = model.solve(WRENCH, np.zeros(9))
    expected = np.concatenate([rotation_log(rot @ model.r0.T), dp])
    assert np.max(np.abs(state.twist - expected)) < 1e-11 * np.max(np.abs(expected))
    np.testing.assert_allclose(state.leg_wrenches.sum(axis=0), WRENCH, rtol=0, atol=1e-12)


def test_loaded_tangent_is_the_independent_models_derivative(truss: Any) -> None:
    """K_F is the inverse of the central differences of the independent model's
    equilibria (platform twist, the conventions' update R -> exp(phi) R) under the load
    plus and minus small wrenches: measured 1.7e-10 (length-balanced norm; the solves'
    round-off, falling as h grows: 1.1e-8 at h/100), asserted to 1e-9, where the frozen
    loaded K differs by 6.9e-4 and the chain of two P joints and a U in place of the bars
    by 3.5e-3: the bars' swing under their forces is in K_F, and only it."""
    pose = full_pose(truss, np.array([0.05, -0.03, -0.78]))
    state = moving_loaded_state(truss, WRENCH, pose)
    model = IndependentDelta(truss, pose)
    rot, dp = model.solve(WRENCH, np.zeros(9))
    start = np.concatenate([state.actuator_displacements, rotation_log(rot), dp])
    h = np.array([0.1] * 3 + [1.0] * 3)  # round-off of the solves falls with h
    fd = model.tangent(WRENCH, start, h)
    assert relative_difference(fd, state.stiffness_matrix) < 1e-9
    assert relative_difference(state.frozen_stiffness, state.stiffness_matrix) > 1e-4


def test_zero_load_gives_the_frozen_k() -> None:
    """K_F at zero wrench is today's K of the shipped Delta, at a pose away from home
    (measured 1.5e-15; 2.0e-15 at home, tests/test_moving_geometry.py)."""
    design = design_from_dict(_data())
    pose = full_pose(design, np.array([0.05, -0.03, -0.78]))
    state = moving_loaded_state(design, np.zeros(6), pose)
    diff = relative_difference(state.stiffness_matrix, stiffness_at_pose(design, pose))
    assert diff < 1e-14


def test_the_cli_gives_the_deltas_loaded_tangent_and_load_margin(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """``analyze --wrench 0,0,0,-20,0,0 --geometry moving`` (a couple of -20 N·m about
    x; was refused) prints the library's K_F and a load margin (measured: 99.94 times
    the load, a limit point), and ``deflect --geometry moving`` follows a vertical load
    (-0.6173 mm at -200 N: measured)."""
    from ppm_stiffness.cli import main
    from ppm_stiffness.statics.moving import moving_loaded_state as solve

    argv = ["analyze", "--design", str(EXAMPLE), "--wrench", "0,0,0,-20,0,0"]
    assert main([*argv, "--geometry", "moving", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    state = solve(design_from_dict(_data()), np.array([-20.0, 0, 0, 0, 0, 0]))
    mg = doc["moving_geometry"]
    np.testing.assert_allclose(mg["stiffness_matrix"], state.stiffness_matrix, rtol=1e-12)
    assert mg["load_margin"]["kind"] == "limit point"
    assert mg["load_margin"]["factor"] == pytest.approx(99.9356, abs=5e-4)
    assert main([*argv, "--geometry", "moving"]) == 0
    out = capsys.readouterr().out
    assert "Loaded tangent stiffness K_F at the displaced P" in out
    assert "load margin: 99.9356 times the load" in out
    deflect = ["deflect", "--design", str(EXAMPLE), "--mode", "wrench", "--json"]
    deflect += ["--wrench", "0,0,-100,0,0,0", "--max", "2", "--step", "1"]
    assert main([*deflect, "--geometry", "moving"]) == 0
    text = capsys.readouterr().out
    assert "moving_geometry" in json.loads(text)
    assert "-0.6173" in text or "-0.0006173" in text


def test_rigid_bars_and_a_couple() -> None:
    """Rigid bars (compliance 0: their lengths held, their forces reactions): K_F(0) = K
    (measured 2.7e-15) and K_F is the derivative of the wrench the legs exert with the
    platform held at displaced_pose(pose, +-h e_j) (measured 1.3e-10, asserted 1e-9;
    the frozen K differs by 9.9e-4). A couple m of fixed direction adds exactly -m^ to
    K_F - K_F^T in the rotation block (measured 1e-15 of K_F; -m^ is 4.4e-5 of it)."""
    from ppm_stiffness.core.conventions import hat
    from ppm_stiffness.core.pose import displaced_pose
    from ppm_stiffness.statics.moving import relative_size
    from ppm_stiffness.statics.moving_tangents import held_wrenches

    data = _data()
    forearm = data["legs"][0]["elements"][2]
    forearm["parallelogram"] = "rigid"
    forearm.pop("springs")
    design = design_from_dict(data)
    pose = full_pose(design, np.array([0.05, -0.03, -0.78]))
    zero = moving_loaded_state(design, np.zeros(6), pose)
    assert relative_difference(zero.stiffness_matrix, stiffness_at_pose(design, pose)) < 1e-14
    state = moving_loaded_state(design, WRENCH, pose)
    h = np.array([1e-5] * 3 + [1e-6] * 3)
    poses = [
        displaced_pose(state.displaced_pose, sign * h[j] * np.eye(6)[j])
        for j in range(6)
        for sign in (1.0, -1.0)
    ]
    held, _ = held_wrenches(design, state, np.array(poses))
    fd = np.stack([(held[2 * j] - held[2 * j + 1]) / (2 * h[j]) for j in range(6)], axis=1)
    k = state.stiffness_matrix
    assert relative_difference(fd, k) < 1e-9
    assert relative_difference(state.frozen_stiffness, k) > 5e-4
    expected = np.zeros((6, 6))
    expected[:3, :3] = -hat(WRENCH[:3])
    assert relative_size(k - k.T - expected, k) < 1e-14
    assert relative_size(expected, k) > 1e-5


def test_the_p_delta_tangent_is_the_prestressed_models(truss: Any) -> None:
    """The loaded tangent on the unloaded geometry (moving_tangents.reference_tangent,
    the second-order FE comparison's): the independent model with the bars and drives
    prestressed by the forces that carry the load at the reference geometry, its
    tangent there by central differences: measured 1.5e-10, asserted 1e-9, where the
    tangent without the geometric term differs by 3.6e-4 (the bars' forces were left
    at 0 before: the P-Delta tangent was the frozen K exactly)."""
    from ppm_stiffness.statics.moving_tangents import reference_tangent

    pose = full_pose(truss, np.array([0.05, -0.03, -0.78]))
    k2, k1 = reference_tangent(truss, WRENCH, pose)
    model = IndependentDelta(truss, pose)
    model.prestress_for(WRENCH)
    np.testing.assert_allclose(model.residual(np.zeros(9), WRENCH), 0.0, atol=1e-12)
    fd = model.tangent(WRENCH, np.zeros(9), np.array([0.1] * 3 + [1.0] * 3))
    assert relative_difference(fd, k2) < 1e-9


def test_a_loaded_map_of_the_delta_is_the_single_pose_analysis() -> None:
    """``map --actuators WRENCH --geometry moving`` on the Delta (an x-y slice): the
    spatial principal stiffnesses of K_F's symmetric part and the load margin at each
    pose equal the single-pose ones (the batched path is the single-pose path:
    measured 2.0e-15 and 0, asserted 1e-13 and 1e-14); the margin is finite (measured
    91-141 times this load, limit points)."""
    from ppm_stiffness.core.principal import principal_compliance
    from ppm_stiffness.maps.result import PRINCIPAL
    from ppm_stiffness.maps.workspace import stiffness_map
    from ppm_stiffness.statics.margin import MarginKind, load_margin

    design = design_from_dict(_data())
    wrench = np.array([-20.0, 0.0, 0.0, 0.0, 0.0, -100.0])
    z = float(design.workspace.start()[2])
    smap = stiffness_map(
        design,
        axes=("x", "y"),
        fixed={"z": z},
        grid=(3, 2),
        bounds=(-0.1, 0.1, -0.1, 0.1),
        actuators="wrench",
        wrench=wrench,
        geometry="moving",
        quantities="principal,load_margin",
    )
    assert smap.reachable.all()
    for j, i in np.argwhere(smap.reachable):
        pose = np.array([smap.u[i], smap.v[j], z])
        k_f = moving_loaded_state(design, wrench, pose).stiffness_matrix
        pc = principal_compliance(0.5 * (k_f + k_f.T))
        ref = np.concatenate([np.sort(pc.rotational_values), np.sort(pc.translational_values)])
        got = np.array([smap.quantities[q][j, i] for q in PRINCIPAL])
        np.testing.assert_allclose(got, ref, rtol=1e-13)
        margin = load_margin(design, wrench, pose)
        assert margin.factor is not None and margin.kind == MarginKind.LIMIT_POINT
        assert smap.quantities["load_margin"][j, i] == pytest.approx(margin.factor, rel=1e-14)


def _newton(model: IndependentDelta, z: np.ndarray, wrench: np.ndarray) -> np.ndarray:
    """The independent model's equilibrium near z: Newton's method with a central-
    difference Jacobian (scipy's hybr does not follow the path this far)."""
    for _ in range(30):
        r = model.residual(z, wrench)
        if np.max(np.abs(r)) < 1e-9 * np.max(np.abs(wrench)):
            return z
        z = z - np.linalg.solve(_jacobian(model, z, wrench), r)
    raise AssertionError("the independent model's Newton did not converge")


def _jacobian(model: IndependentDelta, z: np.ndarray, wrench: np.ndarray) -> np.ndarray:
    eps = 1e-8
    columns = [
        (model.residual(z + eps * e, wrench) - model.residual(z - eps * e, wrench)) / (2 * eps)
        for e in np.eye(9)
    ]
    return np.stack(columns, axis=1)


def test_the_load_margin_is_the_independent_models_limit_point(truss: Any) -> None:
    """The load margin under a couple and a vertical force (a limit point at 316.22
    times the load: the platform turned by 0.5 rad) is where the independent model's
    equilibrium path folds: following it to 0.995 and 0.999 of that factor, its
    Jacobian's smallest eigenvalue falls as sqrt(lambda_c - lambda) (a fold), and the
    lambda_c of that law from the two is the margin to 5e-5 (measured 5.1e-6, the
    law's own truncation)."""
    from ppm_stiffness.statics.margin import MarginKind, load_margin

    pose = full_pose(truss, np.array([0.05, -0.03, -0.78]))
    wrench = np.array([-20.0, 0.0, 0.0, 0.0, 0.0, -100.0])
    margin = load_margin(truss, wrench, pose)
    assert margin.kind == MarginKind.LIMIT_POINT and margin.factor is not None
    model = IndependentDelta(truss, pose)
    z = np.zeros(9)
    smallest = []
    for lam in [*np.linspace(0.0, 0.99, 34)[1:], 0.995, 0.999]:
        w = lam * margin.factor * wrench
        z = _newton(model, z, w)
        if lam > 0.99:
            smallest.append(np.min(np.abs(np.linalg.eigvals(_jacobian(model, z, w)))))
    ratio = (smallest[0] / smallest[1]) ** 2  # (c - 0.995) / (c - 0.999), a fold at c
    fold = (0.999 * ratio - 0.995) / (ratio - 1.0)
    assert abs(fold - 1.0) < 5e-5
    assert abs(z[3]) > 0.45  # the independent platform has turned by 0.5 rad about x
