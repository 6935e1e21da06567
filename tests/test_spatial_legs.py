"""The spatial leg types (U-P-S, P-R-S, R-P-S) and the U and S joints, leg by leg:
their chains against their inverse kinematics, the two-force leg's closed form, the
constraints and the parasitic motion of symmetric tripods (closed form)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pytest

from ppm_stiffness.core import pose as P
from ppm_stiffness.core.solver import leg_stiffness
from ppm_stiffness.legs.base import LegModel
from ppm_stiffness.legs.chain import (
    CONSTRAINED,
    FREEDOMS,
    Joint,
    constrained_screws,
    freedom_screws,
    leg_springs,
)
from ppm_stiffness.legs.completion import complete_poses, residuals
from spatial_legs import (
    LINEAR_ACTUATOR,
    SPHERICAL,
    STEEL_ROD,
    STEEL_TUBE,
    UNIVERSAL,
    hexapod_legs,
    prs_legs,
    rps_legs,
    tripod_angles,
)

BALANCE = np.diag([10.0, 10.0, 10.0, 1.0, 1.0, 1.0])  # conventions.LENGTH_SCALE = 0.1 m
HOME_HEIGHT = 0.25
TRIPOD_DEPENDENT = [0, 1, 5]  # x, y, rz


def rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(
        np.max(np.abs(BALANCE @ (a - b) @ BALANCE)) / np.max(np.abs(BALANCE @ b @ BALANCE))
    )


@pytest.mark.parametrize("kind", ["U", "S"])
def test_freedoms_and_constrained_directions_span_all_twists(kind: str) -> None:
    rng = np.random.default_rng(1)
    e1 = rng.normal(size=3)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(e1, rng.normal(size=3))
    e2 /= np.linalg.norm(e2)
    joint = Joint(kind, e1, rng.normal(size=3), axis2=e2 if kind == "U" else None)
    free, fixed = freedom_screws(joint), constrained_screws(joint)
    assert free.shape == (6, FREEDOMS[kind]) and fixed.shape == (6, CONSTRAINED[kind])
    assert np.linalg.matrix_rank(np.hstack([free, fixed]), tol=1e-12) == 6


def hexapod_pose(rng: np.random.Generator) -> np.ndarray:
    return np.array([0, 0, HOME_HEIGHT, 0, 0, 0]) + np.concatenate(
        [rng.uniform(-0.02, 0.02, 3), rng.uniform(-0.1, 0.1, 3)]
    )


def tripod_pose(legs: Sequence[LegModel], rng: np.random.Generator) -> np.ndarray:
    start = np.array([0, 0, HOME_HEIGHT + rng.uniform(-0.02, 0.02), *rng.uniform(-0.3, 0.3, 2), 0])
    q, ok = complete_poses(legs, TRIPOD_DEPENDENT, start)
    assert ok
    return q


def feasible_twists(
    legs: Sequence[LegModel], pose: np.ndarray, rng: np.random.Generator
) -> np.ndarray:
    """Random twists (6, k) that satisfy every leg's constraint to first order."""
    _, w = residuals(legs, pose)
    t = rng.normal(size=(6, 4)) * np.array([1, 1, 1, 0.1, 0.1, 0.1])[:, None]
    if w.shape[-1]:
        q, _ = np.linalg.qr(w)
        t = t - q @ (q.T @ t)
    return t


