"""Conventions of ppm-stiffness, stated once.

Every other module follows this page; ``docs/conventions.md`` repeats it for readers.

Units
    SI everywhere inside the library: m, rad, N, N·m, N/m, N·m/rad. Only the CLI
    speaks mm and degrees, and only at its edges.

Frames
    ``F_b``: the base frame, fixed to the ground, z up (normal to the plane of motion).
    ``F_p``: the platform frame, origin at the platform centre ``P``, x-axis parallel
    to D1-D2 at phi = 0. A pose is ``(x, y, phi)``: the position of ``P`` in ``F_b``
    and the rotation of ``F_p`` about z.
    Cartesian stiffness matrices are expressed **at P with the axes of F_b** (the
    paper's "MP centre as reference point").

Twists and wrenches (paper eq. 12, 22)
    twist  ``t = (omega, v)``  [rad, m]: omega the small rotation, v the small
    displacement of the body point that coincides with the reference point.
    wrench ``w = (m, f)``  [N·m, N]: m the moment about the reference point, f the force.
    The power (virtual work) is the plain dot product ``w @ t``.
    The stiffness matrix maps twist to wrench, ``w = K @ t``, with blocks
    ``[[K_rr, K_rt], [K_rt.T, K_tt]]`` in N·m/rad, N and N/m.

A unit screw of a rotation about an axis ``a`` through a point ``c`` (relative to
the reference point) is ``(a, c x a)``; of a translation along ``a`` it is ``(0, a)``.

Length balancing
    Rotations and translations are compared through one length, ``LENGTH_SCALE``
    L = 0.1 m: the length-balanced stiffness is ``S K S`` with
    ``S = diag(1/L, 1/L, 1/L, 1, 1, 1)`` (K_rr / L^2, K_rt / L, K_tt: every entry in
    N/m), the length-balanced compliance ``S^-1 C S^-1``. Condition numbers, the
    singularity test and relative matrix differences use it.

Change of frame (paper eq. 13-16)
    Frame B sees frame A rotated by ``R_ba`` (A components -> B components), and the
    origin of A sits at ``p`` from the origin of B (in B components). Then twists map
    with ``T = [[R, 0], [hat(p) R, R]]`` (``twist_b_from_twist_a``), wrenches with
    ``Gamma T Gamma = T^{-T}`` and stiffness matrices as ``K_b = T^{-T} K_a T^{-1}``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

# defined in core.names (no numpy: the CLI's --help uses it), re-exported here
from ppm_stiffness.core.names import DEFAULT_REFERENCE_FORCE as DEFAULT_REFERENCE_FORCE

FloatArray = NDArray[np.float64]
#: Boolean arrays (masks: reachable, valid, ...).
BoolArray = NDArray[np.bool_]

#: The 6x6 permutation that swaps the rotational and translational halves (eq. 6).
GAMMA: FloatArray = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])

#: The unit vector of the z axis, normal to the plane of motion.
Z_AXIS: FloatArray = np.array([0.0, 0.0, 1.0])

#: Length [m] that balances rotational against translational coordinates (above).
LENGTH_SCALE = 0.1
#: The diagonal of ``S``: the balanced stiffness is ``S K S`` (module doc).
BALANCE: FloatArray = np.array([1 / LENGTH_SCALE] * 3 + [1.0] * 3)
#: The diagonal of ``S^-1`` = (L, L, L, 1, 1, 1): a twist's balanced form is
#: ``(omega L, v)`` = ``TWIST_BALANCE * t`` [m] (a wrench's is ``BALANCE * w`` = (m / L, f) [N]).
TWIST_BALANCE: FloatArray = 1.0 / BALANCE

#: The name of each twist component when it dominates a mode or a twist, in order.
DIRECTION_NAMES = (
    "rotation about x",
    "rotation about y",
    "rotation about z",
    "x translation",
    "y translation",
    "z translation",
)

#: Names of the six twist / wrench components, in order.
TWIST_COMPONENTS = ("phi_x", "phi_y", "phi_z", "x", "y", "z")
#: SI unit of each twist component.
TWIST_UNITS = ("rad", "rad", "rad", "m", "m", "m")
#: SI unit of each wrench component.
WRENCH_UNITS = ("N·m", "N·m", "N·m", "N", "N", "N")


def length_balanced(stiffness: ArrayLike) -> FloatArray:
    """Length-balanced stiffness ``S K S`` (K_rr / L^2, K_rt / L, K_tt), shape (..., 6, 6)."""
    k = np.asarray(stiffness, dtype=float)
    return np.asarray(k * BALANCE[:, None] * BALANCE[None, :])


def length_balanced_compliance(compliance: ArrayLike) -> FloatArray:
    """Length-balanced compliance ``S^-1 C S^-1`` (the inverse of :func:`length_balanced`)."""
    c = np.asarray(compliance, dtype=float)
    return np.asarray(c / BALANCE[:, None] / BALANCE[None, :])


def hat(vector: ArrayLike) -> FloatArray:
    """Cross-product matrix (CPM) of a 3-vector: ``hat(a) @ b == cross(a, b)``.

    Parameters
    ----------
    vector : array_like, shape (..., 3)

    Returns
    -------
    ndarray, shape (..., 3, 3)
    """
    a = np.asarray(vector, dtype=float)
    out = np.zeros(a.shape[:-1] + (3, 3))
    out[..., 0, 1] = -a[..., 2]
    out[..., 0, 2] = a[..., 1]
    out[..., 1, 0] = a[..., 2]
    out[..., 1, 2] = -a[..., 0]
    out[..., 2, 0] = -a[..., 1]
    out[..., 2, 1] = a[..., 0]
    return out


def vect(matrix: ArrayLike) -> FloatArray:
    """Axial vector of the skew part of a 3x3 matrix (inverse of :func:`hat`).

    ``vect(A) = 0.5 * [a32 - a23, a13 - a31, a21 - a12]``.
    """
    a = np.asarray(matrix, dtype=float)
    return 0.5 * np.stack(
        [
            a[..., 2, 1] - a[..., 1, 2],
            a[..., 0, 2] - a[..., 2, 0],
            a[..., 1, 0] - a[..., 0, 1],
        ],
        axis=-1,
    )


def cross(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """``a x b`` along the last axis, shapes (..., 3) broadcast: the same products and
    differences as ``np.cross`` (bit for bit), without its per-call cost (about 25 us,
    most of a single pose's chain geometry), in plain floats for one pair of vectors."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    shape = np.broadcast_shapes(a.shape, b.shape)
    if a.size == 3 and b.size == 3:
        a0, a1, a2 = a.ravel().tolist()
        b0, b1, b2 = b.ravel().tolist()
        return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0]).reshape(shape)
    out = np.empty(shape)
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def rotation_z(angle: ArrayLike) -> FloatArray:
    """Rotation matrix about z by ``angle`` [rad]; shape (..., 3, 3)."""
    c = np.cos(np.asarray(angle, dtype=float))
    s = np.sin(np.asarray(angle, dtype=float))
    out = np.zeros(c.shape + (3, 3))
    out[..., 0, 0] = c
    out[..., 0, 1] = -s
    out[..., 1, 0] = s
    out[..., 1, 1] = c
    out[..., 2, 2] = 1.0
    return out


