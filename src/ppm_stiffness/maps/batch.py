"""Batched stiffness, decoupling and principal stiffnesses of planar P-P-R designs.

The single-pose path (:mod:`ppm_stiffness.model`) builds 22 spring screws per leg and
inverts a 9x9 bordered matrix. For a map of 10^6 poses that costs ~60 us per pose even
when batched with numpy, dominated by building the (..., 6, 22) screws and the
(..., 22, 22) compliances. This module evaluates the *same* model from a reduced form
that is exact for P-P-R legs:

The reduced form of a leg lives in :mod:`ppm_stiffness.maps.reduced_leg`:

1. Everything in a leg is rigidly attached to its rod, seen from the platform point D:
   the bearing C sits at ``-L w`` from D (L the rod free length), the guide block and
   the proximal link are a constant offset further away, the directions u, w, z never
   change. Expressed at D (axes of F_b) the leg's spring compliance is therefore a
   cubic polynomial in L plus the actuator term: ``C_D(L) = sum_k P_k L^k + e e^T / k_act``
   (guide, proximal link and bearing contribute up to L^2 through their lever arms,
   the rod cantilever up to L^3).
2. The passive joints seen from D (rotation about w through C, translation along w,
   revolute at D) do not depend on the pose, so neither does the basis W_D of the
   wrenches the leg transmits (reciprocal to the passive joints). The leg stiffness is
   the reduced form of eq. (1): ``K_i = W (W^T C W)^{-1} W^T`` with ``W = G(d) W_D`` the
   basis moved from D to P (``d = D - P`` depends on phi only).
3. A planar design splits into in-plane (phi_z, x, y) and out-of-plane
   (phi_x, phi_y, z) motions: per leg ``W^T C W`` is a scalar (the compliance along
   the one in-plane force the leg transmits) plus a 2x2 block. Inverting them is a
   division and a 2x2 adjugate.

The polynomial coefficients are computed once per design *from the general model
itself* (:func:`ppm_stiffness.legs.ppr.leg_springs` at two rod lengths, the rod block of
:func:`ppm_stiffness.core.beam.cantilever_compliance` interpolated at four lengths), so the
two paths cannot drift apart silently; tests compare them to 1e-10 relative.

Decoupling and principal stiffnesses follow :func:`ppm_stiffness.core.decoupling.decouple`
with ``method="paper"`` in closed form for the planar block structure: ``d_z = 0``,
``k_phi = K'_rr[2, 2]`` and ``(k_x, k_y)`` the eigenvalues of the in-plane 2x2 block of
K_tt, each assigned to the axis its eigenvector is closest to (as
:func:`~ppm_stiffness.core.decoupling.principal_axes`).

Poses are arrays (..., 3) = (x [m], y [m], phi [rad]); matrices are at P with the axes
of F_b in the order of :mod:`ppm_stiffness.core.conventions`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import (
    LENGTH_SCALE,
    FloatArray,
    hat,
    length_balanced,
    vect,
)
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.maps.reduced_leg import (
    IN_PLANE,
    OUT_OF_PLANE,
    ReducedLeg,
    reduce_design,
    reduce_leg,
)
from ppm_stiffness.model import SINGULARITY_TOLERANCE, actuator_stiffness_vector

__all__ = ["IN_PLANE", "OUT_OF_PLANE", "ReducedLeg", "reduce_design", "reduce_leg"]

#: Rotations are balanced at 0.1 m in the singularity test, as in model.check_nonsingular.


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


def leg_kinematics(
    leg: ReducedLeg, x: ArrayLike, y: ArrayLike, phi: ArrayLike
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Platform point ``d = D - P`` (x, y parts), actuator coordinate and rod length.

    Same expressions as :meth:`ppm_stiffness.legs.types.ppr.PPRLeg.solve` (the 2x2
    solve ``D - A = rho u + (bearing_offset + rod) w``); arrays broadcast.
    """
    ang = leg.psi + np.asarray(phi, dtype=float)
    dx = -leg.radius * np.cos(ang)
    dy = -leg.radius * np.sin(ang)
    px = (np.asarray(x, dtype=float) + dx) - leg.base_point[0]
    py = (np.asarray(y, dtype=float) + dy) - leg.base_point[1]
    det = leg.u[0] * leg.w[1] - leg.u[1] * leg.w[0]
    rho = (px * leg.w[1] - py * leg.w[0]) / det
    rod = (leg.u[0] * py - leg.u[1] * px) / det - leg.bearing_offset
    return dx, dy, np.asarray(rho), np.asarray(rod)


