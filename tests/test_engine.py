"""The batched engine (legs/engine.py) against the definition (chain springs and the
leg stiffness of core.solver), exact rational arithmetic and the two-force leg's closed
form, on planar and spatial legs; its chunks, its single-pose path, its basis and its
singular poses."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from helpers import design_named, example_designs, is_planar
from ppm_stiffness.core import pose as P
from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.core.conventions import BALANCE
from ppm_stiffness.core.solver import LegSprings, leg_stiffness
from ppm_stiffness.legs import _forms, engine
from ppm_stiffness.legs.chain import Joint, Link, leg_springs
from ppm_stiffness.legs.completion import complete_poses
from spatial_legs import (
    GUIDE,
    LINEAR_ACTUATOR,
    STEEL_ROD,
    STEEL_TUBE,
    hexapod_legs,
    prs_legs,
    rps_legs,
)
from test_spatial_legs import two_force_stiffness

S = BALANCE  # length balancing, L = 0.1 m
#: The engine and the definition differ by rounding: at most 3.8e-14 (3-RPR, whose
#: legs are the worst conditioned), 3.1e-14 on the spatial legs (measured).
TOLERANCE = 2e-13


def rel(a: np.ndarray, b: np.ndarray) -> float:
    """Largest length-balanced difference relative to the largest entry of b."""
    return float(np.max(np.abs((a - b) * S[:, None] * S)) / np.max(np.abs(b * S[:, None] * S)))


def worst_difference(legs, poses: np.ndarray) -> float:  # type: ignore[no-untyped-def]
    n = poses.shape[0]
    worst = 0.0
    k_act = np.linspace(0.5, 2.0, n)  # a different actuator stiffness at every pose
    for leg in legs:
        lp = leg.solve(poses)
        fast = engine.leg_stiffness(engine.reduce_chain(leg.chain(lp), n), k_act * 1e7)
        for i in range(0, n, max(1, n // 7)):
            one = leg.solve(poses[i])
            ref = leg_stiffness(leg_springs(leg.chain(one), k_act[i] * 1e7))
            worst = max(worst, rel(fast[i], ref))
    return worst


def hexapod_poses(rng: np.random.Generator, n: int) -> np.ndarray:
    return np.array([0, 0, 0.25, 0, 0, 0]) + np.concatenate(
        [rng.uniform(-0.02, 0.02, (n, 3)), rng.uniform(-0.1, 0.1, (n, 3))], axis=1
    )


def tripod_poses(legs, rng: np.random.Generator, n: int) -> np.ndarray:  # type: ignore[no-untyped-def]
    start = np.zeros((n, 6))
    start[:, 2] = 0.2 + rng.uniform(-0.02, 0.02, n)
    start[:, 3:5] = rng.uniform(-0.3, 0.3, (n, 2))
    q, ok = complete_poses(legs, [0, 1, 5], start)
    assert ok.all()
    return q


def planar_poses(name: str, rng: np.random.Generator, n: int) -> np.ndarray:
    ws = design_named(name).workspace
    planar = np.stack(
        [
            ws.centre_x + rng.uniform(-0.005, 0.005, n),
            ws.centre_y + rng.uniform(-0.005, 0.005, n),
            rng.uniform(-0.05, 0.05, n),
        ],
        axis=1,
    )
    return P.planar_pose(planar)


def test_engine_equals_the_definition_on_spatial_legs() -> None:
    rng = np.random.default_rng(2)
    assert worst_difference(hexapod_legs(), hexapod_poses(rng, 40)) < TOLERANCE
    for legs in (prs_legs(), rps_legs()):
        assert worst_difference(legs, tripod_poses(legs, rng, 40)) < TOLERANCE


def test_engine_equals_the_definition_on_planar_legs() -> None:
    rng = np.random.default_rng(4)
    for name in example_designs(is_planar, paper=True):
        legs = design_named(name).legs
        assert worst_difference(legs, planar_poses(name, rng, 20)) < TOLERANCE


# -- an independent computation: the definition in exact rational arithmetic ---------
Matrix = list[list[Fraction]]


def _exact(a: np.ndarray) -> Matrix:
    return [[Fraction(float(x)) for x in row] for row in np.atleast_2d(a)]


def _mul(a: Matrix, b: Matrix) -> Matrix:
    return [
        [
            sum((x * y for x, y in zip(row, col, strict=True)), Fraction(0))
            for col in zip(*b, strict=True)
        ]
        for row in a
    ]


def _transpose(a: Matrix) -> Matrix:
    return [list(row) for row in zip(*a, strict=True)]


def _reduce_rows(a: Matrix, columns: int) -> tuple[Matrix, list[int]]:
    """Reduced row echelon form (exact) and its pivot columns."""
    a = [row[:] for row in a]
    pivots: list[int] = []
    for c in range(columns):
        r = len(pivots)
        found = next((i for i in range(r, len(a)) if a[i][c] != 0), None)
        if found is None:
            continue
        a[r], a[found] = a[found], a[r]
        a[r] = [x / a[r][c] for x in a[r]]
        for i in range(len(a)):
            if i != r and a[i][c] != 0:
                a[i] = [x - a[i][c] * y for x, y in zip(a[i], a[r], strict=True)]
        pivots.append(c)
    return a, pivots


def exact_stiffness(springs: LegSprings) -> np.ndarray:
    """K = W (W^T J C J^T W)^-1 W^T of the definition's springs (float64 numbers taken
    exactly), W a basis of the null space of the passive twists^T, all in rationals."""
    passive = _transpose(_exact(springs.passive))
    reduced, pivots = _reduce_rows(passive, 6)
    free = [c for c in range(6) if c not in pivots]
    w_cols = []
    for f in free:
        v = [Fraction(0)] * 6
        v[f] = Fraction(1)
        for row, c in zip(reduced, pivots, strict=False):  # rows past the pivots are 0
            v[c] = -row[f]
        w_cols.append(v)
    w = _transpose(w_cols)
    g = _mul(_transpose(_exact(springs.screws)), w)
    m = _mul(_mul(_transpose(g), _exact(springs.compliance)), g)
    r = len(m)
    inverse, _ = _reduce_rows(
        [row + [Fraction(int(i == j)) for j in range(r)] for i, row in enumerate(m)], r
    )
    k = _mul(_mul(w, [row[r:] for row in inverse]), _transpose(w))
    return np.array([[float(x) for x in row] for row in k])


def test_engine_is_the_exact_stiffness_to_rounding() -> None:
    """At a few poses of the spatial legs, the engine is within 1e-13 (measured: 2.5e-14,
    the 3-PRS; the definition itself 4.8e-15) of K computed exactly from the
    definition's springs."""
    rng = np.random.default_rng(2)
    k_act = LINEAR_ACTUATOR["locked_stiffness"]
    for legs, poses in (
        (hexapod_legs(), hexapod_poses(rng, 3)),
        (prs_legs(), tripod_poses(prs_legs(), rng, 3)),
        (rps_legs(), tripod_poses(rps_legs(), rng, 3)),
    ):
        for leg in legs:
            fast = engine.leg_stiffness(engine.reduce_chain(leg.chain(leg.solve(poses)), 3), k_act)
            for i in range(3):
                springs = leg_springs(leg.chain(leg.solve(poses[i])), k_act)
                assert rel(fast[i], exact_stiffness(springs)) < 1e-13