def rotation_screw(axis: ArrayLike, point: ArrayLike) -> FloatArray:
    """Unit twist of a rotation about ``axis`` through ``point``: ``(a, c x a)``.

    Parameters
    ----------
    axis : array_like, shape (..., 3), unit vector in F_b.
    point : array_like, shape (..., 3), position relative to the reference point [m].

    Returns
    -------
    ndarray, shape (..., 6)
    """
    a = np.asarray(axis, dtype=float)
    c = np.asarray(point, dtype=float)
    a, c = np.broadcast_arrays(a, c)
    return np.concatenate([a, cross(c, a)], axis=-1)


def translation_screw(axis: ArrayLike) -> FloatArray:
    """Unit twist of a translation along ``axis``: ``(0, a)``; shape (..., 6)."""
    a = np.asarray(axis, dtype=float)
    return np.concatenate([np.zeros_like(a), a], axis=-1)


def twist_b_from_twist_a(rotation_ba: ArrayLike, origin_a_in_b: ArrayLike) -> FloatArray:
    """Matrix ``T`` of eq. (13) mapping twist coordinates of frame A to frame B.

    Parameters
    ----------
    rotation_ba : array_like, shape (3, 3)
        Rotation taking A components to B components (the paper's Q).
    origin_a_in_b : array_like, shape (3,)
        Origin of A relative to the origin of B, in B components [m] (the paper's d).

    Returns
    -------
    ndarray, shape (6, 6)
    """
    r = np.asarray(rotation_ba, dtype=float)
    t = np.zeros((6, 6))
    t[:3, :3] = r
    t[3:, 3:] = r
    t[3:, :3] = hat(origin_a_in_b) @ r
    return t


def wrench_b_from_wrench_a(rotation_ba: ArrayLike, origin_a_in_b: ArrayLike) -> FloatArray:
    """Matrix mapping wrench coordinates of frame A to frame B: ``Gamma T Gamma``.

    Equal to ``inv(T).T`` so that the power ``w @ t`` is frame invariant.
    """
    return GAMMA @ twist_b_from_twist_a(rotation_ba, origin_a_in_b) @ GAMMA


def stiffness_b_from_stiffness_a(
    stiffness_a: ArrayLike, rotation_ba: ArrayLike, origin_a_in_b: ArrayLike
) -> FloatArray:
    """Express a 6x6 stiffness matrix in frame B (eq. 16).

    ``K_b = (Gamma T Gamma) K_a T^{-1}``.

    Parameters
    ----------
    stiffness_a : array_like, shape (6, 6), in frame A (SI, this module's order).
    rotation_ba, origin_a_in_b : see :func:`twist_b_from_twist_a`.

    Returns
    -------
    ndarray, shape (6, 6)
    """
    t = twist_b_from_twist_a(rotation_ba, origin_a_in_b)
    w = GAMMA @ t @ GAMMA
    return np.asarray(w @ np.asarray(stiffness_a, dtype=float) @ np.linalg.inv(t))