def planar_entries(
    legs: tuple[ReducedLeg, ...],
    x: ArrayLike,
    y: ArrayLike,
    phi: ArrayLike,
    actuator_stiffness: ArrayLike,
) -> tuple[PlanarEntries, FloatArray]:
    """Stiffness entries and reachability at poses given as broadcastable arrays.

    Parameters
    ----------
    legs : from :func:`reduce_design`
    x, y, phi : array_like, broadcastable [m, m, rad]
    actuator_stiffness : array_like, shape (n_legs,) or broadcastable (..., n_legs) [N/m]

    Returns
    -------
    entries : PlanarEntries, arrays of the broadcast shape
    reachable : ndarray of bool, same shape (strokes and rod ranges respected)
    """
    k_act = np.asarray(actuator_stiffness, dtype=float)
    ph = np.asarray(phi, dtype=float)
    acc: list[FloatArray | float] = [0.0] * 12
    reachable: FloatArray | bool = True
    for i, leg in enumerate(legs):
        dx, dy, rho, rod = leg_kinematics(leg, x, y, ph)
        reachable = (
            reachable
            & (rho >= leg.stroke[0])
            & (rho <= leg.stroke[1])
            & (rod >= leg.rod_length_range[0])
            & (rod <= leg.rod_length_range[1])
        )
        # in-plane: one transmitted force; its wrench moved from D to P
        mz, fx, fy = leg.in_basis
        q = (mz + dx * fy - dy * fx, fx, fy)
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
        wb = leg.out_basis
        cols = [
            (wb[0, j] + dy * wb[2, j], wb[1, j] - dx * wb[2, j], wb[2, j]) for j in range(2)
        ]
        for n, (a, b) in enumerate(_PAIRS, start=6):
            acc[n] = acc[n] + (
                inv[0] * (cols[0][a] * cols[0][b])
                + inv[1] * (cols[0][a] * cols[1][b] + cols[1][a] * cols[0][b])
                + inv[2] * (cols[1][a] * cols[1][b])
            )
    shape = np.broadcast_shapes(np.shape(x), np.shape(y), ph.shape, k_act.shape[:-1])
    entries = PlanarEntries(*(np.broadcast_to(np.asarray(a, dtype=float), shape) for a in acc))
    return entries, np.broadcast_to(np.asarray(reachable, dtype=bool), shape)


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


class Principal(NamedTuple):
    """Paper decoupling (eq. 19) and principal stiffnesses, arrays of one shape.

    d_x, d_y [m] the shift (d_z = 0 for a planar design); k_phi [N·m/rad] = K'_rr[2, 2];
    k_x, k_y [N/m] the in-plane eigenvalues of K_tt assigned to the nearest axis;
    k_z = K_tt[2, 2] [N/m].
    """

    d_x: FloatArray
    d_y: FloatArray
    k_phi: FloatArray
    k_x: FloatArray
    k_y: FloatArray
    k_z: FloatArray


