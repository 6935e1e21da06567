"""Geometry shared by the spatial leg types (a private module: the leg registry skips
it): universal-joint axes along a leg, joint angles against a mounting axis, and the
constraint of a leg whose revolute keeps it in a plane.

Points and axes are arrays with leading batch axes (..., 3), SI, in F_b unless named.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, cross
from ppm_stiffness.legs.chain import unit

#: Tolerance on the norm of a unit vector given in a design file (and on the
#: orthogonality of two axes that must be normal).
UNIT_TOLERANCE = 1e-6


def check_unit(name: str, value: ArrayLike) -> FloatArray:
    """A design's direction as a unit array (3,), or ValueError naming the key."""
    v = np.asarray(value, dtype=float)
    norm = float(np.linalg.norm(v))
    if not abs(norm - 1.0) <= UNIT_TOLERANCE:
        raise ValueError(
            f"{name} = {v.tolist()}: a direction must be a unit vector (norm {norm:.6g})"
        )
    return v / norm


def check_normal(name_a: str, a: FloatArray, name_b: str, b: FloatArray) -> None:
    """Refuse two unit directions that are not normal to each other."""
    if not abs(float(a @ b)) <= UNIT_TOLERANCE:
        raise ValueError(
            f"{name_b} = {b.tolist()}: must be normal to {name_a} = {a.tolist()} "
            f"(dot product {float(a @ b):.3g})"
        )


def universal_axes(direction: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Axes (e1, e2) of a base universal joint whose leg runs along ``n``: e1 =
    unit(z x n), e2 = n x e1 (so that e1 x e2 = n); e1 = unit(n x x) for a vertical leg."""
    n = unit(direction)
    z = np.broadcast_to(np.array([0.0, 0.0, 1.0]), n.shape)
    e1 = cross(z, n)
    vertical = np.linalg.norm(e1, axis=-1, keepdims=True) < 1e-12
    if np.any(vertical):
        e1 = np.where(vertical, cross(n, np.broadcast_to([1.0, 0.0, 0.0], n.shape)), e1)
    e1 = unit(e1)
    return e1, cross(n, e1)


def joint_angle(direction: ArrayLike, mounting_axis: ArrayLike) -> FloatArray:
    """Angle [rad] (...) between a link ``direction`` and a joint's ``mounting_axis``
    (both (..., 3)), in [0, pi]."""
    d = unit(direction)
    m = unit(mounting_axis)
    cos = np.clip(np.einsum("...i,...i->...", d, np.broadcast_to(m, d.shape)), -1.0, 1.0)
    return np.asarray(np.arccos(cos))


def plane_constraint(
    base_point: FloatArray,
    axis: FloatArray,
    platform_point_abs: FloatArray,
    platform_point: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """Residual ``(B - A) . e`` (..., 1) [m] of a leg kept in the plane through A normal to
    e, and its wrench (..., 6, 1): a unit force along e through B (``b = B - P``)."""
    residual = np.einsum("...i,i->...", platform_point_abs - base_point, axis)[..., None]
    b = np.asarray(platform_point, dtype=float)
    e = np.broadcast_to(axis, b.shape)
    wrench = np.concatenate([cross(b, e), e], axis=-1)[..., None]
    return residual, wrench


def angle_limit(part: object) -> float | None:
    """A joint part's ``max_angle`` [rad], or None (no part, or no limit given)."""
    value = getattr(part, "max_angle", None)
    return None if value is None else float(value)


__all__ = [
    "UNIT_TOLERANCE",
    "angle_limit",
    "check_normal",
    "check_unit",
    "joint_angle",
    "plane_constraint",
    "universal_axes",
]
