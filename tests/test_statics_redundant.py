"""Loaded statics of a redundant design (4-PPR), against solutions that do not use the
equilibrium solver or the closed-form actuator displacement delta(G).

References:
- the tangent model integrated along the load path (``deflect --method integrate``):
  dt/dL = K(L)^-1 w_hat with each actuator at its tangent stiffness (eq. 21) under the
  force it carries, dG_i/dL = a_i . K_i K^-1 w_hat;
- each leg's own nonlinear equilibrium solved by damped Newton on its 22 springs
  (tests/test_deflection.py), summed over the legs at the equilibrium twist.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from paper import PAPER_WRENCH
from ppm_stiffness.design import default_design, load_design
from ppm_stiffness.model import leg_springs_at_pose
from ppm_stiffness.statics.actuator import actuator_displacement
from ppm_stiffness.statics.deflection import deflection_path
from ppm_stiffness.statics.equilibrium import equilibrium
from ppm_stiffness.statics.loading import actuator_forces, loaded_state
from test_deflection import _equilibrium_wrench

DESIGN = load_design(Path(__file__).resolve().parents[1] / "examples" / "redundant_4ppr.toml")
POSE = np.array([0.015, -0.015, math.radians(-12.0)])
#: A large asymmetric wrench (m_x, m_y, m_z [N·m], f_x, f_y, f_z [N]): every actuator
#: but one leaves its locked range.
WRENCH = np.array([0.05, -0.03, 0.4, 15.0, -8.0, 10.0])


def test_equilibrium_equals_the_integrated_tangent_model() -> None:
    eq = equilibrium(DESIGN, WRENCH, POSE)
    assert eq.iterations > 0  # the load split really depends on the actuators
    path = deflection_path(DESIGN, WRENCH, np.linspace(0.0, 1.0, 5), POSE, method="integrate")
    g_int, t_int = path.actuator_forces[-1], path.twists[-1]
    # measured: 3.0e-12 (forces) and 8.7e-13 (twist), relative; the issue asks 1e-6, the
    # bound sits a few hundred times above the measured residual
    assert np.max(np.abs(g_int - eq.actuator_forces)) <= 1e-9 * np.max(np.abs(eq.actuator_forces))
    assert np.max(np.abs(t_int - eq.twist)) <= 1e-9 * np.max(np.abs(eq.twist))
    # along the whole path too, against the equilibrium at each load
    for load, g, t in zip(path.loads, path.actuator_forces, path.twists, strict=True):
        e = equilibrium(DESIGN, load * WRENCH, POSE)
        assert np.max(np.abs(g - e.actuator_forces)) <= 1e-9 * max(np.max(np.abs(g)), 1e-9)
        assert np.max(np.abs(t - e.twist)) <= 1e-9 * max(np.max(np.abs(t)), 1e-15)


def test_equilibrium_twist_balances_the_independent_leg_solvers() -> None:
    """At the equilibrium twist each leg, solved on its own with the nonlinear law,
    carries a wrench; they sum to the applied wrench."""
    eq = equilibrium(DESIGN, WRENCH, POSE)
    legs = leg_springs_at_pose(DESIGN, POSE)
    total = _equilibrium_wrench(legs, eq.twist, DESIGN)
    np.testing.assert_allclose(total, WRENCH, rtol=0, atol=1e-8 * np.max(np.abs(WRENCH)))
    np.testing.assert_allclose(eq.leg_wrenches.sum(axis=0), WRENCH, atol=1e-12 * 15)


def test_secant_stiffness_shares_the_load() -> None:
    eq = equilibrium(DESIGN, WRENCH, POSE)
    delta = np.array(
        [
            actuator_displacement(leg.actuator, g)
            for leg, g in zip(DESIGN.legs, eq.actuator_forces, strict=True)
        ]
    )
    np.testing.assert_allclose(eq.actuator_displacements, delta, rtol=1e-14)
    np.testing.assert_allclose(eq.secant_stiffness * delta, eq.actuator_forces, rtol=1e-12)
    # the locked linear split (the old loaded state) is measurably wrong here
    linear = actuator_forces(DESIGN, WRENCH, POSE)
    assert np.max(np.abs(linear - eq.actuator_forces)) > 1.0  # N (measured 2.7 N)


@pytest.mark.parametrize("design", [default_design()], ids=["paper_3ppr"])
def test_three_leg_forces_are_determinate(design) -> None:  # type: ignore[no-untyped-def]
    """For the 3-PPR the actuator forces do not depend on the stiffnesses: no Newton
    iteration, and the same forces as the linear split (the paper's 2.3, 7.3, 5 N)."""
    eq = equilibrium(design, PAPER_WRENCH, np.zeros(3))
    assert eq.iterations == 0
    np.testing.assert_allclose(
        eq.actuator_forces, actuator_forces(design, PAPER_WRENCH), rtol=1e-12
    )
    state = loaded_state(design, PAPER_WRENCH)
    np.testing.assert_allclose(state.actuator_forces, eq.actuator_forces, rtol=1e-14)


def test_integration_follows_a_force_back_below_its_threshold() -> None:
    """Regression (review): an actuator whose force rises through its threshold and
    falls back below it must return to its locked branch. Legs 1, 2, 4 on the paper's
    law with a tiny locked range; leg 3 nearly linear (q = 0.999, k_a 5000 N/m^q) with a
    0.3 N threshold:
    along this load its force peaks at 0.33 N and ends at 0.076 N. Before the fix the
    integration kept leg 3 powered (phi_z 0.8 % off the equilibrium)."""
    from ppm_stiffness.legs.parts import ActuatorModel

    paper = ActuatorModel(
        locked_stiffness=111080.0, k_a=44.75, q=0.225, threshold_displacement=1e-9
    )
    # nearly linear: q = 1 would make locked_stiffness and k_a one stiffness
    linear = ActuatorModel(
        locked_stiffness=111080.0,
        k_a=5000.0,
        q=0.999,
        threshold_displacement=(0.3 / 5000.0) ** (1 / 0.999),
    )
    legs = [leg.model_copy(update={"actuator": paper}) for leg in DESIGN.legs]
    legs[2] = legs[2].model_copy(update={"actuator": linear})
    design = DESIGN.model_copy(update={"legs": legs})
    unit = np.array([0.0, 0.0, 0.07244926, -0.93553117, -0.34573476, 0.0])
    loads = np.linspace(0.05, 12.0, 60)
    pose = np.zeros(3)
    integrated = deflection_path(design, unit, loads, pose, method="integrate")
    exact = deflection_path(design, unit, loads, pose, method="closed-form")
    g3 = np.abs(exact.actuator_forces[:, 2])
    assert g3.max() > 0.3 > g3[-1]  # up through the threshold and back down
    # measured: 2.1e-13 rad on phi_z = 0.041 rad, 3.6e-10 N on forces of ~11 N
    scale = np.max(np.abs(exact.twists), axis=0)
    assert np.all(np.abs(integrated.twists - exact.twists) <= 1e-9 * scale + 1e-18)
    assert np.max(np.abs(integrated.actuator_forces - exact.actuator_forces)) <= 1e-8
