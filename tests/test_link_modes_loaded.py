"""Link modes under a wrench (issue 30 item 4, docs/dynamics.md "Under a wrench"): the
loaded tangent K_F is the legs' sum with each actuator's tangent stiffness, and the
legs' FE built with those tangent stiffnesses condenses to it, so the fixed-interface
modes of ``modes --wrench`` belong to the loaded state."""

from __future__ import annotations

import numpy as np
import pytest

from ppm_stiffness.design import Design
from ppm_stiffness.dynamics.analysis import modal_analysis
from ppm_stiffness.dynamics.legmodes import (
    design_leg_modes,
    reduced_frequencies,
    reduced_matrices,
    stack_leg_modes,
)
from ppm_stiffness.dynamics.mass import mass_matrix_at_pose
from ppm_stiffness.model import actuator_stiffness_vector
from ppm_stiffness.poses import home_pose
from ppm_stiffness.statics.loading import loaded_state
from test_dynamics import _with_masses

#: The paper's 3-PPR with masses; its actuator law softens under this wrench.
WRENCH = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])


def _design() -> Design:
    return _with_masses(
        "paper",
        platform={"mass": 0.23, "shape": "cylinder", "radius": 0.045, "height": 0.01},
        masses={"proximal": {"mass": 0.1}, "distal": {"mass": 0.06}},
        actuator={"carriage_mass": 0.2},
    )


def test_the_legs_fe_with_the_tangent_actuators_condenses_to_the_loaded_k() -> None:
    """Each leg's FE (the relative coordinates of its chain, 8 elements per link) built
    with the tangent actuator stiffnesses sums, condensed to P, to the loaded state's
    K_F (the bordered inverses of :mod:`ppm_stiffness.statics.equilibrium`, an
    independent formula): residual 1.1e-15; with the locked stiffnesses it misses K_F
    by 0.26 (two tangent stiffnesses are 0.046 and 0.17 of the locked here)."""
    design = _design()
    home = home_pose(design)
    state = loaded_state(design, WRENCH, home)
    locked = actuator_stiffness_vector(design, None)
    ratio = state.actuator_stiffness / locked
    assert np.min(ratio) < 0.2
    scale = np.max(np.abs(state.stiffness_matrix))
    for k_act, tolerance in ((state.actuator_stiffness, 5e-15), (locked, None)):
        legs = design_leg_modes(design, home, k_act, 8)
        total = sum(leg.condensed_stiffness[0] for leg in legs)
        gap = np.max(np.abs(total - state.stiffness_matrix)) / scale
        if tolerance is None:
            assert gap > 1e-2
        else:
            assert gap <= tolerance


def test_modes_under_a_wrench_take_the_legs_modes_of_the_loaded_state() -> None:
    """``modal_analysis(..., wrench)`` with link modes: the Craig-Bampton problem of K_F,
    M and the legs' modes, all with the tangent actuator stiffnesses (the same
    matrices, solved by another eigensolver: residual 9e-12); its f1 is below the
    loaded condensed f1 (Rayleigh-Ritz) and below the locked f1 with link modes (the
    actuators soften)."""
    design = _design()
    home = home_pose(design)
    state = loaded_state(design, WRENCH, home)
    k_t = state.actuator_stiffness
    legs = design_leg_modes(design, home, k_t, 8)
    m = mass_matrix_at_pose(design, None, k_t)
    expected = reduced_frequencies(
        *reduced_matrices(state.stiffness_matrix, m, *stack_leg_modes(legs))
    )[0]
    loaded = modal_analysis(design, wrench=WRENCH, link_modes=8)
    assert loaded.frequencies == pytest.approx(expected, rel=1e-10)
    condensed = modal_analysis(design, wrench=WRENCH, link_modes=0).frequencies
    assert loaded.frequencies[0] < condensed[0]
    assert loaded.frequencies[0] < modal_analysis(design, link_modes=8).frequencies[0]
