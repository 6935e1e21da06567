"""Elastic joint freedoms (a flexure, a torsion spring) in a chain leg (issue 28).

A freedom with a stiffness k is neither passive (eliminated) nor a spring of the
compliance: it enters the leg's bordered solve with its stiffness
(:func:`ppm_stiffness.core.solver.elastic_stiffness`). The tests: a closed form (an R
with a torsion spring and a cantilever), the limits k -> 0 (the passive joint) and
k -> inf (the locked joint) by their slopes, the precision of the bordered form where
adding 1/k to the compliance loses it, an elastic S's one stiffness about every axis,
an elastic U's about its current e1 and e2, a drive in parallel with a flexure, and the
design key's refusals.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from pydantic import ValidationError

from helpers import design_named
from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.core.solver import LegSprings, leg_stiffness
from ppm_stiffness.legs.chain import Joint, Link, leg_springs
from ppm_stiffness.legs.types.chain_leg import JointElement
from ppm_stiffness.model import full_pose, solve_legs

#: A steel rod 20 mm in diameter, 0.2 m long: a stiff link (3EI/L = 2.4e4 N·m/rad).
LENGTH = 0.2
ROD = BeamSection(
    young_modulus=200e9,
    shear_modulus=80e9,
    area=np.pi * 0.01**2,
    torsion_constant=np.pi * 0.01**4 / 2,
    inertia_y=np.pi * 0.01**4 / 4,
    inertia_z=np.pi * 0.01**4 / 4,
)
K_SLIDE = 1e7  # the actuated slider's stiffness [N/m]
X, Y, Z = np.eye(3)


def r_link_chain(k: float) -> list[Joint | Link]:
    """An actuated slider along x, then an R about z with a torsion spring k at
    (-L, 0, 0) and a cantilever along x fixed to the platform at P = 0."""
    c = np.array([-LENGTH, 0.0, 0.0])
    return [
        Joint("P", X, c, None, actuated=True, name="slide"),
        Joint("R", Z, c, None, name="pivot", elastic=np.array([k])),
        Link(c, np.zeros(3), ROD, name="rod"),
    ]


def r_link_closed_form(k: float) -> np.ndarray:
    """K's in-plane block (phi_z, y) of :func:`r_link_chain`: the inverse of the
    compliance [[a + 1/k, b + L/k], [b + L/k, c + L^2/k]] at P (a = L/EI, b =
    L^2/2EI, c = L^3/3EI), written without cancellation: its adjugate times k over
    its determinant times k, k (ac - b^2) + c (the 1/k^2 terms cancel exactly)."""
    ei = ROD.young_modulus * ROD.inertia_z
    a, b, c = LENGTH / ei, LENGTH**2 / (2 * ei), LENGTH**3 / (3 * ei)
    det = k * (a * c - b * b) + c
    adj = np.array([[k * c + LENGTH**2, -(k * b + LENGTH)], [-(k * b + LENGTH), k * a + 1.0]])
    return adj / det


IN_PLANE = np.ix_([2, 4], [2, 4])


def scaled_error(k: np.ndarray, ref: np.ndarray) -> float:
    """max |dK_ij| / sqrt(K_ii K_jj)."""
    d = np.sqrt(np.diag(ref))
    return float(np.max(np.abs(k - ref) / np.outer(d, d)))


@pytest.mark.parametrize("k", [1e-6, 1e-2, 1.0, 1e2, 1e4, 1e6])
def test_r_link_with_a_torsion_spring_equals_its_closed_form(k: float) -> None:
    """Measured residual at most 3.5e-16 from k = 1e-6 to 1e6 N·m/rad; the slider's
    own direction is K_xx = 1/(1/k_slide + L/EA)."""
    kk = leg_stiffness(leg_springs(r_link_chain(k), K_SLIDE))
    assert scaled_error(kk[IN_PLANE], r_link_closed_form(k)) < 1.5e-15
    axial = 1.0 / (1.0 / K_SLIDE + LENGTH / (ROD.young_modulus * ROD.area))
    assert kk[3, 3] == pytest.approx(axial, rel=1e-14)


def test_a_weak_flexure_keeps_full_precision() -> None:
    """k = 1e-6 N·m/rad on a link of 2.4e4: the bordered form is at round-off (2.0e-16
    measured); the same freedom as a spring of compliance 1/k loses about
    (2.4e4 / 1e-6) x 1e-16 (7e-6 measured here)."""
    k = 1e-6
    springs = leg_springs(r_link_chain(k), K_SLIDE)
    assert springs.elastic is not None
    ref = r_link_closed_form(k)
    bordered = leg_stiffness(springs)[IN_PLANE]
    assert scaled_error(bordered, ref) < 1e-15
    m = springs.screws.shape[-1]
    as_compliance = LegSprings(
        screws=np.concatenate([springs.screws, springs.elastic], axis=-1),
        compliance=np.pad(springs.compliance, ((0, 1), (0, 1))) + np.diag([0.0] * m + [1 / k]),
        passive=springs.passive,
    )
    lost = scaled_error(leg_stiffness(as_compliance)[IN_PLANE], ref)
    assert 1e-7 < lost < 1e-4


def _flexure_leg() -> tuple[list[Joint | Link], float]:
    """Leg 1 of examples/6rus_flexure.toml at a pose off home, and its actuator's
    stiffness."""
    design = design_named("6rus_flexure")
    pose = full_pose(design, [0.0008, -0.0005, 0.2130, 0.004, -0.003, 0.005])
    chain = list(design.legs[0].chain(solve_legs(design, pose)[0]))
    return chain, design.legs[0].actuator.locked_stiffness


def _with_elastic(chain: list[Joint | Link], scale: float | None) -> list[Joint | Link]:
    """The chain with its elastic stiffnesses times ``scale`` (None: passive)."""
    out: list[Joint | Link] = []
    for e in chain:
        if isinstance(e, Joint) and e.elastic is not None:
            e = dataclasses.replace(e, elastic=None if scale is None else e.elastic * scale)
        out.append(e)
    return out


def _locked(chain: list[Joint | Link], k_act: float) -> np.ndarray:
    """The leg with its elastic freedoms rigid: neither passive nor springs."""
    springs = leg_springs(chain, k_act)
    return leg_stiffness(dataclasses.replace(springs, elastic=None, elastic_stiffness=None))


def _slope(d_small: float, d_large: float) -> float:
    """log10 of the ratio of two differences two decades apart."""
    return float(np.log10(d_large / d_small))


def test_soft_flexures_tend_to_passive_joints_at_first_order() -> None:
    """K(s k) - K(passive) scales as s: over two decades (s = 1e-6 -> 1e-4) the
    difference grows by 10^2 (log10 of the ratio 2 - 3.8e-6 measured: the next order,
    s k / structure, and round-off; a wrong model would give 0 or 1)."""
    chain, k_act = _flexure_leg()
    passive = leg_stiffness(leg_springs(_with_elastic(chain, None), k_act))
    d = [
        np.max(np.abs(leg_stiffness(leg_springs(_with_elastic(chain, s), k_act)) - passive))
        for s in (1e-6, 1e-4)
    ]
    assert abs(_slope(*d) - 2.0) < 2e-5


def test_stiff_flexures_tend_to_locked_joints_as_one_over_k() -> None:
    """K(s k) - K(locked) scales as 1/s: from s = 1e7 to 1e9 the difference falls by
    10^2 (log10 of the ratio 2 - 6.9e-6 measured)."""
    chain, k_act = _flexure_leg()
    locked = _locked(chain, k_act)
    d = [
        np.max(np.abs(leg_stiffness(leg_springs(_with_elastic(chain, s), k_act)) - locked))
        for s in (1e9, 1e7)
    ]
    assert abs(_slope(*d) - 2.0) < 3e-5


def test_the_example_is_between_its_passive_and_locked_limits() -> None:
    """The flexures add stiffness to the passive leg and remove it from the locked one
    (x^T K x ordered for random x)."""
    chain, k_act = _flexure_leg()
    k = leg_stiffness(leg_springs(chain, k_act))
    passive = leg_stiffness(leg_springs(_with_elastic(chain, None), k_act))
    locked = _locked(chain, k_act)
    assert np.all(np.linalg.eigvalsh(k - passive) > -1e-9 * np.max(np.abs(k)))
    assert np.all(np.linalg.eigvalsh(locked - k) > -1e-9 * np.max(np.abs(locked)))


def _ball_leg(axis: np.ndarray, k_s: float, k_p: float | None = None) -> list[Joint | Link]:
    """An actuated slider along z (a flexure k_p in parallel) and an elastic S of
    stiffness k_s at P, its translations on springs of 1e8 N/m."""
    return [
        Joint(
            "P",
            Z,
            np.zeros(3),
            None,
            actuated=True,
            elastic=None if k_p is None else np.array([k_p]),
        ),
        Joint("S", axis, np.zeros(3), np.full(3, 1e8), elastic=np.full(3, k_s)),
    ]


def test_an_elastic_s_has_one_stiffness_about_every_axis() -> None:
    """K_rr = k I (to 1e-15 relative; the same whatever orients the S's frame) and no
    rotation-translation coupling at its centre."""
    rng = np.random.default_rng(3)
    k_s = 4.7
    for axis in [Z, *rng.normal(size=(3, 3))]:
        axis = axis / np.linalg.norm(axis)
        kk = leg_stiffness(leg_springs(_ball_leg(axis, k_s), 5e6))
        np.testing.assert_allclose(kk[:3, :3], k_s * np.eye(3), rtol=0, atol=1e-15 * k_s)
        np.testing.assert_allclose(kk[:3, 3:], 0.0, atol=1e-9)


def test_a_drive_in_parallel_with_a_flexure_adds_its_stiffness() -> None:
    """A slider of 5e6 N/m with a 2e6 N/m flexure in parallel, in series with the S's
    1e8 N/m: K_zz = 1 / (1/7e6 + 1/1e8)."""
    kk = leg_stiffness(leg_springs(_ball_leg(Z, 4.7, 2e6), 5e6))
    assert kk[5, 5] == pytest.approx(1.0 / (1.0 / 7e6 + 1.0 / 1e8), rel=1e-14)


def test_an_elastic_u_acts_about_its_current_axes() -> None:
    """A U with stiffnesses (k1, k2) about e1, e2 and a torsion spring k_t about
    e1 x e2, at P: K_rr = k1 e1 e1^T + k2 e2 e2^T + k_t e3 e3^T (to 1e-14)."""
    rng = np.random.default_rng(5)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    e1, e2 = q[:, 0], q[:, 1]
    e3 = np.cross(e1, e2)
    k1, k2, k_t = 3.0, 7.0, 50.0
    chain = [
        Joint("P", Z, np.zeros(3), None, actuated=True),
        Joint(
            "U",
            e1,
            np.zeros(3),
            np.array([1e8, 1e8, 1e8, k_t]),
            axis2=e2,
            elastic=np.array([k1, k2]),
        ),
    ]
    kk = leg_stiffness(leg_springs(chain, 5e6))
    expected = k1 * np.outer(e1, e1) + k2 * np.outer(e2, e2) + k_t * np.outer(e3, e3)
    np.testing.assert_allclose(kk[:3, :3], expected, rtol=0, atol=1e-14 * k_t)


def test_the_chain_leg_turns_an_elastic_u_with_its_bodies() -> None:
    """At a pose off home the flexure U of the example carries its elastic stiffness
    about its turned axes (e1 by the crank, e2 by the cross), not its home ones."""
    chain, _ = _flexure_leg()
    u = next(e for e in chain if isinstance(e, Joint) and e.kind == "U")
    design = design_named("6rus_flexure")
    element = design.legs[0].elements[2]
    assert isinstance(element, JointElement) and element.axis is not None
    assert u.elastic is not None and u.axis2 is not None
    np.testing.assert_allclose(u.elastic, [element.elastic] * 2)
    assert np.linalg.norm(np.asarray(u.axis) - np.asarray(element.axis)) > 1e-4
    # still normal (to the 1e-10 of the example's printed home axes: 7.3e-11)
    assert abs(float(np.dot(u.axis, u.axis2))) < 3e-10


def test_the_design_key_is_refused_when_wrong() -> None:
    with pytest.raises(ValidationError, match="spherical joint has one stiffness"):
        JointElement(joint="S", point=(0.0, 0.0, 0.0), elastic=[1.0, 1.0, 1.0])
    with pytest.raises(ValidationError, match="one per freedom .2 for a universal"):
        JointElement(
            joint="U",
            point=(0.0, 0.0, 0.0),
            axis=(1.0, 0.0, 0.0),
            axis2=(0.0, 1.0, 0.0),
            elastic=[1.0, 2.0, 3.0],
        )
    with pytest.raises(ValidationError, match="greater than 0"):
        JointElement(joint="R", point=(0.0, 0.0, 0.0), axis=(1.0, 0.0, 0.0), elastic=0.0)
    with pytest.raises(DesignError, match="positive finite elastic stiffnesses"):
        leg_springs(r_link_chain(-1.0), K_SLIDE)


def test_the_engine_equals_the_definition_with_a_drive_in_parallel() -> None:
    """The batched engine (maps, analyze) and the dense definition agree on the
    ball leg with a flexure in parallel with its drive, at three actuator stiffnesses
    and a rigid drive (measured 0: the same arithmetic on this leg)."""
    from ppm_stiffness.legs import engine

    chain = _ball_leg(Z, 4.7, 2e6)
    reduction = engine.reduce_chain(chain, 1)
    for k_act in (1e5, 5e6, 1e9):
        dense = leg_stiffness(leg_springs(chain, k_act))
        batched = engine.leg_stiffness(reduction, np.array([k_act]))[0]
        np.testing.assert_allclose(batched, dense, rtol=0, atol=2e-15 * np.abs(dense).max())
    rigid = engine.leg_stiffness(reduction, None)[0]
    assert rigid[5, 5] == pytest.approx(1e8, rel=1e-14)  # only the S's spring along z


def test_the_fe_joint_springs_carry_the_elastic_stiffnesses() -> None:
    """The FE frame's joint: an elastic U's rotations about e1, e2 are springs of its
    stiffnesses (0 would be free), an actuated elastic slider's travel the sum."""
    from ppm_stiffness.validation.joints import joint_stiffness

    u = Joint(
        "U", X, np.zeros(3), np.array([1e8, 1e8, 1e8, 50.0]), axis2=Y, elastic=np.array([3.0, 7.0])
    )
    np.testing.assert_array_equal(joint_stiffness(u, 0.0), [3.0, 7.0, 50.0, 1e8, 1e8, 1e8])
    slider = Joint("P", Z, np.zeros(3), None, actuated=True, elastic=np.array([2e6]))
    assert joint_stiffness(slider, 5e6)[3] == 7e6


def test_the_moving_geometry_carries_a_drive_in_parallel() -> None:
    """The actuator column of a drive in parallel with a flexure keeps the flexure's
    stiffness (``ScrewChain.parallel``), its elastic coordinates only the S's."""
    from ppm_stiffness.legs.screw_chain import screw_chain

    chain = screw_chain(_ball_leg(Z, 4.7, 2e6), None, 1)
    assert chain.parallel == 2e6 and chain.actuator == 0
    assert chain.elastic is not None and chain.elastic[chain.actuator] == 0.0


def test_loaded_states_give_the_drives_share() -> None:
    """A flexure of 10 N·m/rad in parallel with leg 1's drive of the 6-RUS: the joint
    carries the drive's force plus the flexure's 10 delta; the linear split's drive
    force is the joint's times k_a / (k_a + 10) (a linear law: the same)."""
    from ppm_stiffness.design import design_from_dict
    from ppm_stiffness.statics.loading import actuator_forces, loaded_state
    from ppm_stiffness.statics.structures import LegStructures

    data = design_named("6rus_flexure").model_dump()
    data["legs"][0]["elements"][0]["elastic"] = 10.0
    design = design_from_dict(data)
    assert design.legs[0].parallel_stiffness() == 10.0
    wrench = np.array([0.0, 0.0, 0.0, 0.0, 0.0, -10.0])
    state = loaded_state(design, wrench)
    a = LegStructures(design, state.pose).actuator
    joint = np.einsum("ij,ij->i", a, state.leg_wrenches)
    shares = state.actuator_forces + np.array([10.0, 0, 0, 0, 0, 0]) * (
        state.actuator_displacements
    )
    np.testing.assert_allclose(joint, shares, rtol=1e-12)
    np.testing.assert_allclose(actuator_forces(design, wrench), state.actuator_forces, rtol=1e-9)


def test_the_mass_model_tends_to_the_passive_joints_at_first_order() -> None:
    """The leg's condensed mass matrix (its rod and crank masses moving with the
    flexures' bordered rates) tends to the passive legs' at first order in the
    flexures' stiffness: log10 of the ratio over s = 1e-5 -> 1e-3 is 2 + 8.9e-6
    (measured; smaller s meets the round-off of the 1e7 springs)."""
    from ppm_stiffness.dynamics.condensation import leg_mass_matrix

    chain, k_act = _flexure_leg()
    passive = leg_mass_matrix(_with_elastic(chain, None), k_act)
    d = [
        np.max(np.abs(leg_mass_matrix(_with_elastic(chain, s), k_act) - passive))
        for s in (1e-5, 1e-3)
    ]
    assert abs(_slope(*d) - 2.0) < 3e-5


def test_elastic_and_passive_freedoms_in_one_leg() -> None:
    """The example's leg with its S passive and its U elastic: the batched engine
    (whose reference point is the passive S) equals the dense definition (measured
    3.7e-16 of the largest entry)."""
    from ppm_stiffness.legs import engine

    chain, k_act = _flexure_leg()
    mixed = [
        dataclasses.replace(e, elastic=None) if isinstance(e, Joint) and e.kind == "S" else e
        for e in chain
    ]
    springs = leg_springs(mixed, k_act)
    assert springs.passive.shape[-1] == 3 and springs.elastic_count == 2
    dense = leg_stiffness(springs)
    batched = engine.leg_stiffness(engine.reduce_chain(mixed, 1), np.array([k_act]))[0]
    np.testing.assert_allclose(batched, dense, rtol=0, atol=2e-15 * np.abs(dense).max())
