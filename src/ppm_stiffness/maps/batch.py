"""Batched stiffness, decoupling and principal stiffnesses of planar designs.

Three paths give the same numbers as the single-pose API (:mod:`ppm_stiffness.model`,
:func:`ppm_stiffness.core.decoupling.decouple` with ``method="paper"``):

**The planar engine** (:func:`planar_engine_entries`, any planar joint chain: every
shipped leg type, redundant designs): the general model in closed form per in-plane and
out-of-plane block over arrays of poses (:mod:`ppm_stiffness.legs.planar`), about 10x
the general path; ``"auto"`` takes it when a design has no reduced form. The batched
loaded state under a wrench (:func:`ppm_stiffness.maps.loaded.loaded_poses`, which
imports this module, never the reverse) runs the same engine through
:mod:`ppm_stiffness.statics.structures`.

**The general path** (the reference; :func:`general_stiffness`, any architecture). Per
chunk of poses and per leg: the batched inverse kinematics ``leg.solve(poses)``, the
reachability mask ``leg.reachable`` (IK solvable and every joint coordinate within its
limits), and only at the reachable poses the joint chain ``leg.chain``, its virtual springs
(:func:`ppm_stiffness.legs.chain.leg_springs`) and the bordered inverse of eq. (1)
(:func:`ppm_stiffness.core.solver.bordered_stiffness`); K is the sum over legs
(N, 6, 6). Poses where a leg's IK has no solution never reach the solver, so no NaN
leaks into the results: they are masked. A chunk whose batched bordered inverse fails
is redone pose by pose and the failing poses are masked. Memory: about 6 kB per pose
and leg (the (m, m) spring compliances, m ~ 22-28), bounded by
:data:`GENERAL_CHUNK` poses per chunk.

**The reduced path** (P-P-R legs). When every leg offers an exact reduced form
(:meth:`ppm_stiffness.legs.base.LegModel.reduced_form`, today the P-P-R leg:
:mod:`ppm_stiffness.legs.types._ppr_reduced`), the same model is evaluated in closed
form, about 100x faster:

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
the length-balanced K, and both to the single-pose path to 1e-10.

**Principal stiffnesses** (both paths). For a planar K (in-plane and out-of-plane
blocks uncoupled, as every shipped leg type gives) the paper's decoupling has a closed
form (:func:`principal_from_entries`): ``d_z = 0``, ``k_phi = K'_rr[2, 2]`` and
``(k_x, k_y)`` the eigenvalues of the in-plane 2x2 block of K_tt, each assigned to the
axis its eigenvector is closest to (as
:func:`~ppm_stiffness.core.decoupling.principal_axes`). A K that is not planar to
1e-12 (length-balanced) is decoupled pose by pose with
:func:`~ppm_stiffness.core.decoupling.decouple`.

**Singularity mask** (every path): the test of the single-pose API, K finite and the
transmission index of :mod:`ppm_stiffness.core.singularity` above
``SINGULARITY_TOLERANCE`` (the legs' transmitted wrenches span every direction; the
joints' geometry decides, not the parts' stiffness). Each path builds the legs'
summed projector ``Pi``: by blocks from the reduced legs' wrenches (P-P-R; at constant
phi it is the same at every position) or from the planar engine's wrench bases, in
6-D from the passive twists on the general path; the decision is
:func:`~ppm_stiffness.core.singularity.nonsingular` of
:func:`~ppm_stiffness.core.singularity.transmission_index` (by blocks:
:func:`~ppm_stiffness.core.singularity.nonsingular_blocks`, which clears most poses
with a cheap bound).

Poses are arrays (..., 3) = (x [m], y [m], phi [rad]); matrices are at P with the axes
of F_b in the order of :mod:`ppm_stiffness.core.conventions`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import (
    BoolArray,
    FloatArray,
    hat,
    length_balanced,
    vect,
)
from ppm_stiffness.core.decoupling import decouple
from ppm_stiffness.core.errors import (
    DesignError,
    InputDataError,
)
from ppm_stiffness.core.singularity import (
    Vec3,
    block_projector,
    leg_projector,
    nonsingular,
    nonsingular_blocks,
    transmission_index,
)
from ppm_stiffness.core.solver import leg_compliance_at_platform
from ppm_stiffness.design import Design
from ppm_stiffness.legs import planar as engine
from ppm_stiffness.legs.base import LegPose
from ppm_stiffness.legs.chain import leg_springs
from ppm_stiffness.maps.reduced_leg import (
    IN_PLANE,
    OUT_OF_PLANE,
    ReducedLeg,
    reduce_design,
    reduce_leg,
    reduced_design,
)
from ppm_stiffness.model import actuator_stiffness_vector, transmission_blocks
from ppm_stiffness.statics.structures import bordered_or_nan, take

__all__ = [
    "IN_PLANE",
    "OUT_OF_PLANE",
    "ReducedLeg",
    "reduce_design",
    "reduce_leg",
    "reduced_design",
]

#: Poses per chunk of the general path (about 6 kB per pose and leg of temporaries).
GENERAL_CHUNK = 4096
#: Poses per chunk of the reduced path (about 1 kB per pose).
REDUCED_CHUNK = 65536
#: Largest length-balanced in-plane/out-of-plane coupling, relative to the largest
#: entry, for which K counts as planar (closed-form decoupling).
PLANAR_TOLERANCE = 1e-12

#: Poses per chunk of the planar engine (about 2 kB per pose of temporaries).
PLANAR_CHUNK = 16384

Path = Literal["auto", "reduced", "planar", "general"]


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


def _finite(e: PlanarEntries) -> BoolArray:
    finite = np.isfinite(e.k22)
    for value in e[1:]:
        finite = finite & np.isfinite(value)
    return np.asarray(finite)


def nonsingular_from_entries(stiffness: PlanarEntries, projector: PlanarEntries) -> BoolArray:
    """Boolean array: False exactly where the single-pose API refuses the pose as singular
    (:func:`ppm_stiffness.model.stiffness_at_pose`): K not finite, or the transmission
    index of ``Pi`` at or below the tolerance (:mod:`ppm_stiffness.core.singularity`).

    Parameters
    ----------
    stiffness : PlanarEntries
        K's entries; their shape is the batch shape.
    projector : PlanarEntries
        ``Pi``'s entries (broadcastable to it): :func:`reduced_projector` or the planar
        engine's (:func:`planar_engine_entries`).
    """
    shape = np.shape(stiffness.k22)
    pi = [np.broadcast_to(np.asarray(v, dtype=float), shape) for v in projector]
    return np.asarray(_finite(stiffness) & nonsingular_blocks(list(pi[:6]), list(pi[6:]), shape))


def nonsingular_from_matrices(stiffness: ArrayLike, projector: ArrayLike) -> BoolArray:
    """Boolean array (...): False exactly where the single-pose API refuses the pose as
    singular, from K (..., 6, 6) and the legs' summed projector ``Pi`` (..., 6, 6) (any
    K, planar or not)."""
    k = np.asarray(stiffness, dtype=float)
    finite = np.all(np.isfinite(k), axis=(-2, -1))
    return np.asarray(finite & nonsingular(transmission_index(projector)))


def _solve_chunk(
    design: Design, poses: ArrayLike, actuator_stiffness: ArrayLike
) -> tuple[FloatArray, list[LegPose], BoolArray]:
    """Per-pose actuator stiffness (n, n_legs), every leg's inverse kinematics and the
    reachability mask (n,) of a chunk of poses (n, 3)."""
    p = np.asarray(poses, dtype=float)
    n = p.shape[0]
    k_act = np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), (n, len(design.legs)))
    leg_poses = [leg.solve(p) for leg in design.legs]
    reach = np.ones(n, dtype=bool)
    for leg, lp in zip(design.legs, leg_poses, strict=True):
        reach &= np.asarray(leg.reachable(lp), dtype=bool)
    return k_act, leg_poses, reach


def general_stiffness(
    design: Design, poses: ArrayLike, actuator_stiffness: ArrayLike
) -> tuple[FloatArray, FloatArray, BoolArray]:
    """Stiffness at poses by the general model (any leg type), one chunk.

    Parameters
    ----------
    design : Design
    poses : array_like, shape (n, 3)
        (x [m], y [m], phi [rad]) of P in F_b.
    actuator_stiffness : array_like, shape (n, n_legs) or (n_legs,)
        Per pose and leg [N/m, or N·m/rad for a rotary actuator].

    Returns
    -------
    stiffness : ndarray (n, 6, 6)
        K at P, axes of F_b (SI); zero where not reachable, NaN where a leg's bordered
        matrix is singular.
    projector : ndarray (n, 6, 6)
        The legs' summed projector ``Pi`` (:mod:`ppm_stiffness.core.singularity`);
        zero where not reachable.
    reachable : ndarray of bool (n,)
        Every leg's IK solvable and its joint coordinates within limits.
    """
    k_act, leg_poses, reach = _solve_chunk(design, poses, actuator_stiffness)
    n = reach.size
    total = np.zeros((n, 6, 6))
    pi = np.zeros((n, 6, 6))
    index = np.flatnonzero(reach)
    if index.size == 0:
        return total, pi, reach
    sub = np.zeros((index.size, 6, 6))
    sub_pi = np.zeros((index.size, 6, 6))
    for i, (leg, lp) in enumerate(zip(design.legs, leg_poses, strict=True)):
        springs = leg_springs(leg.chain(take(lp, index)), k_act[index, i])
        c6 = leg_compliance_at_platform(springs.screws, springs.compliance)
        sub += bordered_or_nan(c6, springs.passive)
        sub_pi += leg_projector(springs.passive)
    total[index] = sub
    pi[index] = sub_pi
    return total, pi, reach


def planar_engine_entries(
    design: Design, poses: ArrayLike, actuator_stiffness: ArrayLike
) -> tuple[PlanarEntries, PlanarEntries, BoolArray] | None:
    """Stiffness entries at poses by the planar engine (:mod:`ppm_stiffness.legs.planar`),
    one chunk.

    Same inputs as :func:`general_stiffness`. Returns the planar entries of K (n,)
    (meaningless where not reachable), those of the legs' summed projector ``Pi``
    (:mod:`ppm_stiffness.core.singularity`) and the reachability mask, or None when a
    leg's chain is not planar at these poses (use :func:`general_stiffness`). Poses
    where a leg's reduced compliance is singular give non-finite entries (masked by
    :func:`nonsingular_from_entries`).
    """
    k_act, leg_poses, reach = _solve_chunk(design, poses, actuator_stiffness)
    n = reach.size
    index: np.ndarray | None = None
    if not reach.all():
        index = np.flatnonzero(reach)
        leg_poses = [take(lp, index) for lp in leg_poses]
        k_act = k_act[index]
    legs, found = [], []
    with np.errstate(all="ignore"):
        for i, (leg, lp) in enumerate(zip(design.legs, leg_poses, strict=True)):
            blocks = engine.leg_blocks(leg.chain(lp))
            if blocks is None:
                return None
            found.append(blocks)
            k_leg: engine.Scalar = k_act[:, i]
            if k_act.shape[0] and np.all(k_act[:, i] == k_act[0, i]):
                k_leg = float(k_act[0, i])  # one value for every pose: a constant
            legs.append(engine.leg_stiffness_blocks(blocks, k_leg))
        total_in, total_out = engine.sum_blocks(legs)
        pi_in, pi_out = transmission_blocks(found)
    m = n if index is None else index.size

    def spread(entries: list[engine.Scalar]) -> PlanarEntries:
        values = [np.broadcast_to(np.asarray(v, dtype=float), (m,)) for v in entries]
        if index is not None:
            full = []
            for v in values:
                f = np.zeros(n)
                f[index] = v
                full.append(f)
            values = full
        return PlanarEntries(*values)

    return spread(total_in + total_out), spread(pi_in + pi_out), reach


def is_planar(stiffness: ArrayLike) -> BoolArray:
    """Mask (...): K has no in-plane/out-of-plane coupling, to :data:`PLANAR_TOLERANCE`
    relative to its largest entry, on the length-balanced matrix."""
    kb = length_balanced(stiffness)
    mixed = kb[..., list(IN_PLANE), :][..., list(OUT_OF_PLANE)]
    scale = np.max(np.abs(kb), axis=(-2, -1))
    return np.asarray(np.max(np.abs(mixed), axis=(-2, -1)) <= PLANAR_TOLERANCE * scale)


def principal_from_matrices(stiffness: ArrayLike) -> Principal:
    """The paper's decoupling and principal stiffnesses of matrices (n, 6, 6).

    Closed form (:func:`principal_from_entries`) where K is planar (:func:`is_planar`);
    elsewhere :func:`~ppm_stiffness.core.decoupling.decouple` pose by pose (k_phi =
    f_rr[2], k_x, k_y, k_z = f_tt). Only finite matrices should be passed.
    """
    k = np.asarray(stiffness, dtype=float)
    with np.errstate(all="ignore"):
        pr = principal_from_entries(entries_from_matrices(k))
    planar = is_planar(k)
    if np.all(planar):
        return pr
    fields = [np.array(v, dtype=float, copy=True) for v in pr]
    for n in np.flatnonzero(~planar):
        dec = decouple(k[n], "paper")
        values = (dec.d[0], dec.d[1], dec.rotational_values[2], *dec.translational_values)
        for field, value in zip(fields, values, strict=True):
            field[n] = value
    return Principal(*fields)


def select_path(design: Design, path: Path = "auto") -> tuple[ReducedLeg, ...] | None:
    """The reduced legs to use, or None for the planar engine or the general path.

    ``"auto"``: the reduced path when every leg offers it, else the planar engine;
    ``"planar"``: the planar engine (:func:`planar_engine_entries`, falling back to the
    general path for chains that are not planar); ``"general"``: always the general
    path (the reference); ``"reduced"``: the reduced path or :class:`DesignError`.
    """
    if path in ("general", "planar"):
        return None
    if path == "reduced":
        return reduce_design(design)
    if path == "auto":
        return reduced_design(design)
    raise InputDataError(f"path must be 'auto', 'reduced', 'planar' or 'general', got {path!r}")


@dataclass(frozen=True)
class BatchResult:
    """Stiffness of many poses (SI). Arrays have the batch shape of the poses.

    Attributes
    ----------
    valid : ndarray of bool
        Reachable (joint limits) and not singular (the transmission index of
        :mod:`ppm_stiffness.core.singularity`, K finite): where
        :func:`ppm_stiffness.model.stiffness_at_pose` returns.
    reachable : ndarray of bool
        Every leg's IK solvable and its joint coordinates within limits.
    k_phi, k_x, k_y : numpy.ma.MaskedArray
        Principal stiffnesses [N·m/rad, N/m, N/m], masked where not valid.
    d : ndarray (..., 3) [m]
        The paper's decoupling shift (zero where not valid).
    stiffness : ndarray (..., 6, 6) or None
        The matrices (zero where not valid), when asked for.
    path : {"reduced", "planar", "general"}
        Which path computed them ("general" if any chunk needed it).
    """

    valid: BoolArray
    reachable: BoolArray
    k_phi: np.ma.MaskedArray
    k_x: np.ma.MaskedArray
    k_y: np.ma.MaskedArray
    d: FloatArray
    stiffness: FloatArray | None
    path: str = "reduced"


def _masked(values: FloatArray, valid: BoolArray) -> np.ma.MaskedArray:
    data = np.where(valid, values, np.nan)
    return np.ma.MaskedArray(data, mask=~valid, fill_value=np.nan)


def _per_pose_actuator_stiffness(
    design: Design, actuator_stiffness: ArrayLike | None, batch: tuple[int, ...], n: int
) -> FloatArray:
    """Actuator stiffness (n, n_legs) from None (locked), (n_legs,) or (..., n_legs)."""
    n_legs = len(design.legs)
    if actuator_stiffness is None:
        return np.broadcast_to(actuator_stiffness_vector(design, None), (n, n_legs))
    k_in = np.asarray(actuator_stiffness, dtype=float)
    try:
        k_act = np.broadcast_to(k_in, batch + (n_legs,)).reshape(n, n_legs)
    except ValueError:
        raise DesignError(
            f"actuator stiffness of shape {k_in.shape} does not fit {n} poses of {n_legs} legs"
        ) from None
    if not np.all(np.isfinite(k_act)) or np.any(k_act <= 0):
        raise DesignError("actuator stiffness must be finite and > 0")
    return k_act


def chunk_result(
    design: Design,
    legs: tuple[ReducedLeg, ...] | None,
    poses: FloatArray,
    actuator_stiffness: FloatArray,
    planar: bool,
    matrices: bool = True,
) -> tuple[FloatArray | None, BoolArray, BoolArray, Principal, str]:
    """One chunk of poses (n, 3) with actuator stiffness (n, n_legs) or (n_legs,).

    ``legs``: the reduced path; otherwise the planar engine when ``planar`` (and the
    chains are planar), else the general path.

    Returns
    -------
    stiffness : ndarray (n, 6, 6) or None
        [SI]; None on the reduced and planar paths unless ``matrices``.
    reachable, valid : ndarray of bool (n,)
    principal : Principal, arrays (n,) (meaningless where not valid)
    path : {"reduced", "planar", "general"}
        The path used.
    """
    found: tuple[PlanarEntries, PlanarEntries, BoolArray] | None = None
    used = "general"
    if legs is not None:
        x, y, ph = poses[:, 0], poses[:, 1], poses[:, 2]
        with np.errstate(all="ignore"):
            e, reach = planar_entries(legs, x, y, ph, actuator_stiffness)
            found = e, reduced_projector(legs, ph), reach
        used = "reduced"
    elif planar:
        found = planar_engine_entries(design, poses, actuator_stiffness)
        used = "planar" if found is not None else "general"
    if found is not None:
        e, pi, reach = found
        with np.errstate(all="ignore"):
            pr = principal_from_entries(e)
            valid = reach & nonsingular_from_entries(e, pi)
        return (assemble(e) if matrices else None), reach, valid, pr, used
    k, pi_m, reach = general_stiffness(design, poses, actuator_stiffness)
    valid = reach & nonsingular_from_matrices(k, pi_m)
    safe = np.where(valid[:, None, None], k, np.eye(6))  # no NaN into the closed forms
    pr = principal_from_matrices(safe)
    return k, reach, valid, pr, used


def evaluate_poses(
    design: Design,
    poses: ArrayLike,
    actuator_stiffness: ArrayLike | None = None,
    *,
    matrices: bool = False,
    chunk_size: int | None = None,
    path: Path = "auto",
) -> BatchResult:
    """Stiffness, paper decoupling and principal stiffnesses at many poses.

    Parameters
    ----------
    design : Design
        Any architecture.
    poses : array_like, shape (..., 3)
        (x [m], y [m], phi [rad]) of P in F_b.
    actuator_stiffness : array_like, shape (n_legs,) or (..., n_legs), optional
        [N/m, or N·m/rad for a rotary actuator]; each leg's locked value when None.
    matrices : bool
        Also return the 6x6 matrices (memory: 288 bytes per pose).
    chunk_size : int, optional
        Poses evaluated at once (bounds the temporary memory); default
        :func:`default_chunk` by the path.
    path : {"auto", "reduced", "planar", "general"}
        :func:`select_path`: ``"auto"`` takes the fastest exact path (the reduced form,
        else the planar engine, else the general path).

    Returns
    -------
    BatchResult
        Same numbers as :func:`ppm_stiffness.model.stiffness_at_pose` and
        :func:`ppm_stiffness.core.decoupling.decouple` (to rounding), masked where the
        single-pose path raises.

    Raises
    ------
    InputDataError
        Poses not of shape (..., 3) or not finite; unknown path.
    DesignError
        Actuator stiffnesses of the wrong shape or not finite and positive; or
        ``path="reduced"`` for a design whose legs offer no reduced form.
    """
    p = np.asarray(poses, dtype=float)
    if p.shape[-1:] == (6,) and design.planar:  # full poses of a planar design
        if np.any(p[..., 2:5] != 0):
            raise InputDataError("a planar design's poses have z = rx = ry = 0")
        p = p[..., [0, 1, 5]]
    if p.shape[-1:] != (3,):
        raise InputDataError(f"poses must have shape (..., 3), got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise InputDataError("poses must be finite")
    batch = p.shape[:-1]
    flat = p.reshape(-1, 3)
    n = flat.shape[0]
    k_act = _per_pose_actuator_stiffness(design, actuator_stiffness, batch, n)
    legs = select_path(design, path)
    planar = path != "general"
    if chunk_size is None:
        chunk_size = default_chunk(legs, planar)
    step = max(int(chunk_size), 1)
    used: set[str] = set()
    valid = np.zeros(n, dtype=bool)
    reach = np.zeros(n, dtype=bool)
    out = np.zeros((5, n))
    mats = np.zeros((n, 6, 6)) if matrices else None
    for start in range(0, n, step):
        sl = slice(start, min(start + step, n))
        k, r, ok, pr, how = chunk_result(design, legs, flat[sl], k_act[sl], planar, matrices)
        used.add(how)
        valid[sl], reach[sl] = ok, r
        for row, values in enumerate((pr.k_phi, pr.k_x, pr.k_y, pr.d_x, pr.d_y)):
            out[row, sl] = values
        if mats is not None and k is not None:
            mats[sl] = np.where(ok[:, None, None], k, 0.0)
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
        path="general" if "general" in used or not used else used.pop(),
    )


def default_chunk(legs: tuple[ReducedLeg, ...] | None, planar: bool = True) -> int:
    """Poses per chunk by path: :data:`REDUCED_CHUNK`, :data:`PLANAR_CHUNK` or
    :data:`GENERAL_CHUNK`."""
    if legs is not None:
        return REDUCED_CHUNK
    return PLANAR_CHUNK if planar else GENERAL_CHUNK


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
