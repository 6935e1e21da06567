"""A leg's chain as a product of exponentials (legs/screw_chain.py): its Jacobian and its
second derivatives (Lie brackets) against finite differences of its own forward
kinematics, the exponential against Rodrigues' rotation about a point, and, unloaded,
the leg stiffness of today's model (core/solver.py) exactly."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from tests.helpers import design_named, example_designs, flexure_jointed

from ppm_stiffness.core.solver import leg_stiffness
from ppm_stiffness.legs.chain import leg_springs
from ppm_stiffness.legs.screw_chain import (
    bracket,
    bracket_form,
    forward,
    screw_chain,
    se3_exp,
)
from ppm_stiffness.model import solve_legs
from ppm_stiffness.poses import home_pose
from ppm_stiffness.statics.moving_core import PlatformChains, linearize, zero_state

DESIGNS = example_designs(paper=True)


def _chain(name: str, leg: int = 0, offset: tuple[float, float, float] = (0.01, -0.02, 0.03)):
    design = design_named(name)
    lp = solve_legs(design, home_pose(design))[leg]
    return screw_chain(design.legs[leg].chain(lp), design.legs[leg].actuator, 1, offset)


def _twist_of(rot_dot: np.ndarray, rot: np.ndarray, pos_dot: np.ndarray, pos: np.ndarray):
    """The spatial twist (w, v at the origin) of a motion from the rates of (R, p)."""
    w_hat = rot_dot @ rot.T
    w = np.array([w_hat[2, 1], w_hat[0, 2], w_hat[1, 0]])
    return np.concatenate([w, pos_dot - np.cross(w, pos)])


@pytest.mark.parametrize("name", ["3rpr", "hexapod_6ups", "3prs"])
def test_jacobian_and_its_derivative_are_those_of_the_product_of_exponentials(name: str) -> None:
    """Central differences (h = 1e-6) of forward() at a random configuration: the
    Jacobian's columns are the twists of the coordinates (largest residual measured
    8e-11, of unit twists) and dJ_k/dx_l = [J_l, J_k] for l < k, 0 otherwise (measured
    3e-10)."""
    chain = _chain(name)
    x = np.random.default_rng(3).normal(size=(1, chain.n)) * 0.05
    kin = forward(chain.screws, x)
    h = 1e-6
    worst_j, worst_h = 0.0, 0.0
    for i in range(chain.n):
        xp, xm = x.copy(), x.copy()
        xp[0, i] += h
        xm[0, i] -= h
        kp, km = forward(chain.screws, xp), forward(chain.screws, xm)
        fd = _twist_of(
            (kp.rotation - km.rotation)[0] / (2 * h),
            kin.rotation[0],
            (kp.translation - km.translation)[0] / (2 * h),
            kin.translation[0],
        )
        worst_j = max(worst_j, float(np.abs(fd - kin.jacobian[0, :, i]).max()))
        d_jac = (kp.jacobian - km.jacobian)[0] / (2 * h)
        for k in range(chain.n):
            expected = (
                bracket(kin.jacobian[0, :, i], kin.jacobian[0, :, k]) if i < k else np.zeros(6)
            )
            worst_h = max(worst_h, float(np.abs(d_jac[:, k] - expected).max()))
    assert worst_j < 5e-10
    assert worst_h < 2e-9


def test_bracket_form_is_the_wrench_on_the_brackets() -> None:
    chain = _chain("hexapod_6ups")
    rng = np.random.default_rng(5)
    kin = forward(chain.screws, rng.normal(size=(1, chain.n)) * 0.05)
    w = rng.normal(size=(1, 6))
    q = bracket_form(kin.jacobian, w)[0]
    jac = kin.jacobian[0]
    expected = np.array(
        [[w[0] @ bracket(jac[:, a], jac[:, b]) for b in range(chain.n)] for a in range(chain.n)]
    )
    np.testing.assert_allclose(q, expected, rtol=0, atol=1e-14 * np.abs(expected).max())


def test_exponential_of_a_rotation_screw_turns_about_its_axis_point() -> None:
    """exp of theta (a, c x a): R = Rodrigues(a theta) (scipy), p = (I - R) c."""
    rng = np.random.default_rng(7)
    a = rng.normal(size=3)
    a /= np.linalg.norm(a)
    c = rng.normal(size=3) * 0.2
    for theta in (1e-7, 0.3, 2.5):
        rot, p = se3_exp(np.concatenate([a, np.cross(c, a)]) * theta)
        expected = Rotation.from_rotvec(a * theta).as_matrix()
        np.testing.assert_allclose(rot, expected, rtol=0, atol=1e-15)
        np.testing.assert_allclose(p, (np.eye(3) - expected) @ c, rtol=0, atol=1e-15)


@pytest.mark.parametrize("name", DESIGNS)
def test_unloaded_chain_gives_todays_leg_stiffness(name: str) -> None:
    """The chain's coordinates at rest are the leg's virtual springs and passive joints
    (reordered): each leg's loaded tangent at zero load equals today's bordered
    inverse (core.solver.leg_stiffness) to round-off (largest measured 4e-14 of the
    largest length-balanced entry; 2.05e-12 for the flexure 6-RUS, whose flexures'
    4.7 N·m/rad and hardware springs of 1e7 N/m meet in one LU: asserted to 6e-12)."""
    design = design_named(name)
    pose = home_pose(design)
    for leg, lp in zip(design.legs, solve_legs(design, pose), strict=True):
        chain = screw_chain(leg.chain(lp), leg.actuator, 1)
        system = PlatformChains((chain,))
        k_chain = linearize(system, zero_state(system), np.zeros((1, 6))).stiffness[0]
        k_today = leg_stiffness(leg_springs(leg.chain(lp), leg.locked_stiffness()))
        scale = np.array([10.0] * 3 + [1.0] * 3)
        err = np.abs((k_chain - k_today) * scale[:, None] * scale).max()
        tol = 6e-12 if flexure_jointed(design) else 2e-13
        assert err <= tol * np.abs(k_today * scale[:, None] * scale).max()


def test_forward_with_translations_is_the_product_of_the_exps() -> None:
    """``forward`` takes a translation's exp as (I, v) without se3_exp (issue 32 item 2):
    the product of every coordinate's se3_exp, to round-off, on a chain of rotations and
    translations at random coordinates (bit for bit the code before on the shipped
    examples' chains, checked when the shortcut was made)."""
    rng = np.random.default_rng(3)
    k, n = 4, 8
    screws = rng.normal(size=(k, 6, n))
    screws[:, :3, [1, 4, 5]] = 0.0  # three translations
    x = rng.normal(size=(k, n)) * 0.1
    r_e, p_e = se3_exp(np.swapaxes(screws, 1, 2) * x[:, :, None])
    rot = np.broadcast_to(np.eye(3), (k, 3, 3)).copy()
    pos = np.zeros((k, 3))
    jac = np.zeros((k, 6, n))
    for i in range(n):  # J_i = Ad(g_1 ... g_{i-1}) s_i, then g <- g g_i
        w = np.einsum("kij,kj->ki", rot, screws[:, :3, i])
        v = np.einsum("kij,kj->ki", rot, screws[:, 3:, i]) + np.cross(pos, w)
        jac[:, :, i] = np.concatenate([w, v], axis=1)
        pos = pos + np.einsum("kij,kj->ki", rot, p_e[:, i])
        rot = rot @ r_e[:, i]
    kin = forward(screws, x)
    np.testing.assert_allclose(kin.rotation, rot, rtol=0, atol=1e-15)
    np.testing.assert_allclose(kin.translation, pos, rtol=0, atol=1e-15)
    np.testing.assert_allclose(kin.jacobian, jac, rtol=0, atol=1e-14)


def test_a_chain_with_bars_shifted_is_the_chain_about_the_new_point() -> None:
    """The Delta's chains (each ends in a parallelogram's two bars) built about P and
    then shifted to a point d equal those built about d: the twists, and the bars' ends
    relative to the new point (``shifted`` left the bars' ends relative to the old one)."""
    from ppm_stiffness.poses import full_pose
    from ppm_stiffness.statics.moving_path import platform_chains

    design = design_named("delta")
    pose = full_pose(design, home_pose(design)[:3] + np.array([0.02, -0.01, 0.03]))[None, :]
    d = np.array([[0.03, -0.05, 0.08]])
    about_p = platform_chains(design, pose, np.zeros((1, 3)))
    about_d = platform_chains(design, pose, d)
    for a, b in zip(about_p.chains, about_d.chains, strict=True):
        assert a.bars is not None and b.bars is not None
        moved = a.shifted(d)
        assert moved.bars is not None
        np.testing.assert_allclose(moved.screws, b.screws, rtol=0, atol=1e-15)
        np.testing.assert_allclose(moved.bars.near, b.bars.near, rtol=0, atol=1e-15)
        np.testing.assert_allclose(moved.bars.far, b.bars.far, rtol=0, atol=1e-15)
        np.testing.assert_allclose(moved.bars.rest, b.bars.rest, rtol=0, atol=1e-15)