@pytest.mark.parametrize("soft", [False, True])
def test_two_force_leg_is_its_closed_form(soft: bool) -> None:
    """The U-P-S leg: K = k w w^T (tests/test_spatial_legs.py), to 5e-15 (measured
    9.4e-16), also with bending 1e6 times softer than its axial compliance (where
    summing c |f|^2 - c (e . f)^2 would lose digits)."""
    overrides = (
        {
            "cylinder": {**STEEL_TUBE, "inertia_y": 1e-14, "inertia_z": 1e-14},
            "guide": {**GUIDE, "lateral": 2e1, "vertical": 2e1},
        }
        if soft
        else {}
    )
    rng = np.random.default_rng(11)
    poses = hexapod_poses(rng, 20)
    k_act = LINEAR_ACTUATOR["locked_stiffness"]
    for leg in hexapod_legs(**overrides):
        fast = engine.leg_stiffness(engine.reduce_chain(leg.chain(leg.solve(poses)), 20), k_act)
        for i in range(20):
            assert rel(fast[i], two_force_stiffness(leg, poses[i], k_act)) < 5e-15


def test_equal_springs_and_round_tubes_take_the_frame_identities() -> None:
    """Isotropic joints (equal compliances on all or two axes of a frame) and round tubes
    (the engine's shortcuts, module doc of legs/_forms.py) against the definition, and
    against the same chains evaluated axis by axis."""
    legs = hexapod_legs(
        base_joint={"radial": 5e7, "axial": 5e7, "torsion": 300.0},
        platform_joint={"axial": 4e7, "radial": 4e7},
        guide={**GUIDE, "lateral": 2e7, "vertical": 2e7},
        rod={**STEEL_ROD, "inertia_z": 3e-9},  # not round: its couplings axis by axis
    )
    rng = np.random.default_rng(5)
    poses = hexapod_poses(rng, 10)
    assert worst_difference(legs, poses) < TOLERANCE
    for leg in legs:
        chain = leg.chain(leg.solve(poses))
        fast = engine.leg_stiffness(engine.reduce_chain(chain, 10), 5e7)
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(_forms, "_identity", lambda keys: None)
            by_axis = engine.leg_stiffness(engine.reduce_chain(chain, 10), 5e7)
        for i in range(10):
            assert rel(fast[i], by_axis[i]) < 1e-14


