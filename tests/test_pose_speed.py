"""The one-pose dynamics path (issue 32 item 1, issue 30 item 5): at one pose the legs
of one structure are evaluated in one batched call (:func:`ppm_stiffness.legs.chain
.stack_chains`), each link's elements at once. It is the batched (map) path's model,
leg by leg, run on other arrays: every shipped example's leg modes, M and f1..f6 at one
pose equal those of the batched path over poses (which keeps one call per leg) to
1e-13. Residuals measured when the tolerances were set are given at each assertion."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from helpers import design_named, example_designs
from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.design import Design
from ppm_stiffness.dynamics.analysis import modal_analysis
from ppm_stiffness.dynamics.batch import first_frequencies
from ppm_stiffness.dynamics.legmodes import (
    design_leg_modes,
    reduced_frequencies,
    reduced_matrices,
    stack_leg_modes,
)
from ppm_stiffness.dynamics.mass import mass_matrix, mass_matrix_at_pose
from ppm_stiffness.legs.chain import Link, stack_chains, structure_groups
from ppm_stiffness.model import (
    actuator_stiffness_vector,
    solve_legs,
    stiffness_at_pose,
    workspace_centre,
)
from ppm_stiffness.poses import full_pose

#: Relative agreement of the one-pose path with the batched one.
AGREEMENT = 1e-13
#: The frequencies from inputs that agree to AGREEMENT (the reduced pair's conditioning).
FREQUENCY_AGREEMENT = 3e-11


def _has_mass(design: Design) -> bool:
    return design.has_mass_model


def _centre(design: Design) -> np.ndarray:
    return full_pose(design, workspace_centre(design))


def _chains(design: Design, pose: np.ndarray) -> list[list[object]]:
    return [leg.chain(lp) for leg, lp in zip(design.legs, solve_legs(design, pose), strict=True)]


@pytest.mark.parametrize("name", example_designs(_has_mass, paper=True))
def test_the_one_pose_leg_modes_and_mass_are_the_batched_ones(name: str) -> None:
    """Each leg's fixed-interface modes (omega^2, and ``C C^T``, which does not depend on
    the basis of a degenerate pair) and M at one pose against the batched path at two
    poses (one call per leg; measured: the Tricept's M 2.8e-16 of its largest entry, the
    legs' reciprocal bases by the scalar and the array code; the 3-PRR's omega^2
    1.1e-14, the other examples' below 1e-14: 1e-14 failed on the 3-PRR)."""
    design = design_named(name)
    p = _centre(design)
    k_act = actuator_stiffness_vector(design, None)
    for count in (2, 8):
        one = design_leg_modes(design, p, k_act, count)
        batched = design_leg_modes(design, np.stack([p, p]), k_act, count)
        assert len(one) == len(batched) == len(design.legs)
        for a, b in zip(one, batched, strict=True):
            assert a.omega2.shape == (1, b.omega2.shape[-1])
            assert a.omega2[0] == pytest.approx(b.omega2[0], rel=AGREEMENT, nan_ok=True)
            ca, cb = a.coupling[0] @ a.coupling[0].T, b.coupling[0] @ b.coupling[0].T
            assert np.max(np.abs(ca - cb)) <= AGREEMENT * max(np.max(np.abs(cb)), 1e-300)
            assert np.max(np.abs(a.condensed_mass[0] - b.condensed_mass[0])) <= (
                AGREEMENT * np.max(np.abs(b.condensed_mass[0]))
            )
    m_one = mass_matrix_at_pose(design, p, k_act)
    m_batched = mass_matrix(design, np.stack([p, p]), k_act)[0]
    assert np.max(np.abs(m_one - m_batched)) <= AGREEMENT * np.max(np.abs(m_batched))


@pytest.mark.parametrize("name", example_designs(_has_mass, paper=True))
def test_the_one_pose_frequencies_are_the_batched_ones(name: str) -> None:
    """f1..f6 of the reduced pair (condensed, 2 and 8 link modes) from the one-pose M
    and leg modes against those from the batched ones, by one solver
    (:func:`~ppm_stiffness.dynamics.legmodes.reduced_frequencies`), and the batched f1
    (:func:`~ppm_stiffness.dynamics.batch.first_frequencies`) against the single-pose
    modal analysis (another generalised eigensolver). Inputs equal to 1e-12 (the test
    above) give frequencies equal to the reduced pair's conditioning: measured at most
    9.8e-12 relative (the 6-RUS with 8 modes; 8e-14 or less condensed), the same
    figures as before the one-pose path stacked the legs."""
    design = design_named(name)
    p = _centre(design)
    k_act = actuator_stiffness_vector(design, None)
    k = stiffness_at_pose(design, p, k_act)
    poses, ks = np.stack([p, p]), np.stack([k, k])
    m_one = mass_matrix_at_pose(design, p, k_act)[None]
    m_batched = mass_matrix(design, poses, k_act)
    for count in (0, 2, 8):
        one = stack_leg_modes(design_leg_modes(design, p, k_act, count))
        batched = stack_leg_modes(design_leg_modes(design, poses, k_act, count))
        f_one = reduced_frequencies(*reduced_matrices(k[None], m_one, *one))[0]
        f_batched = reduced_frequencies(*reduced_matrices(ks, m_batched, *batched))[0]
        assert np.all(np.isfinite(f_one))
        assert f_one == pytest.approx(f_batched, rel=FREQUENCY_AGREEMENT)
        f1, ok = first_frequencies(design, poses, ks, k_act, link_modes=count)
        assert ok.all()
        single = modal_analysis(design, p, link_modes=count).frequencies
        assert f1[0] == pytest.approx(single[0], rel=FREQUENCY_AGREEMENT)


def test_legs_of_one_structure_are_grouped() -> None:
    """The Tricept's three actuated legs are one structure, its passive central leg
    another; the hexapod's six struts one; a leg with another section is its own."""
    tricept = design_named("tricept")
    assert structure_groups(_chains(tricept, _centre(tricept))) == [[0, 1, 2], [3]]
    hexapod = design_named("hexapod_6ups")
    chains = _chains(hexapod, _centre(hexapod))
    assert structure_groups(chains) == [[0, 1, 2, 3, 4, 5]]
    i = next(i for i, e in enumerate(chains[2]) if isinstance(e, Link))
    thin = BeamSection(2.1e11, 8.1e10, 1e-5, 1e-10, 5e-11, 5e-11)
    chains[2] = [replace(e, section=thin) if j == i else e for j, e in enumerate(chains[2])]
    assert structure_groups(chains) == [[0, 1, 3, 4, 5], [2]]
    assert stack_chains(chains) is None


def test_stacked_chains_carry_each_legs_points() -> None:
    """The stacked chain's points and axes are each leg's, along a leading axis."""
    design = design_named("hexapod_6ups")
    chains = _chains(design, _centre(design))
    stacked = stack_chains(chains)
    assert stacked is not None and len(stacked) == len(chains[0])
    for e, element in enumerate(stacked):
        for leg, chain in enumerate(chains):
            mine = chain[e]
            if isinstance(element, Link):
                assert isinstance(mine, Link)
                np.testing.assert_array_equal(element.start[leg], mine.start)
                np.testing.assert_array_equal(element.end[leg], mine.end)
            else:
                np.testing.assert_array_equal(element.point[leg], mine.point)  # type: ignore[union-attr]
                np.testing.assert_array_equal(element.axis[leg], mine.axis)  # type: ignore[union-attr]