@pytest.mark.parametrize("family", ["UPS", "PRS", "RPS"])
def test_chain_moves_as_the_inverse_kinematics_says(family: str) -> None:
    """A feasible platform twist is a combination of the chain's joint freedoms, and the
    actuated joint's rate in it is the derivative of the IK's actuator coordinate
    (central differences along the twist, with the pose update of the conventions)."""
    rng = np.random.default_rng(7)
    legs: list[LegModel] = {"UPS": hexapod_legs, "PRS": prs_legs, "RPS": rps_legs}[family]()
    for _ in range(3):
        pose = hexapod_pose(rng) if family == "UPS" else tripod_pose(legs, rng)
        for leg in legs:
            chain = leg.chain(leg.solve(pose))
            joints = [e for e in chain if isinstance(e, Joint)]
            cols = [freedom_screws(j) for j in joints]
            actuated = next(i for i, j in enumerate(joints) if j.actuated)
            first = sum(c.shape[1] for c in cols[:actuated])
            basis = np.hstack(cols)
            assert np.linalg.matrix_rank(basis, tol=1e-10) == basis.shape[1]
            for t in feasible_twists(legs, pose, rng).T:
                rates, *_ = np.linalg.lstsq(basis, t, rcond=None)
                assert np.max(np.abs(basis @ rates - t)) < 1e-13
                h = 1e-6
                name = leg.ACTUATED_COORDINATE
                plus = leg.solve(P.displaced_pose(pose, h * t)).coordinates[name]
                minus = leg.solve(P.displaced_pose(pose, -h * t)).coordinates[name]
                fd = float(plus - minus) / (2 * h)
                assert abs(rates[first] - fd) <= 1e-7 * max(1.0, abs(fd))


@pytest.mark.parametrize("family", ["PRS", "RPS"])
def test_constraint_wrench_is_the_derivative_of_the_residual(family: str) -> None:
    rng = np.random.default_rng(3)
    legs: list[LegModel] = {"PRS": prs_legs, "RPS": rps_legs}[family]()
    pose = tripod_pose(legs, rng)
    for leg in legs:
        _, w = leg.constraint(pose)
        for t in rng.normal(size=(4, 6)):
            h = 1e-6
            fd = (
                leg.constraint(P.displaced_pose(pose, h * t))[0]
                - leg.constraint(P.displaced_pose(pose, -h * t))[0]
            ) / (2 * h)
            np.testing.assert_allclose(fd, w[:, 0] @ t, atol=1e-9)


def two_force_stiffness(leg: LegModel, pose: np.ndarray, k_act: float) -> np.ndarray:
    """Sum k w w^T of the issue: w = ((B - P) x n; n), 1/k the axial compliances."""
    lp = leg.solve(pose)
    a, b = lp.points["A"], lp.points["B"]
    length = float(np.linalg.norm(b - a))
    n = (b - a) / length
    w = np.concatenate([np.cross(b, n), n])
    lc = leg.cylinder_length  # type: ignore[attr-defined]
    cyl, rod = leg.cylinder, leg.rod  # type: ignore[attr-defined]
    c = (
        1 / k_act
        + lc / (cyl.young_modulus * cyl.area)
        + (length - lc) / (rod.young_modulus * rod.area)
        + 1 / UNIVERSAL["axial"]
        + 1 / SPHERICAL["axial"]
    )
    return np.outer(w, w) / c


@pytest.mark.parametrize(
    "overrides",
    [
        {},
        # bending and torsion of the links, and the P joint's lateral and rotational
        # springs, changed by 1e6: a two-force leg does not feel them
        {
            "cylinder": {
                **STEEL_TUBE,
                "inertia_y": 1e-14,
                "inertia_z": 1e-14,
                "torsion_constant": 1e-14,
            },
            "rod": {**STEEL_ROD, "inertia_y": 2e-3, "inertia_z": 2e-3, "torsion_constant": 4e-3},
            "guide": {"roll": 1e-3, "pitch": 2e9, "yaw": 2e-3, "lateral": 1e13, "vertical": 2e1},
        },
    ],
)
def test_two_force_leg_stiffness_is_its_closed_form(overrides: dict[str, object]) -> None:
    rng = np.random.default_rng(11)
    legs = hexapod_legs(**overrides)
    k_act = LINEAR_ACTUATOR["locked_stiffness"]
    for _ in range(5):
        pose = hexapod_pose(rng)
        for leg in legs:
            k = leg_stiffness(leg_springs(leg.chain(leg.solve(pose)), k_act))
            # largest measured 2.2e-15 (both cases, 5 poses, 6 legs)
            assert rel(k, two_force_stiffness(leg, pose, k_act)) < 1e-14