def principal_from_entries(e: PlanarEntries) -> Principal:
    """Closed-form :func:`ppm_stiffness.core.decoupling.decouple` (paper) for planar K.

    ``M = (tr(K_tt) 1 - K_tt) / 2`` is block diagonal, so ``d = M^{-1} vect(K_rt)`` has
    ``d_z = 0`` and ``K'_rr[2, 2] = K_rr[2, 2] - 2 (K_rt[2,0] d_y - K_rt[2,1] d_x)
    + g^T K_tt g`` with ``g = (-d_y, d_x)``; K'_rr[0:2, 2] vanish. The eigenvalue of
    the in-plane K_tt block whose eigenvector is nearer x is ``k_x`` (ties, when
    K_tt[0,0] == K_tt[1,1] with a nonzero coupling, are resolved towards x = larger).
    """
    m00 = 0.5 * (e.k44 + e.k55)
    m11 = 0.5 * (e.k33 + e.k55)
    m01 = -0.5 * e.k34
    vx = 0.5 * (e.k24 - e.k15)
    vy = 0.5 * (e.k05 - e.k23)
    det = m00 * m11 - m01 * m01
    d_x = (m11 * vx - m01 * vy) / det
    d_y = (m00 * vy - m01 * vx) / det
    k_phi = (
        e.k22
        - 2.0 * (e.k23 * d_y - e.k24 * d_x)
        + (d_y * d_y * e.k33 - 2.0 * d_x * d_y * e.k34 + d_x * d_x * e.k44)
    )
    half = 0.5 * (e.k33 - e.k44)
    mean = 0.5 * (e.k33 + e.k44)
    radius = np.hypot(half, e.k34)
    big = mean + radius
    small = (e.k33 * e.k44 - e.k34 * e.k34) / big
    x_is_big = half >= 0
    k_x = np.where(x_is_big, big, small)
    k_y = np.where(x_is_big, small, big)
    return Principal(d_x, d_y, np.asarray(k_phi), k_x, k_y, np.asarray(e.k55))


