"""The batched path (ppm_stiffness.maps.batch) against the general single-pose path.

The batched path evaluates the same virtual-spring model through an exact reduced form
(see the batch module docstring); every number must equal the single-pose path
(model.stiffness_at_pose + decoupling.decouple(K, "paper")) to 1e-10 relative, and the
masked poses must be exactly those where the single-pose path raises.
"""

from __future__ import annotations

import numpy as np
import pytest

from helpers import wide_design
from ppm_stiffness.core.decoupling import decouple
from ppm_stiffness.core.errors import (
    DesignError,
    InputDataError,
    SingularConfigurationError,
    UnreachablePoseError,
)
from ppm_stiffness.design import Design, default_design
from ppm_stiffness.maps import batch
from ppm_stiffness.maps.loaded import loaded_poses
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.statics.loading import actuator_forces

DESIGN = default_design()
RTOL = 1e-10


def single(design: Design, pose: np.ndarray, k_act: np.ndarray | None = None) -> np.ndarray:
    """(k_phi, k_x, k_y, d_x, d_y) by the single-pose API."""
    k = stiffness_at_pose(design, pose, k_act)
    dec = decouple(k, "paper")
    return np.array(
        [
            dec.rotational_values[2],
            dec.translational_values[0],
            dec.translational_values[1],
            dec.d[0],
            dec.d[1],
        ]
    )


def random_poses(rng: np.random.Generator, n: int, phi_max: float = 0.6) -> np.ndarray:
    return np.stack(
        [
            rng.uniform(-0.012, 0.008, n),
            rng.uniform(-0.03, 0.03, n),
            rng.uniform(-phi_max, phi_max, n),
        ],
        axis=-1,
    )


def test_batched_equals_single_pose_on_random_poses_phi_and_actuators() -> None:
    design = wide_design()
    rng = np.random.default_rng(20240611)
    n = 120
    poses = random_poses(rng, n)
    k_act = rng.uniform(1.5e3, 1.2e5, (n, 3))  # the actuator law's whole range
    res = batch.evaluate_poses(design, poses, k_act, matrices=True, chunk_size=37)
    assert res.stiffness is not None
    assert res.valid.all()  # the sampled region is reachable and nonsingular
    for i in range(n):
        k_ref = stiffness_at_pose(design, poses[i], k_act[i])
        assert np.max(np.abs(res.stiffness[i] - k_ref)) <= RTOL * np.max(np.abs(k_ref))
        ref = single(design, poses[i], k_act[i])
        got = np.array([res.k_phi[i], res.k_x[i], res.k_y[i]])
        np.testing.assert_allclose(got, ref[:3], rtol=RTOL, atol=0)
        # the shift d (29): relative to its size
        assert np.max(np.abs(res.d[i, :2] - ref[3:])) <= RTOL * np.max(np.abs(ref[3:]))
        assert res.d[i, 2] == 0.0


def test_batched_equals_single_pose_at_the_centre_with_the_paper_numbers() -> None:
    res = batch.evaluate_poses(DESIGN, np.zeros(3))
    ref = single(DESIGN, np.zeros(3))
    np.testing.assert_allclose([res.k_phi, res.k_x, res.k_y], ref[:3], rtol=RTOL)
    # paper (31)-(32): k_phi = 193.5 N·m/rad, k_x = 0.3458e5, k_y = 0.6597e5 N/m.
    # Measured: 193.588, 34570.09, 65950.00, relative +4.5e-4, -2.9e-4, -3.0e-4 (the
    # design is calibrated on (22), which prints K_tt 10-20 N/m below (31)-(32));
    # 1.5e-3 allowed.
    np.testing.assert_allclose([res.k_phi, res.k_x, res.k_y], [193.5, 34580, 65970], rtol=1.5e-3)


def test_masked_poses_are_exactly_those_the_single_pose_path_rejects() -> None:
    rng = np.random.default_rng(7)
    n = 250
    # a box larger than the reconstructed workspace: about half the poses are outside
    poses = np.stack(
        [rng.uniform(-0.025, 0.015, n), rng.uniform(-0.035, 0.035, n), rng.uniform(-0.7, 0.7, n)],
        axis=-1,
    )
    res = batch.evaluate_poses(DESIGN, poses)
    expected = np.ones(n, dtype=bool)
    for i in range(n):
        try:
            stiffness_at_pose(DESIGN, poses[i])
        except (UnreachablePoseError, SingularConfigurationError):
            expected[i] = False
    assert 0.2 < expected.mean() < 0.8
    np.testing.assert_array_equal(res.valid, expected)
    assert np.all(res.k_phi.mask == ~expected)
    assert np.all(np.isfinite(res.k_x.compressed()))


