"""Spatial inertia of rigid bodies, and the inertia tensors of simple solids.

A rigid body of mass m, centre of mass c (from the reference point P, axes of F_b) and
inertia tensor I_c about its centre of mass (axes of F_b) moving with the twist
``t = (omega, v)`` at P (:mod:`ppm_stiffness.core.conventions`) has the kinetic energy
``t^T M_b t / 2`` with the spatial inertia at P, in the order (omega, v):

    M_b = [[I_c - m hat(c)^2,  m hat(c)],
           [-m hat(c),         m 1     ]]

(the velocity of the centre of mass is ``v + omega x c = v - hat(c) omega``). It is
symmetric, positive semi-definite, and positive definite when m > 0 and I_c is. Moved
to another reference point it changes by the congruence of the twists' change of
frame, ``M' = T^-T M T^-1`` (:func:`ppm_stiffness.core.conventions
.twist_b_from_twist_a`), as a stiffness matrix does.

Solids (axes of their own frame, about their centre): a solid cylinder of radius r and
height h along z, ``diag(m (3 r^2 + h^2) / 12, same, m r^2 / 2)``; a box of edges
(a, b, c) along x, y, z, ``m diag(b^2 + c^2, a^2 + c^2, a^2 + b^2) / 12``; a uniform
slender rod of length L along the unit axis n, ``m L^2 / 12 (1 - n n^T)``.

Arrays carry leading batch axes (...). SI: kg, m, kg·m^2.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, hat


def spatial_inertia(mass: ArrayLike, centre: ArrayLike, inertia: ArrayLike) -> FloatArray:
    """The spatial inertia M_b (..., 6, 6) at P, order (omega, v) (module doc).

    Parameters
    ----------
    mass : array_like (...) [kg]
    centre : array_like (..., 3) [m]
        Centre of mass relative to P, axes of F_b.
    inertia : array_like (..., 3, 3) [kg·m^2]
        Inertia tensor about the centre of mass, axes of F_b.
    """
    m = np.asarray(mass, dtype=float)
    c = hat(centre)
    i_c = np.asarray(inertia, dtype=float)
    shape = np.broadcast_shapes(m.shape, c.shape[:-2], i_c.shape[:-2])
    mm = np.broadcast_to(m, shape)[..., None, None]
    out = np.empty(shape + (6, 6))
    out[..., :3, :3] = i_c - mm * (c @ c)
    out[..., :3, 3:] = mm * c
    out[..., 3:, :3] = -mm * c
    out[..., 3:, 3:] = mm * np.eye(3)
    return np.asarray(0.5 * (out + np.swapaxes(out, -1, -2)))  # exactly symmetric


def rod_inertia(transverse: ArrayLike, axial: ArrayLike, axis: ArrayLike) -> FloatArray:
    """Inertia tensor (..., 3, 3) of an axisymmetric body about its centre of mass:
    ``transverse (1 - n n^T) + axial n n^T`` for the unit axis n (..., 3)."""
    n = np.asarray(axis, dtype=float)
    nn = n[..., :, None] * n[..., None, :]
    it = np.asarray(transverse, dtype=float)[..., None, None]
    ia = np.asarray(axial, dtype=float)[..., None, None]
    return np.asarray(it * (np.eye(3) - nn) + ia * nn)


def cylinder_inertia(mass: float, radius: float, height: float) -> FloatArray:
    """Inertia tensor (3, 3) of a solid cylinder about its centre, axis along z."""
    transverse = mass * (3.0 * radius**2 + height**2) / 12.0
    return np.diag([transverse, transverse, 0.5 * mass * radius**2])


def box_inertia(mass: float, size: ArrayLike) -> FloatArray:
    """Inertia tensor (3, 3) of a solid box of edges (a, b, c) along x, y, z about its
    centre."""
    a, b, c = (float(v) for v in np.asarray(size, dtype=float))
    return mass / 12.0 * np.diag([b**2 + c**2, a**2 + c**2, a**2 + b**2])


def rotated_inertia(inertia: ArrayLike, rotation: ArrayLike) -> FloatArray:
    """``R I R^T`` (..., 3, 3): an inertia tensor given in a body's axes, in F_b's."""
    r = np.asarray(rotation, dtype=float)
    return np.asarray(r @ np.asarray(inertia, dtype=float) @ np.swapaxes(r, -1, -2))
