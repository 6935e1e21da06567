"""Physical properties of the model over many seeded random poses and frames."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from helpers import wide_design
from ppm_stiffness.core.beam import cantilever_compliance
from ppm_stiffness.core.conventions import (
    GAMMA,
    hat,
    rotation_z,
    stiffness_b_from_stiffness_a,
    twist_b_from_twist_a,
    vect,
    wrench_b_from_wrench_a,
)
from ppm_stiffness.core.decoupling import Method, decouple, shift_blocks
from ppm_stiffness.core.eigenscrews import eigenscrews, stiffness_from_screw_springs
from ppm_stiffness.core.solver import (
    leg_compliance_at_platform,
    leg_stiffness,
    transmitted_wrench_basis,
)
from ppm_stiffness.design import Design, default_design, design_from_dict
from ppm_stiffness.model import leg_springs_at_pose, stiffness_at_pose

DESIGN = default_design()


def random_poses(n: int, seed: int) -> np.ndarray:
    """Seeded reachable poses of the built-in design."""
    rng = np.random.default_rng(seed)
    out: list[np.ndarray] = []
    while len(out) < n:
        pose = np.array(
            [rng.uniform(-0.015, 0.010), rng.uniform(-0.03, 0.03), rng.uniform(-0.5, 0.5)]
        )
        if all(bool(leg.reachable(leg.solve(pose))) for leg in DESIGN.legs):
            out.append(pose)
    return np.array(out)


POSES = random_poses(40, seed=1)


@pytest.mark.parametrize("pose", POSES)
def test_stiffness_symmetric_positive_definite(pose: np.ndarray) -> None:
    k = stiffness_at_pose(DESIGN, pose)
    np.testing.assert_allclose(k, k.T, rtol=0, atol=1e-9 * np.abs(k).max())
    assert np.linalg.eigvalsh(k)[0] > 0


@pytest.mark.parametrize("pose", POSES[:15])
def test_eigenscrews_pairs_pitch_sign_and_rebuild(pose: np.ndarray) -> None:
    k = stiffness_at_pose(DESIGN, pose)
    s = eigenscrews(k)
    # the design is symmetric about its plane: eigenvalues in +- pairs
    np.testing.assert_allclose(s.eigenvalues[:3], -s.eigenvalues[3:], rtol=1e-8)
    # lambda * pitch >= 0 (a positive-definite K has positive spring constants)
    assert np.all(s.eigenvalues * s.pitches >= 0)
    assert np.all(s.spring_constants > 0)
    # the six screw springs rebuild K
    np.testing.assert_allclose(stiffness_from_screw_springs(s), k, atol=1e-8 * np.abs(k).max())
    # each eigenvector solves K zeta = lambda Gamma zeta
    for i in range(6):
        z = s.eigenvectors[:, i]
        np.testing.assert_allclose(k @ z, s.eigenvalues[i] * GAMMA @ z, atol=1e-8 * np.abs(k).max())


@pytest.mark.parametrize("pose", POSES[:15])
def test_decoupling_keeps_K_tt_and_is_a_frame_shift(pose: np.ndarray) -> None:
    k = stiffness_at_pose(DESIGN, pose)
    methods: tuple[Method, ...] = ("paper", "least-squares")
    for method in methods:
        dec = decouple(k, method)
        # the decoupled blocks are K expressed at the shifted point, eq. (16), whose
        # translational block is unchanged, eq. (18c)
        shifted = stiffness_b_from_stiffness_a(k, np.eye(3), dec.d)
        scale = np.abs(k).max()
        np.testing.assert_allclose(shifted[3:, 3:], k[3:, 3:], atol=1e-9 * scale)
        np.testing.assert_allclose(shifted[:3, :3], dec.K_rr, atol=1e-9 * scale)
        np.testing.assert_allclose(shifted[:3, 3:], dec.K_rt, atol=1e-9 * scale)


@pytest.mark.parametrize("pose", POSES[:10])
def test_leg_stiffness_bordered_inverse_equals_reciprocal_basis(pose: np.ndarray) -> None:
    # Independent route: K_i = W (W^T C W)^{-1} W^T with W the wrenches reciprocal to
    # the passive joints. Also K_i annihilates the passive twists.
    for leg in leg_springs_at_pose(DESIGN, pose):
        k = leg_stiffness(leg)
        c = leg_compliance_at_platform(leg.screws, leg.compliance)
        w = transmitted_wrench_basis(leg.passive)
        k_ref = w @ np.linalg.inv(w.T @ c @ w) @ w.T
        np.testing.assert_allclose(k, k_ref, atol=1e-7 * np.abs(k_ref).max())
        np.testing.assert_allclose(k @ leg.passive, 0, atol=1e-7 * np.abs(k).max())


@settings(max_examples=60, deadline=None)
@given(
    angle=st.floats(-np.pi, np.pi),
    p=st.lists(st.floats(-1, 1), min_size=3, max_size=3),
    t=st.lists(st.floats(-1, 1), min_size=6, max_size=6),
    w=st.lists(st.floats(-1, 1), min_size=6, max_size=6),
)
def test_twist_and_wrench_transforms_preserve_power(
    angle: float, p: list[float], t: list[float], w: list[float]
) -> None:
    r = rotation_z(angle) @ np.array(
        [[1, 0, 0], [0, np.cos(1.0), -np.sin(1.0)], [0, np.sin(1.0), np.cos(1.0)]]
    )
    tb = twist_b_from_twist_a(r, p) @ np.array(t)
    wb = wrench_b_from_wrench_a(r, p) @ np.array(w)
    assert wb @ tb == pytest.approx(np.dot(w, t), abs=1e-12)


@settings(max_examples=30, deadline=None)
@given(
    v=st.lists(st.floats(-10, 10), min_size=3, max_size=3),
    b=st.lists(st.floats(-10, 10), min_size=3, max_size=3),
)
def test_hat_and_vect(v: list[float], b: list[float]) -> None:
    np.testing.assert_allclose(hat(v) @ np.array(b), np.cross(v, b), atol=1e-9)
    np.testing.assert_allclose(vect(hat(v)), v)


def _transformed_design(design: Design, angle: float, shift: np.ndarray) -> Design:
    """The whole machine rotated by ``angle`` about z and then translated by ``shift``."""
    data = design.model_dump()
    c, s = np.cos(angle), np.sin(angle)
    for leg in data["legs"]:
        x, y = leg["base_point"]
        leg["base_point"] = (c * x - s * y + shift[0], s * x + c * y + shift[1])
        leg["alpha"] = math.remainder(leg["alpha"] + angle, 2 * math.pi)
        leg["psi"] = math.remainder(leg["psi"] + angle, 2 * math.pi)
    return wide_design(design_from_dict(data))


@pytest.mark.parametrize("seed", range(5))
def test_frame_invariance_of_the_model(seed: int) -> None:
    # Moving the whole machine (base and pose) by a rigid planar motion must give the
    # same K, expressed in the rotated axes: K_b = T^-T K_a T^-1 with T of eq. (13).
    rng = np.random.default_rng(seed)
    angle = rng.uniform(-np.pi, np.pi)
    shift = rng.uniform(-0.2, 0.2, size=2)
    pose = POSES[seed]
    k_a = stiffness_at_pose(DESIGN, pose)
    moved = _transformed_design(DESIGN, angle, shift)
    r = rotation_z(angle)
    xy = r[:2, :2] @ pose[:2] + shift
    k_b = stiffness_at_pose(moved, np.array([xy[0], xy[1], pose[2]]))
    expected = stiffness_b_from_stiffness_a(k_a, r, np.zeros(3))
    np.testing.assert_allclose(k_b, expected, atol=1e-8 * np.abs(k_a).max())


def test_shift_blocks_equal_eq16() -> None:
    k = stiffness_at_pose(DESIGN, POSES[0])
    d = np.array([0.01, -0.02, 0.005])
    rr, rt, tt = shift_blocks(k, d)
    full = stiffness_b_from_stiffness_a(k, np.eye(3), d)
    np.testing.assert_allclose(full, np.block([[rr, rt], [rt.T, tt]]), atol=1e-9 * np.abs(k).max())


def test_cantilever_compliance_textbook() -> None:
    # Tip deflection F L^3 / 3EI and tip rotation F L^2 / 2EI of a cantilever.
    section = DESIGN.legs[0].distal.section()
    length = 0.1
    c = cantilever_compliance(section, length)
    ei = section.young_modulus * section.inertia_z
    f = 10.0
    tip = c @ np.array([0, 0, 0, 0, f, 0])
    assert tip[4] == pytest.approx(f * length**3 / (3 * ei))
    assert tip[2] == pytest.approx(f * length**2 / (2 * ei))
    assert np.all(np.linalg.eigvalsh(c) > 0)
