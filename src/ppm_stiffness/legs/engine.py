"""The batched engine: the stiffness of any joint chain at many poses, block by block.

The same model as the definition (:func:`ppm_stiffness.legs.chain.leg_springs` and
:func:`ppm_stiffness.core.solver.leg_stiffness`), evaluated without the leg's dense
spring matrices. A leg transmits the wrenches W (6 x r) reciprocal to its passive
twists (``r = 6 - p``); its stiffness is

    K = W (A + v v^T / k_act)^-1 W^T,   A = sum_b G_b^T C_b G_b,   v = W^T a,

where each block b of springs (a joint's hardware springs, a link's cantilever of eq.
3c) has its unit twists J_b at P and compliance C_b, ``G_b = J_b^T W`` are the wrenches
W expressed in the block's own frame, and a is the actuator's unit twist. ``A`` is the
compliance of the leg's structure against the wrenches it transmits with a rigid
actuator (what :class:`LegReduction` holds): the loaded statics reuse it.

Every array has one batch axis (n,); points and axes of the chain may be (n, 3) or
constant (3,). Twists and wrenches at P, axes of F_b, SI.

The basis. W is an orthonormal basis, in length-balanced units
(:data:`ppm_stiffness.core.conventions.LENGTH_SCALE`), of the wrenches reciprocal to
the passive twists; K does not depend on which (``W -> W T`` cancels). The passive
twists are taken at a reference point c, the point of the passive joint with the most
rotational freedoms: its rotations have no translation part there, and when it is a
spherical joint they span every rotation about c, so that W is made of forces through
c and only the translation parts of the other twists need a QR (Householder,
:mod:`ppm_stiffness.legs._soa`, whose remainders test the twists' dependence). W is
then made orthonormal at P. A pose whose passive twists are dependent (a remainder at
most :data:`DEPENDENT_TOLERANCE` times the twist's norm, at c) gets NaN entries, which
callers mask as singular.

Evaluation. The poses are taken :data:`CHUNK` at a time, "structure of arrays": every
scalar entry of a point, axis, twist or small matrix is one contiguous array of the
chunk's poses, or a Python float when it holds at every pose (constant geometry, exact
zeros skipped), so that the work is elementwise numpy arithmetic on short arrays; at
one pose (n = 1) every entry is a float. Points and axes shared by several elements of
the chain (the same array object) are read once. The blocks' compliances are applied
by :mod:`ppm_stiffness.legs._forms` (a cantilever from its entries' monomials in the
length; equal compliances about the axes of a frame through ``|x|^2``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.beam import cantilever_compliance
from ppm_stiffness.core.conventions import LENGTH_SCALE, FloatArray
from ppm_stiffness.core.errors import DesignError, SingularConfigurationError
from ppm_stiffness.core.solver import elastic_stiffness
from ppm_stiffness.legs import _forms as forms
from ppm_stiffness.legs import _soa as soa
from ppm_stiffness.legs._soa import Scalar, Vec
from ppm_stiffness.legs.chain import (
    Element,
    Joint,
    Link,
    check_chain,
    elastic_stiffnesses,
    freedom_count,
    freedom_screws,
    parallel_stiffness,
)
from ppm_stiffness.legs.joint_kinds import joint_kind

#: Smallest norm of a passive twist's remainder (length-balanced, at the reference
#: point, after removing the twists before it) relative to its norm, for the passive
#: joints to count as independent.
DEPENDENT_TOLERANCE = 1e-10
#: Poses evaluated together: their arrays stay in the processor's caches
#: (benchmarks/bench_engine.py).
CHUNK = 4096


@dataclass(frozen=True)
class LegReduction:
    """One leg at n poses, reduced to the wrenches it transmits (module doc).

    Attributes
    ----------
    basis : ndarray (n, 6, r)
        W: wrenches (m, f) the leg transmits with a rigid actuator, reciprocal to its
        passive twists; orthonormal in length-balanced units.
    compliance : ndarray (n, r, r)
        A = W^T S W: the structure's compliance (actuator excluded) against them.
    actuator : ndarray (n, r)
        v = W^T a.
    twist : ndarray (n, 6)
        a, the actuated joint's unit twist at P.
    elastic : ndarray (n, r, e) or None
        H = W^T J_e for the chain's elastic freedoms (:mod:`ppm_stiffness.core.solver`);
        None: none.
    elastic_stiffness : ndarray (n, e) or None
        Their stiffnesses [N·m/rad or N/m].
    parallel : float
        The elastic stiffness in parallel with the actuator (its joint's, 0 without).
    """

    basis: FloatArray
    compliance: FloatArray
    actuator: FloatArray
    twist: FloatArray
    elastic: FloatArray | None = None
    elastic_stiffness: FloatArray | None = None
    parallel: float = 0.0


def reciprocal_basis(passive: Sequence[FloatArray], n: int) -> FloatArray:
    """W (n, 6, 6 - p) reciprocal to the passive twists (each (n, 6)), orthonormal in
    length-balanced units; NaN where the twists are dependent (module doc; the twists
    as given, at P)."""
    if len(passive) > 6:
        raise DesignError(f"{len(passive)} passive twists: a leg has at most 6 freedoms")
    out = np.empty((n, 6, 6 - len(passive)))
    if n == 1:  # one pose: the same operations on Python floats (no per-call numpy cost)
        scalar_twists: list[Vec] = [np.asarray(q, dtype=float).reshape(6).tolist() for q in passive]
        columns, bad = soa.householder_complement(
            [[soa.mul(LENGTH_SCALE, x) for x in q[:3]] + q[3:] for q in scalar_twists],
            DEPENDENT_TOLERANCE,
        )
        for j, y in enumerate(columns):
            w = [soa.mul(LENGTH_SCALE, x) for x in y[:3]] + y[3:]
            out[0, :, j] = [soa.where(bad, math.nan, x) for x in w]
        return out
    with np.errstate(divide="ignore", invalid="ignore"):
        for lo in range(0, n, CHUNK):
            hi = min(n, lo + CHUNK)
            twists = [list(np.asarray(q, dtype=float)[lo:hi].T.copy()) for q in passive]
            columns, bad = soa.householder_complement(
                [[soa.mul(LENGTH_SCALE, x) for x in q[:3]] + q[3:] for q in twists],
                DEPENDENT_TOLERANCE,
            )
            for j, y in enumerate(columns):
                w = [soa.mul(LENGTH_SCALE, x) for x in y[:3]] + y[3:]
                soa.stack([soa.where(bad, math.nan, x) for x in w], out[lo:hi, :, j])
    return out


def _reference(chain: Sequence[Element]) -> int | None:
    """Index of the passive joint with the most rotational freedoms (the last of
    equals), or None if no passive joint rotates."""
    best, ref = 0, None
    for i, element in enumerate(chain):
        if isinstance(element, Joint) and not element.actuated and element.elastic is None:
            count = joint_kind(element.kind).rotations
            if count and count >= best:
                best, ref = count, i
    return ref


def _orthonormal_at_p(columns: list[list[Vec]], ref: Vec | None) -> list[list[Vec]]:
    """Columns ``[m_c, f]`` (moment about the reference point c, force) of a basis,
    made orthonormal in length-balanced units at P (Gram-Schmidt); each returned as
    ``[m_c, f, m]`` with m the moment about P."""
    out: list[list[Vec]] = []
    weight = 1.0 / LENGTH_SCALE**2

    def inner(a: list[Vec], b: list[Vec]) -> Scalar:
        return soa.add(soa.mul(weight, soa.dot(a[2], b[2])), soa.dot(a[1], b[1]))

    for m_c, f in columns:
        m = (
            m_c
            if ref is None
            else [soa.add(a, b) for a, b in zip(m_c, soa.cross(ref, f), strict=True)]
        )
        col = [m_c, f, m]
        for prev in out:
            d = inner(col, prev)
            col = [soa.axpy(a, d, b) for a, b in zip(col, prev, strict=True)]
        scale = soa.recip(soa.sqrt(inner(col, col)))
        out.append([[soa.mul(scale, x) for x in v] for v in col])
    return out


def _wrenches(
    chain: Sequence[Element], placed: list[tuple[soa.Frame, Scalar]]
) -> tuple[list[list[Vec]], Callable[[Vec], Vec], Vec]:
    """W at one chunk (module doc): columns ``[m_c, f, m]``, the offset ``q - c`` of a
    point of the chain from the reference point, and the actuated joint's twist a."""
    index = _reference(chain)
    ref = None if index is None else placed[index][0].point
    offsets: dict[int, Vec] = {} if ref is None else {id(ref): [0.0, 0.0, 0.0]}

    def offset(point: Vec) -> Vec:
        if id(point) not in offsets:
            offsets[id(point)] = (
                point if ref is None else [soa.sub(a, b) for a, b in zip(point, ref, strict=True)]
            )
        return offsets[id(point)]

    twist: Vec = [0.0] * 6
    passive: list[Vec] = []
    all_rotations: soa.Mask | None = None
    for i, (element, (frame, norm)) in enumerate(zip(chain, placed, strict=True)):
        if not isinstance(element, Joint):
            continue
        record = joint_kind(element.kind)
        directions = record.freedoms
        if i == index and record.spherical:
            all_rotations = norm > 0.0  # every rotation about c where its frame exists
            continue
        axes = frame.axes() if any(k for _, k in directions) else [frame.e1]
        if element.actuated:
            kind, k = directions[0]
            twist = soa.twist(kind, frame.point, axes[k])
            continue
        if element.elastic is not None:  # not passive: kept by the bordered solve
            continue
        free = [
            soa.twist(kind, offset(frame.point), axes[k], LENGTH_SCALE) for kind, k in directions
        ]
        passive = free + passive if i == index else passive + free
    columns, bad = soa.householder_complement(passive, DEPENDENT_TOLERANCE, all_rotations)
    basis = _orthonormal_at_p(
        [[[soa.mul(LENGTH_SCALE, x) for x in y[:3]], y[3:]] for y in columns], ref
    )
    if soa.any_true(bad):
        basis = [[[soa.where(bad, math.nan, x) for x in v] for v in col] for col in basis]
    return basis, offset, twist


def _reduce(
    chain: Sequence[Element], geo: soa.Geometry
) -> tuple[list[Vec], list[Scalar], Vec, Vec]:
    """W (columns), A (upper triangle), v and a at one chunk of poses."""
    placed = [geo.frame(e) for e in chain]
    basis, offset, twist = _wrenches(chain, placed)
    r = len(basis)
    acc: list[Scalar] = [0.0] * (r * (r + 1) // 2)
    forces = [col[1] for col in basis]
    cache = forms.Projections()
    moments: dict[int, list[Vec]] = {}
    for element, (frame, length) in zip(chain, placed, strict=True):
        terms: Sequence[forms.Term]
        if isinstance(element, Link):
            monomials = forms.cantilever_terms(element.section)
            terms = (
                monomials
                if monomials is not None
                else forms.full_terms(cantilever_compliance(element.section, length))
            )
        elif element.springs is not None:
            springs = _chunk_springs(np.asarray(element.springs, dtype=float), geo)
            terms = forms.spring_terms(springs, joint_kind(element.kind).constrained)
        else:
            continue
        key = id(frame.point)
        if key not in moments:  # moments about the element's point: m_c - d x f
            d = offset(frame.point)
            moments[key] = [
                soa.cross(f, d)
                if soa.is_zero(m_c)
                else [soa.sub(a, b) for a, b in zip(m_c, soa.cross(d, f), strict=True)]
                for m_c, f, _ in basis
            ]
        forms.add_block(acc, terms, length, frame, (moments[key], forces), cache)
    w = [col[2] + col[1] for col in basis]
    return w, acc, [soa.dot(x, twist) for x in w], twist


def _chunk_springs(k: FloatArray, geo: soa.Geometry) -> list[Scalar]:
    """A joint's springs at the chunk's poses: a float per direction where the same at
    every pose (all of them, usually), else the chunk's slice."""
    if k.ndim == 1:
        return list(k.tolist())
    rows = k.reshape(-1, k.shape[-1])
    out: list[Scalar] = []
    for column in rows.T:
        if rows.shape[0] == 1 or bool(np.all(column == column[0])):
            out.append(float(column[0]))
        else:
            out.append(float(column[geo.lo]) if geo.scalar else column[geo.lo : geo.hi])
    return out


def reduce_chain(chain: Sequence[Element], n: int) -> LegReduction:
    """A leg's chain at n poses reduced to its transmitted wrenches (module doc).

    Parameters
    ----------
    chain : sequence of Joint and Link
        Base to platform; points and axes (n, 3) or (3,), relative to P, axes of F_b.
    n : int
        Number of poses.
    """
    check_chain(chain)
    p = sum(
        freedom_count(e)
        for e in chain
        if isinstance(e, Joint) and not e.actuated and e.elastic is None
    )
    if p > 6:
        raise DesignError(f"a leg with {p} passive freedoms (at most 6)")
    r = 6 - p
    basis = np.empty((n, 6, r))
    compliance = np.empty((n, r, r))
    actuator = np.empty((n, r))
    twist = np.empty((n, 6))
    with np.errstate(divide="ignore", invalid="ignore"):
        for lo in range(0, n, CHUNK):
            hi = min(n, lo + CHUNK)
            w, acc, v, a = _reduce(chain, soa.Geometry(lo, hi))
            for j, col in enumerate(w):
                soa.stack(col, basis[lo:hi, :, j])
            k = 0
            for i in range(r):
                for j in range(i, r):
                    compliance[lo:hi, i, j] = compliance[lo:hi, j, i] = acc[k]
                    k += 1
            soa.stack(v, actuator[lo:hi])
            soa.stack(a, twist[lo:hi])
    return LegReduction(basis, compliance, actuator, twist, *_elastic(chain, basis))


def _elastic(
    chain: Sequence[Element], basis: FloatArray
) -> tuple[FloatArray | None, FloatArray | None, float]:
    """H = W^T J_e (n, r, e), the stiffnesses (n, e) of the chain's elastic freedoms
    (None, None without any) and the stiffness in parallel with the actuator."""
    n = basis.shape[0]
    twists, stiffness = [], []
    for element in chain:
        if isinstance(element, Joint) and not element.actuated and element.elastic is not None:
            k = elastic_stiffnesses(element)
            assert k is not None
            f = k.size
            twists.append(np.broadcast_to(freedom_screws(element), (n, 6, f)))
            stiffness.append(np.broadcast_to(k, (n, f)))
    parallel = parallel_stiffness(chain)
    if not twists:
        return None, None, parallel
    j_e = np.concatenate(twists, axis=-1)
    return np.swapaxes(basis, -1, -2) @ j_e, np.concatenate(stiffness, axis=-1), parallel


def _elastic_leg_stiffness(reduction: LegReduction, k_inv: FloatArray | None) -> FloatArray:
    """K (n, 6, 6) of a leg with elastic freedoms: the bordered form of
    :func:`ppm_stiffness.core.solver.elastic_stiffness`; NaN where it is singular or
    not finite."""
    assert reduction.elastic is not None and reduction.elastic_stiffness is not None
    m = reduction.compliance
    if k_inv is not None:
        v = reduction.actuator
        m = m + v[:, :, None] * v[:, None, :] * k_inv[:, None, None]
    out = np.full((m.shape[0], 6, 6), np.nan)
    good = np.isfinite(m).all(axis=(1, 2)) & np.isfinite(reduction.basis).all(axis=(1, 2))
    try:  # the usual case: one batched solve
        out[good] = elastic_stiffness(
            reduction.basis[good],
            m[good],
            reduction.elastic[good],
            reduction.elastic_stiffness[good],
        )
        return out
    except SingularConfigurationError:
        pass
    for i in np.flatnonzero(good):
        try:
            out[i] = elastic_stiffness(
                reduction.basis[i],
                m[i],
                reduction.elastic[i],
                reduction.elastic_stiffness[i],
            )
        except SingularConfigurationError:
            continue
    return out


def _by_inverse(m: FloatArray, w: FloatArray) -> FloatArray:
    """``W M^-1 W^T`` (n, 6, 6) symmetrised, by the inverse; NaN where M is singular or
    not finite."""
    out = np.full((m.shape[0], 6, 6), np.nan)
    for i in np.flatnonzero(np.isfinite(m).all(axis=(1, 2))):
        try:
            k = w[i] @ np.linalg.inv(m[i]) @ w[i].T
        except np.linalg.LinAlgError:
            continue
        out[i] = 0.5 * (k + k.T)
    return out


def leg_stiffness(reduction: LegReduction, actuator_stiffness: ArrayLike | None) -> FloatArray:
    """A leg's stiffness (n, 6, 6) at P with the actuator stiffness (n,) or scalar
    [N/m or N·m/rad]; None: a rigid actuator.

    With the Cholesky factor ``M = A + v v^T / k = R^T R`` (entry by entry),
    ``K = U U^T`` for ``U = W R^-1``: exactly symmetric. Where M has no such factor
    (singular, or not positive: a non-physical actuator), K is taken from the inverse,
    NaN where M is singular or not finite.
    """
    m = reduction.compliance
    n, r = m.shape[0], m.shape[-1]
    if r == 0 or n == 0:
        return np.zeros((n, 6, 6))
    k_inv = (
        None
        if actuator_stiffness is None
        else 1.0
        / (np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), (n,)) + reduction.parallel)
    )
    if reduction.elastic is not None:
        return _elastic_leg_stiffness(reduction, k_inv)
    v = reduction.actuator
    w = np.ascontiguousarray(reduction.basis.transpose(2, 1, 0))  # (r, 6, n)
    factor: list[list[FloatArray]] = []  # R[j][i - j], i >= j
    cols: list[FloatArray] = []  # the columns of U, (6, n) each
    out = np.empty(0)
    ok = np.ones(n, dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        for j in range(r):
            row = []
            for i in range(j, r):
                mji = m[:, j, i] if k_inv is None else m[:, j, i] + v[:, j] * v[:, i] * k_inv
                for k in range(j):
                    mji = mji - factor[k][j - k] * factor[k][i - k]
                row.append(mji)
            ok &= (row[0] > 0.0) & (row[0] < math.inf)  # False where NaN
            pivot = np.sqrt(row[0])
            inv = 1.0 / pivot
            factor.append([pivot] + [x * inv for x in row[1:]])
            u = w[j]
            for k in range(j):
                u = u - factor[k][j - k] * cols[k]
            cols.append(u * inv)
            # each term a fresh array (not np.zeros: calloc'd pages fault when written)
            term = np.einsum("in,jn->nij", cols[j], cols[j])
            out = term if j == 0 else out + term
    if not ok.all():
        bad = ~ok
        m_bad = m[bad]
        if k_inv is not None:
            vb = v[bad]
            m_bad = m_bad + vb[:, :, None] * vb[:, None, :] * k_inv[bad][:, None, None]
        out[bad] = _by_inverse(m_bad, reduction.basis[bad])
    return out


def platform_stiffness(
    reductions: Sequence[LegReduction], actuator_stiffness: ArrayLike
) -> FloatArray:
    """K (n, 6, 6) at P: the sum of the legs' (eq. 4); ``actuator_stiffness`` (n, n_legs)
    or (n_legs,)."""
    k_act = np.asarray(actuator_stiffness, dtype=float)
    total = leg_stiffness(reductions[0], k_act[..., 0])
    for i, red in enumerate(reductions[1:], start=1):
        total += leg_stiffness(red, k_act[..., i])
    return total
