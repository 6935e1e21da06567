"""The maps' closed forms against independent computations: the spatial principal
stiffnesses (Schur complements, 3x3 eigenvalues by the trigonometric method with the
discriminant as a sum of squares) against numpy's linalg route
(core.principal.principal_compliance_values) and against matrices built from known
eigenvalues; the tool-point transform against model.stiffness_at_tool_point; the cheap
singularity bound against the exact transmission index.

Measured when written: known eigenvalues, exactly repeated ones included, to 1.5e-15
of the largest (numpy's eigvalsh: 1.8e-15), so 5e-15; the shipped designs' K (random
and home poses, the hexapod's home with repeated eigenvalues) against the linalg route
to 4.1e-14 (3-PRS), 1.2e-14 (3-RPS), 3.7e-15 (hexapod) of the largest value of each
set, so 1e-12. On random ill-conditioned matrices the two
routes differ by up to 2e-11: there the closed form is the accurate one (checked once
against 40-digit arithmetic, mpmath: <= 2e-15 against 2e-11 for the linalg route).
"""

from __future__ import annotations

import numpy as np
import pytest

from helpers import design_named, example_designs, flexure_jointed, within_required
from ppm_stiffness.core.principal import principal_compliance_values
from ppm_stiffness.core.singularity import nonsingular, transmission_index
from ppm_stiffness.maps import batch
from ppm_stiffness.maps.principal_batch import (
    principal_values,
    stiffness_at_points,
    sym3_eigenvalues,
    tool_offsets,
)
from ppm_stiffness.maps.transmission import nonsingular_projector
from ppm_stiffness.model import stiffness_at_tool_point
from ppm_stiffness.poses import home_pose, task_indices

PAIRS = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


def rotations(rng: np.random.Generator, n: int) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(n, 3, 3)))
    return q * np.sign(np.diagonal(r, axis1=1, axis2=2))[:, None, :]


@pytest.mark.parametrize(
    "values",
    [
        [1.0, 2.0, 3.0],
        [1.0, 1.0, 5.0],  # a repeated pair below
        [1.0, 5.0, 5.0],  # a repeated pair above
        [3.0, 3.0, 3.0],  # a multiple of the identity (no spread)
        [3.0, 3.0, 3.0 + 1e-9],
        [1e-3, 1.0, 1e3],
        [-2.0, 0.5, 4.0],
    ],
)
def test_symmetric_3x3_eigenvalues_of_known_matrices(values: list[float]) -> None:
    rng = np.random.default_rng(len(values) + int(1e3 * abs(values[0])))
    q = rotations(rng, 500)
    lam = np.array(values) * rng.uniform(0.5, 2.0, (500, 1))
    s = q @ (lam[:, :, None] * np.swapaxes(q, 1, 2))
    got = sym3_eigenvalues([s[:, i, j] for i, j in PAIRS])
    ref = np.sort(lam, axis=1)
    scale = np.max(np.abs(ref), axis=1, keepdims=True)
    assert np.max(np.abs(got - ref) / scale) <= 5e-15


@pytest.mark.parametrize("name", example_designs(paper=True))
def test_principal_values_equal_the_linalg_route(name: str) -> None:
    design = design_named(name)
    idx = list(task_indices(design))
    rng = np.random.default_rng(2)
    home = home_pose(design)[idx]
    half = np.array([0.02 if i < 3 else 0.15 for i in idx])
    if flexure_jointed(design):  # its flexures' range
        half = within_required(design, half * 0.05)
    poses = np.vstack([home, home + rng.uniform(-1, 1, (200, len(idx))) * half])
    res = batch.evaluate_poses(design, poses, matrices=True)
    assert res.stiffness is not None and res.valid[0] and res.valid.sum() > 100
    k = res.stiffness[res.valid]
    rot, tra = principal_values(k)
    rot_ref, tra_ref = principal_compliance_values(k)
    for got, ref in ((rot, rot_ref), (tra, tra_ref)):
        assert np.max(np.abs(got - ref) / ref[:, 2:]) <= 1e-12


def test_principal_values_are_nan_where_k_is_not_finite_or_definite() -> None:
    k = np.tile(np.diag([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]), (3, 1, 1))
    k[1, 0, 0] = np.nan
    k[2, 3:, 3:] = -np.eye(3)
    rot, tra = principal_values(k)
    np.testing.assert_allclose(rot[0], [1.0, 2.0, 3.0], rtol=1e-15)
    np.testing.assert_allclose(tra[0], [4.0, 5.0, 6.0], rtol=1e-15)
    assert np.all(np.isnan(rot[1])) and np.all(np.isnan(tra[1]))
    assert np.all(np.isnan(rot[2]))  # C_rr^-1 needs K_tt^-1: K_tt not positive definite


def test_stiffness_at_points_is_the_tool_point_transform() -> None:
    design = design_named("hexapod_6ups")
    rng = np.random.default_rng(8)
    poses = home_pose(design) + rng.uniform(-1, 1, (20, 6)) * np.array([0.02] * 3 + [0.1] * 3)
    res = batch.evaluate_poses(design, poses, matrices=True)
    assert res.stiffness is not None and res.valid.all()
    tool = np.array([0.01, -0.02, 0.07])
    moved = stiffness_at_points(res.stiffness, tool_offsets(poses, tool))
    for n in range(20):
        ref = stiffness_at_tool_point(res.stiffness[n], poses[n], tool)
        np.testing.assert_allclose(moved[n], ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))


def test_the_cheap_singularity_bound_never_decides_otherwise() -> None:
    """Projector sums of six random unit wrench directions, scaled so that the
    transmission index spans 1e-9 to 1 around the tolerance 1e-6: the bound's decision
    (exact index where it cannot clear a pose) equals the exact one everywhere."""
    rng = np.random.default_rng(1)
    n = 4000
    b = rng.normal(size=(n, 6, 6))
    u, _, _ = np.linalg.svd(b)
    sv = np.sort(rng.uniform(0.2, 1.0, (n, 6)), axis=1)
    sv[:, 0] = np.sqrt(10.0 ** rng.uniform(-9, 0, n)) * sv[:, 5]  # tau = (s_min / s_max)^2
    pi = (u * sv[:, None, ::-1] ** 2) @ np.swapaxes(u, 1, 2)
    exact = nonsingular(transmission_index(pi))
    assert 0.2 < exact.mean() < 0.8
    np.testing.assert_array_equal(nonsingular_projector(pi), exact)
    pi[:3] = np.nan
    assert not nonsingular_projector(pi)[:3].any()
