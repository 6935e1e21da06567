"""The 6-D pose convention (docs/conventions.md): R = Rz(rz) Ry(ry) Rx(rx), extrinsic
X-Y-Z, checked against scipy; the twist update and the angle-rate map."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from ppm_stiffness.core import pose as P
from ppm_stiffness.core.conventions import hat

RNG = np.random.default_rng(20261123)
ANGLES = RNG.uniform(-1.2, 1.2, size=(50, 3))


def test_rotation_is_scipy_extrinsic_xyz_not_intrinsic() -> None:
    r = P.rotation_from_angles(ANGLES)
    extrinsic = Rotation.from_euler("xyz", ANGLES).as_matrix()
    intrinsic = Rotation.from_euler("XYZ", ANGLES).as_matrix()
    assert np.max(np.abs(r - extrinsic)) < 2e-15  # measured 4.4e-16
    # uppercase "XYZ" (intrinsic) is another matrix: the convention is not ambiguous
    assert np.min(np.max(np.abs(r - intrinsic), axis=(1, 2))) > 1e-3


def test_rotation_is_rz_ry_rx_applied_to_a_platform_point() -> None:
    rx, ry, rz = 0.3, -0.2, 0.5
    c, s = np.cos, np.sin
    rot_x = np.array([[1, 0, 0], [0, c(rx), -s(rx)], [0, s(rx), c(rx)]])
    rot_y = np.array([[c(ry), 0, s(ry)], [0, 1, 0], [-s(ry), 0, c(ry)]])
    rot_z = np.array([[c(rz), -s(rz), 0], [s(rz), c(rz), 0], [0, 0, 1]])
    b = np.array([0.1, -0.05, 0.02])
    pose = np.array([0.01, 0.02, 0.3, rx, ry, rz])
    # measured 0 (bit for bit); 1e-16 m is 2 ulp of the 0.3 m coordinate
    np.testing.assert_allclose(
        P.platform_offset(pose, b) + pose[:3],
        pose[:3] + rot_z @ rot_y @ rot_x @ b,
        rtol=0,
        atol=1e-16,
    )


def test_angles_round_trip() -> None:
    back = P.angles_from_rotation(P.rotation_from_angles(ANGLES))
    np.testing.assert_allclose(back, ANGLES, rtol=0, atol=5e-16)  # measured 1.1e-16 rad


def test_planar_pose_is_a_rotation_about_z() -> None:
    q = P.planar_pose(np.array([0.01, -0.02, 0.4]))
    np.testing.assert_array_equal(q, [0.01, -0.02, 0.0, 0.0, 0.0, 0.4])
    expected = Rotation.from_euler("z", 0.4).as_matrix()
    np.testing.assert_allclose(P.rotation(q), expected, rtol=0, atol=3e-16)  # measured 5.6e-17


def test_rotation_exp_is_scipy_rotvec() -> None:
    vecs = RNG.normal(0.0, 0.7, size=(40, 3))
    vecs[0] = 0.0
    vecs[1] = [1e-9, -2e-9, 0.5e-9]  # the series branch
    np.testing.assert_allclose(  # measured 4.4e-16
        P.rotation_exp(vecs), Rotation.from_rotvec(vecs).as_matrix(), rtol=0, atol=2e-15
    )


def test_displaced_pose_rotates_about_base_axes() -> None:
    pose = np.array([0.02, -0.01, 0.25, 0.2, -0.1, 0.7])
    twist = np.array([0.01, -0.02, 0.03, 1e-3, 2e-3, -1e-3])
    moved = P.displaced_pose(pose, twist)
    expected = Rotation.from_rotvec(twist[:3]).as_matrix() @ P.rotation(pose)
    # measured 2.2e-16
    np.testing.assert_allclose(P.rotation(moved), expected, rtol=0, atol=1e-15)
    # measured 0 (bit for bit); 1e-16 m is 2 ulp of the 0.25 m coordinate
    np.testing.assert_allclose(moved[:3], pose[:3] + twist[3:], rtol=0, atol=1e-16)
    # no jump of a whole turn near rz = pi
    near_pi = np.array([0.0, 0.0, 0.0, 0.0, 0.0, np.pi - 1e-3])
    # measured 4.4e-16 rad
    assert abs(P.displaced_pose(near_pi, [0, 0, 2e-3, 0, 0, 0])[5] - (np.pi + 1e-3)) < 2e-15


@pytest.mark.parametrize("seed", range(5))
def test_angle_rates_map_to_the_twist(seed: int) -> None:
    """omega = rz' e_z + ry' Rz e_y + rx' Rz Ry e_x: against hat(omega) = R' R^T by
    central differences along a straight line in the coordinates."""
    rng = np.random.default_rng(seed)
    q = np.concatenate([rng.normal(0, 0.1, 3), rng.uniform(-1.0, 1.0, 3)])
    qdot = rng.normal(0, 1.0, 6)
    h = 1e-6
    r_plus, r_minus = P.rotation(q + h * qdot), P.rotation(q - h * qdot)
    omega_hat = (r_plus - r_minus) / (2 * h) @ P.rotation(q).T
    twist = P.twist_from_coordinate_rates(q) @ qdot
    # the difference's error, largest measured 8.7e-11 over the five seeds
    np.testing.assert_allclose(hat(twist[:3]), omega_hat, rtol=0, atol=4e-10)
    # measured 0 (bit for bit); 1e-15 is about 4 ulp of the rates (about 1)
    np.testing.assert_allclose(twist[3:], qdot[:3], rtol=0, atol=1e-15)


def test_rotation_entries_kept_for_the_next_call_are_those_of_its_angles() -> None:
    """The last batch's rotation is reused only for the same angles (bit for bit): a
    repeated call gives the fresh values, an array changed in place its new rotation,
    and the kept entries cannot be written to."""
    poses = np.zeros((30, 6))
    poses[:, 3:] = ANGLES[:30]
    fresh = P.rotation(poses.copy())
    again = P.rotation(poses)  # the same angles: from the kept entries
    np.testing.assert_array_equal(again, fresh)
    scipy = Rotation.from_euler("xyz", ANGLES[:30]).as_matrix()
    assert np.max(np.abs(again - scipy)) < 2e-15  # measured 3.9e-16
    poses[5, 4] += 0.3  # changed in place: not the batch that was kept
    moved = P.rotation(poses)
    np.testing.assert_allclose(  # measured 3.3e-16
        moved[5], Rotation.from_euler("xyz", poses[5, 3:]).as_matrix(), rtol=0, atol=2e-15
    )
    np.testing.assert_array_equal(moved[:5], fresh[:5])
    entries = P.rotation_entries(poses[:, 3:])
    with pytest.raises(ValueError, match="read-only"):
        entries[0][0][0] = 2.0