def test_a_universal_joint_with_skewed_axes_is_taken_axis_by_axis() -> None:
    """A U joint's axes are given, not built: with e1 . e2 != 0 its frame is not
    orthonormal and |f|^2 is not the sum of its squared components; the engine still
    equals the definition."""
    leg = hexapod_legs(base_joint={"radial": 5e7, "axial": 5e7, "torsion": 300.0})[0]
    pose = hexapod_poses(np.random.default_rng(6), 1)
    chain = list(leg.chain(leg.solve(pose)))
    u = chain[0]
    assert isinstance(u, Joint) and u.axis2 is not None
    skewed = u.axis2 + 0.3 * u.axis
    chain[0] = Joint("U", u.axis, u.point, u.springs, axis2=skewed / np.linalg.norm(skewed))
    fast = engine.leg_stiffness(engine.reduce_chain(chain, 1), 5e7)
    assert rel(fast[0], leg_stiffness(leg_springs(chain, 5e7))[0]) < TOLERANCE


def test_a_cantilever_whose_entries_are_not_monomials_is_taken_as_given() -> None:
    rng = np.random.default_rng(7)
    legs = prs_legs()
    poses = tripod_poses(legs, rng, 6)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_forms, "cantilever_terms", lambda section: None)
        assert worst_difference(legs, poses) < TOLERANCE


def test_chunks_and_single_poses_give_the_same_bits() -> None:
    """Every pose is evaluated on its own: chunks of 7 poses, or one pose at a time (the
    float path), give K bit for bit as one chunk does."""
    rng = np.random.default_rng(8)
    cases = [
        (hexapod_legs()[:2], hexapod_poses(rng, 30)),
        (prs_legs()[:1], tripod_poses(prs_legs(), rng, 30)),
        (design_named("3rpr").legs[:1], planar_poses("3rpr", rng, 30)),
    ]
    for legs, poses in cases:
        for leg in legs:
            chain = leg.chain(leg.solve(poses))
            whole = engine.leg_stiffness(engine.reduce_chain(chain, 30), 5e7)
            with pytest.MonkeyPatch.context() as mp:
                mp.setattr(engine, "CHUNK", 7)
                chunked = engine.leg_stiffness(engine.reduce_chain(chain, 30), 5e7)
            single = [
                engine.leg_stiffness(engine.reduce_chain(leg.chain(leg.solve(q[None])), 1), 5e7)
                for q in poses
            ]
            np.testing.assert_array_equal(chunked, whole)
            np.testing.assert_array_equal(np.concatenate(single), whole)


def test_stiffness_is_exactly_symmetric() -> None:
    rng = np.random.default_rng(9)
    for legs, poses in (
        (hexapod_legs()[:1], hexapod_poses(rng, 8)),
        (rps_legs()[:1], tripod_poses(rps_legs(), rng, 8)),
        (design_named("3rrr").legs[:1], planar_poses("3rrr", rng, 8)),
    ):
        leg = legs[0]
        k = engine.leg_stiffness(engine.reduce_chain(leg.chain(leg.solve(poses)), 8), 3e7)
        np.testing.assert_array_equal(k, np.swapaxes(k, 1, 2))


