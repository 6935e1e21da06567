"""Platform poses in 6-D: position, orientation angles, and the twist update.

A pose is six coordinates ``(x, y, z, rx, ry, rz)`` [m, m, m, rad, rad, rad]: the
position p of the platform reference point P in F_b and the orientation of the
platform frame F_p,

    R = Rz(rz) @ Ry(ry) @ Rx(rx)

(extrinsic X-Y-Z angles: a roll rx about the fixed x axis, then a pitch ry about the
fixed y axis, then a yaw rz about the fixed z axis; ``scipy.spatial.transform.Rotation
.from_euler("xyz", [rx, ry, rz])`` with lowercase "xyz"). A point b given in F_p is at
``p + R b`` in F_b. A planar pose ``(x, y, phi)`` is ``(x, y, 0, 0, 0, phi)``.

A twist ``t = (phi, v)`` (rotation first, :mod:`ppm_stiffness.core.conventions`) is a
small rotation vector about the axes of F_b and a small displacement of P; it moves a
pose to ``R' = exp(hat(phi)) R``, ``p' = p + v`` (:func:`displaced_pose`). Rates of the
angles map to the angular velocity by ``omega = rz' e_z + ry' Rz e_y + rx' Rz Ry e_x``
(:func:`twist_from_coordinate_rates`).

Every function takes arrays with leading batch axes.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, hat

# defined in core.names (no numpy: the CLI's --help uses them), re-exported here
from ppm_stiffness.core.names import ANGLE_COORDINATES as ANGLE_COORDINATES
from ppm_stiffness.core.names import PLANAR_INDEX as PLANAR_INDEX
from ppm_stiffness.core.names import POSE_COORDINATES as POSE_COORDINATES
from ppm_stiffness.core.names import POSE_CSV_COLUMNS as POSE_CSV_COLUMNS
from ppm_stiffness.core.names import POSE_INDEX as POSE_INDEX
from ppm_stiffness.core.names import POSE_UNITS as POSE_UNITS

#: The nine entries of R, row by row (each an array of the batch shape).
RotationEntries = tuple[tuple[FloatArray, ...], ...]
#: Largest batch whose rotation :func:`rotation_entries` keeps for the next call.
ROTATION_CACHE_POSES = 65536
#: The last batch of angles evaluated (a private copy) and its entries.
_last_rotation: tuple[FloatArray, RotationEntries] | None = None


def rotation_entries(angles: ArrayLike) -> RotationEntries:
    """The nine entries ``R[i][j]`` (each (...), read-only) of ``R = Rz(rz) Ry(ry) Rx(rx)``
    from angles (..., 3) = (rx, ry, rz) [rad], in closed form (one array per entry: no
    (..., 3, 3) temporaries or matrix products).

    Every leg of a design evaluates R at the same poses (its inverse kinematics), twice
    for a spatial leg: the entries of the last batch (up to
    :data:`ROTATION_CACHE_POSES` poses) are kept with a copy of its angles and returned
    again when the angles are the same bits, so that the result is the same whether or
    not it comes from the cache (and an array changed in place is not mistaken for the
    one evaluated). The pair is replaced in one assignment: threads may share it.
    """
    global _last_rotation
    a = np.asarray(angles, dtype=float)
    last = _last_rotation
    if (
        last is not None
        and last[0].shape == a.shape
        and np.array_equal(last[0].view(np.int64), a.view(np.int64))
    ):
        return last[1]
    columns = np.moveaxis(a, -1, 0).copy()  # contiguous rx, ry, rz
    cx, sx = np.cos(columns[0]), np.sin(columns[0])
    cy, sy = np.cos(columns[1]), np.sin(columns[1])
    cz, sz = np.cos(columns[2]), np.sin(columns[2])
    szsy, czsy = sz * sy, cz * sy
    entries = (
        (cz * cy, czsy * sx - sz * cx, czsy * cx + sz * sx),
        (sz * cy, szsy * sx + cz * cx, szsy * cx - cz * sx),
        (-sy, cy * sx, cy * cx),
    )
    for row in entries:
        for value in row:
            if isinstance(value, np.ndarray):  # (one pose: immutable numpy scalars)
                value.flags.writeable = False
    if a.size <= 3 * ROTATION_CACHE_POSES:
        _last_rotation = (a.copy(), entries)
    return entries


def rotation_from_angles(angles: ArrayLike) -> FloatArray:
    """``R = Rz(rz) Ry(ry) Rx(rx)`` from angles (..., 3) = (rx, ry, rz) [rad]; (..., 3, 3)."""
    entries = rotation_entries(angles)
    out = np.empty(entries[0][0].shape + (3, 3))
    for i, row in enumerate(entries):
        for j, value in enumerate(row):
            out[..., i, j] = value
    return out


def angles_from_rotation(rotation: ArrayLike) -> FloatArray:
    """The angles (rx, ry, rz) (..., 3) of ``R = Rz Ry Rx``, ry in [-pi/2, pi/2].

    At ry = +-pi/2 (gimbal lock) only rx -+ rz is defined; rx is then returned as 0.
    """
    r = np.asarray(rotation, dtype=float)
    ry = np.arctan2(-r[..., 2, 0], np.hypot(r[..., 2, 1], r[..., 2, 2]))
    rx = np.arctan2(r[..., 2, 1], r[..., 2, 2])
    rz = np.arctan2(r[..., 1, 0], r[..., 0, 0])
    lock = np.hypot(r[..., 0, 0], r[..., 1, 0]) < 1e-12
    if np.any(lock):
        rx = np.where(lock, 0.0, rx)
        rz = np.where(lock, np.arctan2(-r[..., 0, 1], r[..., 1, 1]), rz)
    return np.stack([rx, ry, rz], axis=-1)


def rotation_exp(rotation_vector: ArrayLike) -> FloatArray:
    """``exp(hat(phi))`` (Rodrigues) of rotation vectors (..., 3) [rad]; (..., 3, 3)."""
    phi = np.asarray(rotation_vector, dtype=float)
    angle = np.linalg.norm(phi, axis=-1)
    small = angle < 1e-8
    safe = np.where(small, 1.0, angle)
    # sin(a)/a and (1 - cos(a))/a^2 with their series near 0
    a = np.where(small, 1.0 - angle**2 / 6.0, np.sin(safe) / safe)
    b = np.where(small, 0.5 - angle**2 / 24.0, (1.0 - np.cos(safe)) / safe**2)
    k = hat(phi)
    return np.asarray(np.eye(3) + a[..., None, None] * k + b[..., None, None] * (k @ k))


def position(pose: ArrayLike) -> FloatArray:
    """Position p (..., 3) [m] of P in F_b."""
    return np.asarray(np.asarray(pose, dtype=float)[..., :3])


def rotation(pose: ArrayLike) -> FloatArray:
    """Orientation R (..., 3, 3) of F_p in F_b (F_p components -> F_b components)."""
    return rotation_from_angles(np.asarray(pose, dtype=float)[..., 3:])


def platform_offset(pose: ArrayLike, point: ArrayLike) -> FloatArray:
    """``R b`` (..., 3) [m]: a platform point b (F_p) relative to P, axes of F_b."""
    q = np.asarray(pose, dtype=float)
    b = np.asarray(point, dtype=float)
    entries = rotation_entries(q[..., 3:])
    out = np.empty(np.broadcast_shapes(q.shape[:-1], b.shape[:-1]) + (3,))
    if b.ndim == 1:  # one point: its components are numbers, exact zeros cost nothing
        terms = [(j, float(b[j])) for j in range(3) if b[j] != 0.0]
        for i, row in enumerate(entries):
            value: FloatArray | float = 0.0
            for j, bj in terms:
                value = row[j] * bj if type(value) is float else value + row[j] * bj
            out[..., i] = value
        return out
    for i, row in enumerate(entries):
        out[..., i] = row[0] * b[..., 0] + row[1] * b[..., 1] + row[2] * b[..., 2]
    return out


def _wrap_near(angle: FloatArray, reference: FloatArray) -> FloatArray:
    """``angle`` shifted by whole turns to lie within pi of ``reference``."""
    return np.asarray(reference + np.mod(angle - reference + math.pi, 2 * math.pi) - math.pi)


def pose_from_rotation(p: ArrayLike, r: ArrayLike, near: ArrayLike | None = None) -> FloatArray:
    """A pose (..., 6) from a position (..., 3) and a rotation (..., 3, 3); angles rx, rz
    within a half turn of those of ``near`` (a pose) when given."""
    angles = angles_from_rotation(r)
    if near is not None:
        ref = np.asarray(near, dtype=float)[..., 3:]
        angles[..., 0] = _wrap_near(angles[..., 0], ref[..., 0])
        angles[..., 2] = _wrap_near(angles[..., 2], ref[..., 2])
    return np.concatenate([np.broadcast_to(np.asarray(p, dtype=float), angles.shape), angles], -1)


def displaced_pose(pose: ArrayLike, twist: ArrayLike) -> FloatArray:
    """The pose after a twist (..., 6) = (phi, v): ``R' = exp(hat(phi)) R``, ``p' = p + v``.

    Parameters
    ----------
    pose : array_like (..., 6) [m, rad]
    twist : array_like (..., 6) [rad, m], rotation vector about the axes of F_b first.

    Returns
    -------
    ndarray (..., 6)
        The angles stay within a half turn of the given ones (no jump of 2 pi).
    """
    q = np.asarray(pose, dtype=float)
    t = np.asarray(twist, dtype=float)
    r_new = rotation_exp(t[..., :3]) @ rotation(q)
    return pose_from_rotation(q[..., :3] + t[..., 3:], r_new, near=q)


def twist_from_coordinate_rates(pose: ArrayLike) -> FloatArray:
    """Matrix E (..., 6, 6) with ``t = E @ qdot``: the twist (omega, v) of the platform
    from the rates of its coordinates (x, y, z, rx, ry, rz).

    ``v = (x', y', z')``; ``omega = rz' e_z + ry' Rz e_y + rx' Rz Ry e_x``.
    """
    q = np.asarray(pose, dtype=float)
    ry, rz = q[..., 4], q[..., 5]
    cz, sz = np.cos(rz), np.sin(rz)
    cy, sy = np.cos(ry), np.sin(ry)
    out = np.zeros(q.shape[:-1] + (6, 6))
    out[..., 3, 0] = out[..., 4, 1] = out[..., 5, 2] = 1.0
    # rx: Rz Ry e_x = (cz cy, sz cy, -sy)
    out[..., 0, 3] = cz * cy
    out[..., 1, 3] = sz * cy
    out[..., 2, 3] = -sy
    # ry: Rz e_y = (-sz, cz, 0)
    out[..., 0, 4] = -sz
    out[..., 1, 4] = cz
    # rz: e_z
    out[..., 2, 5] = 1.0
    return out


def planar_pose(planar: ArrayLike) -> FloatArray:
    """``(x, y, 0, 0, 0, phi)`` (..., 6) from planar poses (x, y, phi) (..., 3)."""
    p = np.asarray(planar, dtype=float)
    out = np.zeros(p.shape[:-1] + (6,))
    out[..., 0] = p[..., 0]
    out[..., 1] = p[..., 1]
    out[..., 5] = p[..., 2]
    return out