def test_universal_frame_choice_does_not_change_an_isotropic_leg() -> None:
    """The U's e1 about the leg is a convention: turning it changes nothing."""
    leg = hexapod_legs()[0]
    pose = np.array([0.01, -0.02, HOME_HEIGHT, 0.05, -0.03, 0.1])
    chain = list(leg.chain(leg.solve(pose)))
    k0 = leg_stiffness(leg_springs(chain, 5e7))
    u = chain[0]
    assert isinstance(u, Joint) and u.axis2 is not None
    n = np.cross(u.axis, u.axis2)
    ang = 0.7
    e1 = np.cos(ang) * u.axis + np.sin(ang) * u.axis2
    chain[0] = Joint("U", e1, u.point, u.springs, name=u.name, axis2=np.cross(n, e1))
    assert rel(leg_stiffness(leg_springs(chain, 5e7)), k0) < 1e-12


@pytest.mark.parametrize("make", [prs_legs, rps_legs], ids=["3-PRS", "3-RPS"])
@pytest.mark.parametrize("alpha0_deg", [0.0, 17.0, 40.0])
def test_parasitic_motion_of_a_symmetric_tripod(make, alpha0_deg: float) -> None:  # type: ignore[no-untyped-def]
    """Completed pose = pure tilt R = Rz(psi) Ry(theta) Rz(-psi) with
    x + i y = -(r_p / 2)(1 - cos theta) e^{i (3 alpha0 - 2 psi)} (r_p = 0.1 m)."""
    alpha0 = np.radians(alpha0_deg)
    legs = make(alpha0)
    rot_z, rot_y = (
        (lambda a: P.rotation_from_angles([0, 0, a])),
        (lambda a: P.rotation_from_angles([0, a, 0])),
    )
    worst = 0.0
    for theta in np.radians([0.5, 5.0, 15.0, 30.0]):
        for psi in np.radians([0.0, 35.0, 100.0, 200.0, 290.0]):
            angles = P.angles_from_rotation(rot_z(psi) @ rot_y(theta) @ rot_z(-psi))
            start = np.array([0.0, 0.0, 0.2, angles[0], angles[1], 0.0])
            q, ok = complete_poses(legs, TRIPOD_DEPENDENT, start)
            assert ok
            xy = -(0.1 / 2) * (1 - np.cos(theta)) * np.exp(1j * (3 * alpha0 - 2 * psi))
            worst = max(worst, abs(q[0] - xy.real), abs(q[1] - xy.imag), abs(q[5] - angles[2]))
    assert worst < 1e-12


def test_tripod_angles_are_three_fold() -> None:
    a = tripod_angles(0.1)
    np.testing.assert_allclose(np.diff(a), [2 * np.pi / 3] * 2)


def test_reciprocal_basis_stiffness_is_the_bordered_inverse() -> None:
    """core.solver.leg_stiffness (W (G^T C G)^-1 W^T) and eq. (1) as printed (the
    bordered inverse) are one model: equal on every leg type with ordinary springs."""
    from helpers import design_named, example_designs, is_planar
    from ppm_stiffness.core.solver import bordered_stiffness, leg_compliance_at_platform
    from ppm_stiffness.model import workspace_centre

    rng = np.random.default_rng(5)
    cases: list[tuple[LegModel, np.ndarray]] = []
    for name in example_designs(is_planar, paper=True):
        design = design_named(name)
        centre = P.planar_pose(workspace_centre(design))
        cases += [(leg, centre) for leg in design.legs]
    cases += [(leg, hexapod_pose(rng)) for leg in hexapod_legs()]
    tripods: list[list[LegModel]] = [list(prs_legs()), list(rps_legs())]
    for legs in tripods:
        pose = tripod_pose(legs, rng)
        cases += [(leg, pose) for leg in legs]
    worst = 0.0
    for leg, pose in cases:
        springs = leg_springs(leg.chain(leg.solve(pose)), leg.locked_stiffness())
        ref = bordered_stiffness(
            leg_compliance_at_platform(springs.screws, springs.compliance), springs.passive
        )
        worst = max(worst, rel(leg_stiffness(springs), ref))
    assert worst < 1e-12  # measured 3.3e-14 on these legs (the bordered inverse's rounding)