def test_basis_is_orthonormal_and_reciprocal_to_the_passive_twists() -> None:
    """W of reduce_chain (spatial legs: taken at the reference point, then at P) and of
    reciprocal_basis (random twists): orthonormal in length-balanced units, and doing
    no work on the passive twists, to 1e-15 (measured 6.7e-16)."""
    rng = np.random.default_rng(10)
    bases = []
    for legs, poses in (
        (hexapod_legs(), hexapod_poses(rng, 10)),
        (prs_legs(), tripod_poses(prs_legs(), rng, 10)),
        (design_named("3prr").legs, planar_poses("3prr", rng, 10)),
    ):
        for leg in legs:
            chain = leg.chain(leg.solve(poses))
            passive = leg_springs(chain, 1.0).passive
            bases.append((engine.reduce_chain(chain, 10).basis, passive))
    for p in range(6):
        twists = rng.normal(size=(10, 6, p))
        bases.append((engine.reciprocal_basis(list(np.moveaxis(twists, 2, 0)), 10), twists))
    for w, passive in bases:
        balanced = w * S[None, :, None]
        r = w.shape[-1]
        gram = np.einsum("nir,nis->nrs", balanced, balanced)
        assert np.max(np.abs(gram - np.eye(r))) < 1e-15
        work = np.einsum("nir,nip->nrp", w, passive)
        assert np.max(np.abs(work), initial=0.0) < 1e-15 * np.max(np.abs(passive), initial=1.0)


def test_dependent_passive_joints_give_nan_at_those_poses_only() -> None:
    """Two passive revolutes on one axis at the first pose (dependent), apart at the
    second: NaN there, the definition's K at the other."""
    z = np.array([0.0, 0.0, 1.0])
    a = np.array([[-0.3, 0.0, 0.0], [-0.3, 0.0, 0.0]])
    b = np.array([[-0.1, 0.0, 0.0], [-0.1, 0.0, 0.0]])
    d = np.array([[-0.1, 0.0, 0.0], [-0.05, 0.01, 0.0]])
    springs = np.array([4e3, 4e3, 1e7, 2e7, 2e7])
    chain = [
        Joint("P", np.array([1.0, 0.0, 0.0]), a, np.array([1e3, 2e3, 2e3, 1e7, 2e7]), True),
        Link(a, b, BeamSection(**STEEL_TUBE)),
        Joint("R", z, b, springs),
        Joint("R", z, d, springs),
    ]
    reduction = engine.reduce_chain(chain, 2)
    k = engine.leg_stiffness(reduction, 5e7)
    assert np.isnan(reduction.basis[0]).all() and np.isnan(k[0]).all()
    assert np.isfinite(k[1]).all()
    one = [
        Joint(e.kind, e.axis, e.point[1], e.springs, e.actuated)
        if isinstance(e, Joint)
        else Link(e.start[1], e.end[1], e.section)
        for e in chain
    ]
    assert rel(k[1], leg_stiffness(leg_springs(one, 5e7))) < TOLERANCE


def test_a_compliance_without_cholesky_factor_is_inverted_or_nan() -> None:
    """M = A + v v^T / k not positive (a negative actuator stiffness, non-physical):
    K = W M^-1 W^T as the definition computes it; M singular or not finite: NaN."""
    rng = np.random.default_rng(12)
    q, _ = np.linalg.qr(rng.normal(size=(3, 6, 2)))
    basis = q * S[None, :, None] ** -1  # orthonormal in balanced units
    a = np.array([[[2e-8, 1e-9], [1e-9, 3e-8]], [[0.0, 0.0], [0.0, 0.0]], [[np.inf, 0], [0, 1]]])
    v = rng.normal(size=(3, 2))
    reduction = engine.LegReduction(basis, a, v, np.zeros((3, 6)))
    k_act = np.array([-1e7, 1e7, 1e7])
    k = engine.leg_stiffness(reduction, k_act)
    m0 = a[0] + np.outer(v[0], v[0]) / k_act[0]
    expected = basis[0] @ np.linalg.inv(m0) @ basis[0].T
    assert np.max(np.abs(k[0] - expected)) < 1e-14 * np.max(np.abs(expected))
    assert np.isnan(k[2]).all()
    assert np.isnan(engine.leg_stiffness(reduction, None)[1]).all()
