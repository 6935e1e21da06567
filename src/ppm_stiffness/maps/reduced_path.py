"""The reduced P-P-R path: the stiffness of a design whose every leg offers an exact
reduced form, in closed form over arrays of poses, about 100x the general path.

When every leg offers an exact reduced form
(:meth:`ppm_stiffness.legs.base.LegModel.reduced_form`, today the P-P-R leg:
:mod:`ppm_stiffness.legs.types._ppr_reduced`), the model is evaluated as follows:

1. Everything in a P-P-R leg is rigidly attached to its rod, seen from the platform
   point D: the leg's spring compliance at D is a cubic polynomial in the rod free
   length L plus the actuator term, ``C_D(L) = sum_k P_k L^k + e e^T / k_act``.
2. The passive joints seen from D do not depend on the pose, so neither does the basis
   W_D of the wrenches the leg transmits: ``K_i = W (W^T C W)^{-1} W^T`` with
   ``W = G(d) W_D`` the basis moved from D to P (``d = D - P`` depends on phi only).
3. A planar design splits into in-plane (phi_z, x, y) and out-of-plane
   (phi_x, phi_y, z) motions: per leg ``W^T C W`` is a scalar plus a 2x2 block.

The polynomial coefficients are computed once per design from the general model
itself, so the two paths cannot drift apart silently; tests compare them to 1e-9 on
the length-balanced K, and both to the single-pose path to 1e-10. K is returned as
its 12 structurally nonzero entries (:class:`PlanarEntries`), the singularity
projector by blocks (:func:`reduced_projector`). Poses are (x [m], y [m], phi [rad]).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.singularity import Vec3, block_projector
from ppm_stiffness.maps.reduced_leg import IN_PLANE, OUT_OF_PLANE, ReducedLeg

#: Poses per chunk of the reduced path (about 1 kB per pose).
REDUCED_CHUNK = 65536


class PlanarEntries(NamedTuple):
    """The 12 structurally nonzero entries of K (upper triangle), arrays of one shape.

    ``k_ij`` is ``K[i, j]`` in the order of :mod:`ppm_stiffness.core.conventions`:
    in-plane (2, 3, 4) and out-of-plane (0, 1, 5) blocks; all others are zero.
    """

    k22: FloatArray
    k23: FloatArray
    k24: FloatArray
    k33: FloatArray
    k34: FloatArray
    k44: FloatArray
    k00: FloatArray
    k01: FloatArray
    k05: FloatArray
    k11: FloatArray
    k15: FloatArray
    k55: FloatArray


#: Upper-triangle index pairs of a 3x3 block, in the order of PlanarEntries' halves.
_PAIRS = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


def _horner(coeffs: FloatArray, x: FloatArray) -> FloatArray:
    out = coeffs[3] * x + coeffs[2]
    out *= x
    out += coeffs[1]
    out *= x
    out += coeffs[0]
    return np.asarray(out)


def planar_entries(
    legs: tuple[ReducedLeg, ...],
    x: ArrayLike,
    y: ArrayLike,
    phi: ArrayLike,
    actuator_stiffness: ArrayLike,
) -> tuple[PlanarEntries, BoolArray]:
    """Stiffness entries and reachability at poses given as broadcastable arrays.

    Parameters
    ----------
    legs : from :func:`reduce_design`
    x, y, phi : array_like, broadcastable [m, m, rad]
    actuator_stiffness : array_like, shape (n_legs,) or broadcastable (..., n_legs)
        [N/m] (the P-P-R actuators are linear).

    Returns
    -------
    entries : PlanarEntries, arrays of the broadcast shape
    reachable : ndarray of bool, same shape (strokes and rod ranges respected)
    """
    k_act = np.asarray(actuator_stiffness, dtype=float)
    ph = np.asarray(phi, dtype=float)
    acc: list[FloatArray | float] = [0.0] * 12
    reachable: BoolArray = np.array(True)
    for i, leg in enumerate(legs):
        dx, dy, rho, rod = leg.kinematics(x, y, ph)
        reachable = reachable & leg.within_limits(rho, rod)
        q, cols = _wrenches_at_p(leg, dx, dy)
        s_in = _horner(leg.in_poly, rod) + leg.in_actuator**2 / k_act[..., i]
        g = 1.0 / s_in
        for n, (a, b) in enumerate(_PAIRS):
            acc[n] = acc[n] + g * (q[a] * q[b])
        # out-of-plane: 2x2 block, inverted by its adjugate
        s00 = _horner(leg.out_poly[:, 0], rod)
        s01 = _horner(leg.out_poly[:, 1], rod)
        s11 = _horner(leg.out_poly[:, 2], rod)
        det = s00 * s11 - s01 * s01
        inv = (s11 / det, -s01 / det, s00 / det)
        for n, (a, b) in enumerate(_PAIRS, start=6):
            acc[n] = acc[n] + (
                inv[0] * (cols[0][a] * cols[0][b])
                + inv[1] * (cols[0][a] * cols[1][b] + cols[1][a] * cols[0][b])
                + inv[2] * (cols[1][a] * cols[1][b])
            )
    shape = np.broadcast_shapes(np.shape(x), np.shape(y), ph.shape, k_act.shape[:-1])
    entries = PlanarEntries(*(np.broadcast_to(np.asarray(a, dtype=float), shape) for a in acc))
    return entries, np.broadcast_to(np.asarray(reachable, dtype=bool), shape)


def _wrenches_at_p(leg: ReducedLeg, dx: FloatArray, dy: FloatArray) -> tuple[Vec3, list[Vec3]]:
    """The wrenches a reduced leg transmits, moved from D to P (``d = D - P`` = (dx,
    dy)): the in-plane one (m_z, f_x, f_y) and the two out-of-plane ones (m_x, m_y,
    f_z)."""
    mz, fx, fy = (float(v) for v in leg.in_basis)
    q: Vec3 = (np.asarray(mz + dx * fy - dy * fx), fx, fy)
    wb = leg.out_basis
    cols: list[Vec3] = [
        (
            np.asarray(wb[0, j] + dy * wb[2, j]),
            np.asarray(wb[1, j] - dx * wb[2, j]),
            float(wb[2, j]),
        )
        for j in range(2)
    ]
    return q, cols


def reduced_projector(legs: tuple[ReducedLeg, ...], phi: ArrayLike) -> PlanarEntries:
    """The legs' summed projector ``Pi`` (:mod:`ppm_stiffness.core.singularity`) of the
    reduced P-P-R legs, entries of the shape of ``phi`` [rad]: the wrenches a P-P-R leg
    transmits at P depend on phi only (``d = D - P``), not on the position."""
    ph = np.asarray(phi, dtype=float)
    p_in: list[FloatArray | float] = [0.0] * 6
    p_out: list[FloatArray | float] = [0.0] * 6
    for leg in legs:
        dx, dy, _, _ = leg.kinematics(0.0, 0.0, ph)
        q, cols = _wrenches_at_p(leg, dx, dy)
        leg_in = block_projector([q], IN_PLANE)
        leg_out = block_projector(cols, OUT_OF_PLANE)
        p_in = [a + b for a, b in zip(p_in, leg_in, strict=True)]
        p_out = [a + b for a, b in zip(p_out, leg_out, strict=True)]
    return PlanarEntries(
        *(np.broadcast_to(np.asarray(a, dtype=float), ph.shape) for a in p_in + p_out)
    )


def assemble(entries: PlanarEntries) -> FloatArray:
    """Full symmetric matrices (..., 6, 6) from the planar entries."""
    shape = np.shape(entries.k22)
    k = np.zeros(shape + (6, 6))
    for name, value in zip(PlanarEntries._fields, entries, strict=True):
        i, j = int(name[1]), int(name[2])
        k[..., i, j] = value
        k[..., j, i] = value
    return k


def entries_from_matrices(stiffness: ArrayLike) -> PlanarEntries:
    """The planar entries of matrices (..., 6, 6) (the other entries are ignored)."""
    k = np.asarray(stiffness, dtype=float)
    return PlanarEntries(*(k[..., int(n[1]), int(n[2])] for n in PlanarEntries._fields))