def _block_lower_bound(
    a: FloatArray, b: FloatArray, c: FloatArray, d: FloatArray, f: FloatArray, g: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """For symmetric [[a, b, c], [b, d, f], [c, f, g]]: a lower bound of its smallest
    eigenvalue valid when positive (-inf when not positive definite), and its trace (an
    upper bound of its largest eigenvalue when positive definite)."""
    minor2 = a * d - b * b
    det = a * (d * g - f * f) - b * (b * g - f * c) + c * (b * f - d * c)
    trace = a + d + g
    pd = (a > 0) & (minor2 > 0) & (det > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = np.where(pd, det / (trace * trace), -np.inf)
    return bound, trace


def nonsingular_from_entries(e: PlanarEntries) -> FloatArray:
    """Boolean array: False where :func:`ppm_stiffness.model.check_nonsingular` raises.

    A cheap sufficient test (``lambda_min >= det / tr^2`` per positive definite 3x3 block,
    ``lambda_max <= max trace``) accepts most poses; the others get the exact test
    (eigenvalues of the length-balanced 6x6 matrix, same tolerance).
    """
    s1 = LENGTH_SCALE  # length balancing (conventions): K_rr / L^2, K_rt / L
    s2 = s1 * s1
    lb_in, tr_in = _block_lower_bound(
        e.k22 / s2, e.k23 / s1, e.k24 / s1, e.k33, e.k34, e.k44
    )
    lb_out, tr_out = _block_lower_bound(
        e.k00 / s2, e.k01 / s2, e.k05 / s1, e.k11 / s2, e.k15 / s1, e.k55
    )
    finite = np.isfinite(e.k22)
    for value in e[1:]:
        finite &= np.isfinite(value)
    with np.errstate(invalid="ignore"):
        sure = finite & (
            np.minimum(lb_in, lb_out) > SINGULARITY_TOLERANCE * np.maximum(tr_in, tr_out)
        )
    result = np.array(sure, dtype=bool, copy=True)
    unsure = finite & ~sure
    if np.any(unsure):
        k = assemble(PlanarEntries(*(np.asarray(v)[unsure] for v in e)))
        ks = length_balanced(k)
        eig = np.linalg.eigvalsh(ks)
        result[unsure] = eig[..., 0] > SINGULARITY_TOLERANCE * eig[..., -1]
    return result


def actuator_forces_batch(
    legs: tuple[ReducedLeg, ...],
    x: ArrayLike,
    y: ArrayLike,
    phi: ArrayLike,
    wrench: ArrayLike,
    locked_stiffness: float,
) -> FloatArray:
    """Actuator forces [N] under ``wrench`` (m_x..f_z at P, F_b), shape (..., n_legs).

    :func:`ppm_stiffness.statics.loading.actuator_forces` batched: the wrench is shared in
    proportion to the locked leg stiffnesses, ``w_i = K_i K^{-1} w``; the actuator
    carries ``u_i . f_i``. Only the in-plane part of each leg's wrench has a force
    along u, so a 3x3 in-plane solve per pose suffices.
    """
    w = np.asarray(wrench, dtype=float)
    n = len(legs)
    k_lock = np.full(n, locked_stiffness)
    e, _ = planar_entries(legs, x, y, phi, k_lock)
    a, b, c, d_, f, g = e.k22, e.k23, e.k24, e.k33, e.k34, e.k44
    rhs = (w[2], w[3], w[4])
    # adjugate solve of the symmetric in-plane block [[a,b,c],[b,d,f],[c,f,g]] t = rhs
    c00, c01, c02 = d_ * g - f * f, c * f - b * g, b * f - c * d_
    c11, c12, c22 = a * g - c * c, b * c - a * f, a * d_ - b * b
    det = a * c00 + b * c01 + c * c02
    t = (
        (c00 * rhs[0] + c01 * rhs[1] + c02 * rhs[2]) / det,
        (c01 * rhs[0] + c11 * rhs[1] + c12 * rhs[2]) / det,
        (c02 * rhs[0] + c12 * rhs[1] + c22 * rhs[2]) / det,
    )
    forces = []
    for leg in legs:
        dx, dy, _, rod = leg_kinematics(leg, x, y, phi)
        mz, fx, fy = leg.in_basis
        q = (mz + dx * fy - dy * fx, fx, fy)
        s_in = _horner(leg.in_poly, rod) + leg.in_actuator**2 / locked_stiffness
        lam = (q[0] * t[0] + q[1] * t[1] + q[2] * t[2]) / s_in
        forces.append(lam * (fx * leg.u[0] + fy * leg.u[1]))
    shape = np.broadcast_shapes(np.shape(x), np.shape(y), np.shape(phi))
    return np.stack([np.broadcast_to(fv, shape) for fv in forces], axis=-1)


@dataclass(frozen=True)
class BatchResult:
    """Stiffness of many poses (SI). Arrays have the batch shape of the poses.

    Attributes
    ----------
    valid : ndarray of bool
        Reachable (strokes, rod ranges) and nonsingular (model.check_nonsingular).
    reachable : ndarray of bool
    k_phi, k_x, k_y : numpy.ma.MaskedArray
        Principal stiffnesses [N·m/rad, N/m, N/m], masked where not valid.
    d : ndarray (..., 3) [m]
        The paper's decoupling shift (zero where not valid).
    stiffness : ndarray (..., 6, 6) or None
        The matrices (zero where not valid), when asked for.
    """

    valid: FloatArray
    reachable: FloatArray
    k_phi: np.ma.MaskedArray
    k_x: np.ma.MaskedArray
    k_y: np.ma.MaskedArray
    d: FloatArray
    stiffness: FloatArray | None


def _masked(values: FloatArray, valid: FloatArray) -> np.ma.MaskedArray:
    data = np.where(valid, values, np.nan)
    return np.ma.MaskedArray(data, mask=~valid, fill_value=np.nan)


def evaluate_poses(
    design: Design,
    poses: ArrayLike,
    actuator_stiffness: ArrayLike | None = None,
    *,
    matrices: bool = False,
    chunk_size: int = 65536,
) -> BatchResult:
    """Stiffness, paper decoupling and principal stiffnesses at many poses.

    Parameters
    ----------
    design : Design
    poses : array_like, shape (..., 3)
        (x [m], y [m], phi [rad]) of P in F_b.
    actuator_stiffness : array_like, shape (n_legs,) or (..., n_legs), optional
        [N/m]; the locked value when None.
    matrices : bool
        Also return the 6x6 matrices (memory: 288 bytes per pose).
    chunk_size : int
        Poses evaluated at once (bounds the temporary memory).

    Returns
    -------
    BatchResult
        Same numbers as :func:`ppm_stiffness.model.stiffness_at_pose` and
        :func:`ppm_stiffness.core.decoupling.decouple` (to rounding), masked where the
        single-pose path raises.
    """
    p = np.asarray(poses, dtype=float)
    if p.shape[-1:] != (3,):
        raise InputDataError(f"poses must have shape (..., 3), got {p.shape}")
    batch = p.shape[:-1]
    flat = p.reshape(-1, 3)
    n = flat.shape[0]
    n_legs = len(design.legs)
    if actuator_stiffness is None:
        k_act = np.broadcast_to(actuator_stiffness_vector(design, None), (n, n_legs))
    else:
        k_in = np.asarray(actuator_stiffness, dtype=float)
        try:
            k_act = np.broadcast_to(k_in, batch + (n_legs,)).reshape(n, n_legs)
        except ValueError:
            raise DesignError(
                f"actuator stiffness of shape {k_in.shape} does not fit {n} poses "
                f"of {n_legs} legs"
            ) from None
        if not np.all(np.isfinite(k_act)) or np.any(k_act <= 0):
            raise DesignError("actuator stiffness must be finite and > 0 N/m")
    legs = reduce_design(design)
    valid = np.zeros(n, dtype=bool)
    reach = np.zeros(n, dtype=bool)
    out = np.zeros((5, n))
    mats = np.zeros((n, 6, 6)) if matrices else None
    for start in range(0, n, max(int(chunk_size), 1)):
        sl = slice(start, min(start + chunk_size, n))
        x, y, ph = flat[sl, 0], flat[sl, 1], flat[sl, 2]
        with np.errstate(all="ignore"):
            e, r = planar_entries(legs, x, y, ph, k_act[sl])
            pr = principal_from_entries(e)
        ok = r & nonsingular_from_entries(e)
        valid[sl], reach[sl] = ok, r
        for row, values in enumerate((pr.k_phi, pr.k_x, pr.k_y, pr.d_x, pr.d_y)):
            out[row, sl] = values
        if mats is not None:
            mats[sl] = np.where(ok[:, None, None], assemble(e), 0.0)
    d = np.zeros((n, 3))
    d[:, 0] = np.where(valid, out[3], 0.0)
    d[:, 1] = np.where(valid, out[4], 0.0)
    return BatchResult(
        valid=valid.reshape(batch),
        reachable=reach.reshape(batch),
        k_phi=_masked(out[0], valid).reshape(batch),
        k_x=_masked(out[1], valid).reshape(batch),
        k_y=_masked(out[2], valid).reshape(batch),
        d=d.reshape(batch + (3,)),
        stiffness=None if mats is None else mats.reshape(batch + (6, 6)),
    )


def decouple_batch(stiffness: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The paper's decoupling (eq. 19, as :func:`~ppm_stiffness.core.decoupling.decouple`)
    of matrices (..., 6, 6), general (not only planar).

    Returns
    -------
    d : ndarray (..., 3) [m]
    K_rr : ndarray (..., 3, 3) [N·m/rad], K'_rr at the shifted point
    K_tt : ndarray (..., 3, 3) [N/m]
    """
    k = np.asarray(stiffness, dtype=float)
    krr, krt, ktt = k[..., :3, :3], k[..., :3, 3:], k[..., 3:, 3:]
    tr = np.trace(ktt, axis1=-2, axis2=-1)
    m = 0.5 * (tr[..., None, None] * np.eye(3) - ktt)
    d = np.linalg.solve(m, vect(krt)[..., None])[..., 0]
    dd = hat(d)
    krt_t = np.swapaxes(krt, -1, -2)
    new_rr = krr - krt @ dd + dd @ (krt_t - ktt @ dd)
    return d, new_rr, ktt.copy()