def test_singular_orientation_is_masked_like_the_single_pose_path() -> None:
    """At phi = 90 deg the force lines of legs 1 and 2 coincide (x_D1 = x_D2): the
    in-plane stiffness is singular. Near it the transmission index crosses the
    threshold; the cheap bound must hand those poses to the exact test and agree with
    the single-pose path pose by pose."""
    design = wide_design()
    # the transmission index grows as 0.0447 offset^2 and crosses the tolerance 1e-6
    # near 0.0047 rad
    offsets = np.array([0.0, 1e-9, 1e-6, 1e-4, 1e-3, 0.0046, 0.0047, 0.0048, 0.01, -0.0048, -0.05])
    poses = np.stack([np.zeros_like(offsets), np.zeros_like(offsets), np.pi / 2 + offsets], axis=-1)
    res = batch.evaluate_poses(design, poses)
    expected = np.ones(offsets.size, dtype=bool)
    for i, pose in enumerate(poses):
        try:
            stiffness_at_pose(design, pose)
        except SingularConfigurationError:
            expected[i] = False
    assert not expected[:5].any() and expected[-1] and expected[-3]  # both outcomes occur
    np.testing.assert_array_equal(res.valid, expected)


def test_batched_loaded_forces_equal_the_linear_split_of_a_determinate_design() -> None:
    """A 3-leg design's actuator forces are statically determinate: the batched loaded
    equilibrium (maps.loaded.loaded_poses) gives the linear split at any actuator
    stiffness (statics.loading.actuator_forces, an independent computation: leg
    stiffnesses and a 6x6 solve). Measured: 1e-15 relative."""
    rng = np.random.default_rng(3)
    design = wide_design()
    poses = random_poses(rng, 12, 0.5)
    for pose in poses:
        wrench = rng.normal(size=6) * np.array([0.01, 0.01, 0.01, 0.5, 0.5, 2])
        res = loaded_poses(design, pose, wrench)
        assert res.valid
        got, ref = res.actuator_forces.data, actuator_forces(design, wrench, pose)
        np.testing.assert_allclose(got, ref, rtol=1e-10, atol=1e-12 * np.max(np.abs(ref)))


def test_decouple_batch_equals_decouple_on_general_matrices() -> None:
    rng = np.random.default_rng(11)
    a = rng.normal(size=(20, 6, 6)) * np.array([0.1, 0.1, 0.1, 1.0, 1.0, 1.0])
    mats = a @ np.swapaxes(a, -1, -2) * 1e5 + np.eye(6) * 10
    d, k_rr, k_tt = batch.decouple_batch(mats)
    for i in range(20):
        ref = decouple(mats[i], "paper")
        np.testing.assert_allclose(d[i], ref.d, rtol=1e-10, atol=1e-14)
        np.testing.assert_allclose(
            k_rr[i], ref.K_rr, rtol=1e-10, atol=1e-12 * np.max(np.abs(ref.K_rr))
        )
        np.testing.assert_allclose(k_tt[i], ref.K_tt, rtol=0, atol=0)


def test_principal_from_matrices_equals_decouple_on_single_pose_matrices() -> None:
    rng = np.random.default_rng(5)
    design = wide_design()
    mats = np.array([stiffness_at_pose(design, p) for p in random_poses(rng, 10)])
    pr = batch.principal_from_entries(batch.entries_from_matrices(mats))
    for i, k in enumerate(mats):
        dec = decouple(k, "paper")
        np.testing.assert_allclose(
            [pr.k_phi[i], pr.k_x[i], pr.k_y[i], pr.k_z[i]],
            [dec.rotational_values[2], *dec.translational_values],
            rtol=1e-12,
        )


def test_bad_inputs_raise_library_errors() -> None:
    with pytest.raises(InputDataError, match=r"poses must have shape .* got \(4, 2\)"):
        batch.evaluate_poses(DESIGN, np.zeros((4, 2)))
    with pytest.raises(DesignError, match="actuator stiffness"):
        batch.evaluate_poses(DESIGN, np.zeros((4, 3)), [1.0, -2.0, 3.0])
