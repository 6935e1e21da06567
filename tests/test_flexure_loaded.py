"""The loaded modes of a drive in parallel with a flexure (issue 29 item 2): the shipped
3-RRR stage, whose piezo-lever drives act on its base notch hinges.

The actuated freedom's spring is the drive's law plus the hinge's elastic stiffness k_h
(resting at the unloaded pose): the joint carries ``G + k_h delta``. Checked against
independent computations: the unloaded K at zero wrench, the actuated joint's law and
the platform's force balance at the moving equilibrium (the chain's Jacobian at the
solved coordinates, not the solver's numbers), the drive-only design as k_h -> 0 (by
the slope), and K_F against finite differences of the equilibria.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.core.pose import rotation_exp
from ppm_stiffness.design import Design, design_from_dict, load_design
from ppm_stiffness.legs.parts import ActuatorModel
from ppm_stiffness.legs.screw_chain import forward, rotation_log, screw_chain
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.statics.actuator import actuator_displacement
from ppm_stiffness.statics.loading import actuator_forces, loaded_state
from ppm_stiffness.statics.moving import moving_loaded_state

ROOT = Path(__file__).resolve().parents[1]
#: A wrench the stage carries well inside its strokes (its load margin under 1 N is
#: 256 N): (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at P.
WRENCH = np.array([0.0, 0.0, 0.5, 30.0, -20.0, 0.0])
#: The stage's piezo stack on its lever, k_p r^2 [N·m/rad] (examples/flexure_3rrr.toml).
K_DRIVE = 5000.0


@pytest.fixture(scope="module")
def stage() -> Design:
    return load_design(ROOT / "examples" / "flexure_3rrr.toml")


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    """max |a_ij - b_ij| / sqrt(b_ii b_jj)."""
    d = np.sqrt(np.outer(np.abs(np.diag(b)), np.abs(np.diag(b))))
    return float(np.max(np.abs(a - b) / d))


def test_the_stages_drive_has_the_hinge_in_parallel(stage: Design) -> None:
    """k_h = 1/C_phiz of the circular notch (0.9012 N·m/rad, the header's figure)."""
    assert [leg.parallel_stiffness() for leg in stage.legs] == pytest.approx([0.90122599] * 3)


def test_the_loaded_k_at_zero_wrench_is_the_unloaded_k(stage: Design) -> None:
    """Frozen and moving: K_F(0) = K (measured 0 and 1.3e-13 of the diagonal); K with
    the hinge's share left out of the actuated freedom differs by 8.1e-5, far above."""
    k = stiffness_at_pose(stage)
    assert _relative(loaded_state(stage, np.zeros(6)).stiffness_matrix, k) < 1e-14
    assert _relative(moving_loaded_state(stage, np.zeros(6)).stiffness_matrix, k) < 1e-12
    drive_only = stiffness_at_pose(stage, actuator_stiffness=K_DRIVE - 0.90122599)
    assert _relative(drive_only, k) > 1e-6


def test_the_moving_equilibrium_balances_the_platform_and_each_joint(stage: Design) -> None:
    """At the moving equilibrium, recomputed from the solved coordinates through each
    leg's chain (its spatial Jacobian at the displaced configuration): the generalised
    force at the actuated freedom is ``(k_p + k_h) x`` and the drive's reported force
    ``k_p x`` (measured 5e-16 relative), and the legs' wrenches sum to the applied one."""
    state = moving_loaded_state(stage, WRENCH)
    np.testing.assert_allclose(state.leg_wrenches.sum(axis=0), WRENCH, rtol=0, atol=1e-13)
    k_h = stage.legs[0].parallel_stiffness()
    pose = np.zeros(6)
    for i, leg in enumerate(stage.legs):
        chain = screw_chain(leg.chain(leg.solve(pose)), leg.actuator, 1, np.zeros(3))
        x = np.atleast_2d(state.coordinates[i])
        jac = forward(chain.screws, x).jacobian[0]
        w0 = state.leg_wrenches[i].copy()  # about the displaced P, moved to its home
        w0[:3] += np.cross(state.twist[3:], w0[3:])
        tau = jac.T @ w0
        a = chain.actuator
        assert a is not None
        x_a = x[0, a]
        assert abs(x_a) > 1e-5  # the drive moves
        assert tau[a] == pytest.approx((K_DRIVE + k_h) * x_a, rel=5e-15)
        assert state.actuator_forces[i] == pytest.approx(K_DRIVE * x_a, rel=5e-15)
        assert state.actuator_displacements[i] == x_a


def test_the_frozen_equilibrium_shares_each_joints_load(stage: Design) -> None:
    """Geometry frozen: each leg's joint force ``a_i . w_i`` is the drive's force plus
    the hinge's ``k_h delta``; the drive's is ``k_p delta``; the legs' wrenches sum to
    the applied one; the linear split gives the same drive forces (linear law)."""
    from ppm_stiffness.statics.structures import LegStructures

    state = loaded_state(stage, WRENCH)
    np.testing.assert_allclose(state.leg_wrenches.sum(axis=0), WRENCH, rtol=0, atol=1e-13)
    a = LegStructures(stage, np.zeros(6)).actuator
    joint = np.einsum("ij,ij->i", a, state.leg_wrenches)
    k_h = stage.legs[0].parallel_stiffness()
    delta = state.actuator_displacements
    np.testing.assert_allclose(joint, (K_DRIVE + k_h) * delta, rtol=1e-13)
    np.testing.assert_allclose(state.actuator_forces, K_DRIVE * delta, rtol=1e-13)
    np.testing.assert_allclose(actuator_forces(stage, WRENCH), state.actuator_forces, rtol=1e-12)


def _variant(stage: Design, scale: float | None) -> Design:
    """The stage with its base hinges replaced by R joints with hardware springs and an
    elastic stiffness ``scale * k_h`` in parallel with the drive (None: a plain driven
    joint, today's drive-only case)."""
    k_h = stage.legs[0].parallel_stiffness()
    data = stage.model_dump()
    for leg in data["legs"]:
        leg["elements"][0].update(
            hinge=None,
            axis2=None,
            springs={"tilt": 1.288, "axial": 2.0e8, "radial": 6.0e7},
            elastic=None if scale is None else scale * k_h,
        )
    return design_from_dict(data)


def test_a_vanishing_hinge_tends_to_the_drive_only_case(stage: Design) -> None:
    """As the parallel stiffness s k_h -> 0 the loaded states tend to the plain driven
    joint's at first order in s: log10 of the differences' ratio over s = 0.1 -> 0.01 is
    1 - 7e-6 (twist, drive forces, K_F; moving and frozen; measured)."""
    plain = _variant(stage, None)
    ref_m, ref_f = moving_loaded_state(plain, WRENCH), loaded_state(plain, WRENCH)

    def gaps(scale: float) -> np.ndarray:
        design = _variant(stage, scale)
        m, f = moving_loaded_state(design, WRENCH), loaded_state(design, WRENCH)
        return np.array(
            [
                np.max(np.abs(m.twist - ref_m.twist)),
                np.max(np.abs(m.actuator_forces - ref_m.actuator_forces)),
                np.max(np.abs(m.stiffness_matrix - ref_m.stiffness_matrix)),
                np.max(np.abs(f.twist - ref_f.twist)),
                np.max(np.abs(f.actuator_forces - ref_f.actuator_forces)),
            ]
        )

    big, small = gaps(0.1), gaps(0.01)
    assert np.all(small > 0)
    np.testing.assert_allclose(np.log10(big / small), 1.0, rtol=0, atol=3e-5)


def test_k_f_is_the_derivative_of_the_equilibria(stage: Design) -> None:
    """Central differences of the moving equilibria at WRENCH +- h (h = 0.1 N, 2 mN·m)
    give K_F^-1 (rotation from R_+ R_-^T): K_F agrees to 1.3e-10 of the diagonal
    (measured; round-off, growing as h shrinks), while the frozen K is 4e-3 off."""
    state = moving_loaded_state(stage, WRENCH)
    compliance = np.zeros((6, 6))
    for j in range(6):
        step = np.zeros(6)
        step[j] = 0.1 if j >= 3 else 0.002
        plus = moving_loaded_state(stage, WRENCH + step).twist
        minus = moving_loaded_state(stage, WRENCH - step).twist
        turn = rotation_log(rotation_exp(plus[:3]) @ rotation_exp(minus[:3]).T)
        compliance[:, j] = np.concatenate([turn, plus[3:] - minus[3:]]) / (2 * step[j])
    fd = np.linalg.inv(compliance)
    assert _relative(fd, state.stiffness_matrix) < 1e-9
    assert _relative(stiffness_at_pose(stage), state.stiffness_matrix) > 1e-3


def test_the_drives_share_of_a_nonlinear_law() -> None:
    """``G + k_h delta(G) = tau`` for q = 1/2 without a locked range (delta = (G/k_a)^2):
    ``G = k_a^2 (sqrt(1 + 4 k_h tau / k_a^2) - 1) / (2 k_h)`` (closed form), odd in tau;
    tau itself without a flexure."""
    from ppm_stiffness.statics.actuator import drive_force

    law = ActuatorModel(locked_stiffness=1e4, k_a=50.0, q=0.5, threshold_displacement=0.0)
    k_h, tau = 300.0, np.array([-40.0, -1.0, 0.0, 0.3, 7.0, 40.0])
    g = drive_force(law, k_h, tau)
    mag = np.abs(tau)
    exact = np.sign(tau) * 50.0**2 * (np.sqrt(1 + 4 * k_h * mag / 50.0**2) - 1) / (2 * k_h)
    np.testing.assert_allclose(g, exact, rtol=1e-13, atol=0)
    np.testing.assert_allclose(g + k_h * actuator_displacement(law, g), tau, rtol=1e-14)
    np.testing.assert_array_equal(drive_force(law, 0.0, tau), tau)


def test_a_nonlinear_drive_in_parallel_balances_each_joint(stage: Design) -> None:
    """The stage with a softening drive law (q = 0.6 above a threshold of 1e-6 rad):
    frozen and moving, each joint's force is the drive's law plus the hinge's
    ``k_h delta`` (checked from the solution's displacements, to 1e-12)."""
    from ppm_stiffness.statics.structures import LegStructures

    data = stage.model_dump()
    for leg in data["legs"]:
        leg["actuator"] = {
            "locked_stiffness": 5000.0,
            "k_a": 60.0,
            "q": 0.6,
            "threshold_displacement": 1e-6,
        }
    design = design_from_dict(data)
    law = design.legs[0].actuator
    assert law is not None
    k_h = design.legs[0].parallel_stiffness()
    frozen = loaded_state(design, WRENCH)
    a = LegStructures(design, np.zeros(6)).actuator
    joint = np.einsum("ij,ij->i", a, frozen.leg_wrenches)
    delta = frozen.actuator_displacements
    assert np.all(np.abs(delta) > 1e-6)  # on the powered branch
    np.testing.assert_allclose(actuator_displacement(law, frozen.actuator_forces), delta)
    np.testing.assert_allclose(joint, frozen.actuator_forces + k_h * delta, rtol=1e-12)
    moving = moving_loaded_state(design, WRENCH)
    np.testing.assert_allclose(
        actuator_displacement(law, moving.actuator_forces),
        moving.actuator_displacements,
        rtol=1e-12,
    )
    np.testing.assert_allclose(moving.leg_wrenches.sum(axis=0), WRENCH, rtol=0, atol=1e-13)


def test_the_hinge_stress_along_a_nonlinear_curve(stage: Design) -> None:
    """Along a deflection curve with the softening drive law, each load's largest hinge
    stress is the one the loaded state's own leg wrenches give (the equilibrium's, not
    rebuilt from the curve's twist), its base hinges bent by ``k_h delta``: to 1e-9
    (the integrated curve, to its integration tolerance: measured 1.1e-10)."""
    from ppm_stiffness.statics.deflection import deflection_path
    from ppm_stiffness.statics.hinge_stress import curve_stresses, hinge_model

    data = stage.model_dump()
    for leg in data["legs"]:
        leg["actuator"] = {
            "locked_stiffness": 5000.0,
            "k_a": 60.0,
            "q": 0.6,
            "threshold_displacement": 1e-6,
        }
    design = design_from_dict(data)
    loads = np.array([0.0, 0.5, 1.0])
    curve = deflection_path(design, WRENCH, loads)
    found = curve_stresses(design, curve, 1.0)
    model = hinge_model(design)
    for k, load in enumerate(loads[1:], start=1):
        state = loaded_state(design, load * WRENCH)
        sigma = model.carried_stresses(state.leg_wrenches, state.actuator_displacements)
        assert found["stress"][k] == pytest.approx(np.max(sigma), rel=1e-9)
        assert found["utilisation"][k] == pytest.approx(np.max(sigma) / 503e6, rel=1e-9)
