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
constant (3,). W is computed by Gram-Schmidt in length-balanced units
(:data:`ppm_stiffness.core.conventions.LENGTH_SCALE`): orthonormalise the passive
twists, then complete with the base vectors of largest remainder. A pose whose passive
twists are dependent (to :data:`DEPENDENT_TOLERANCE`) gets NaN entries, which callers
mask as singular. Twists and wrenches at P, axes of F_b, SI.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.beam import cantilever_compliance
from ppm_stiffness.core.conventions import BALANCE, FloatArray
from ppm_stiffness.legs.chain import (
    CONSTRAINED_DIRECTIONS,
    FREEDOM_DIRECTIONS,
    Direction,
    Element,
    Joint,
    Link,
    check_chain,
    frame_from_axis,
)

#: Smallest norm of a passive twist's remainder (length-balanced, after removing the
#: twists before it) for the passive joints to count as independent.
DEPENDENT_TOLERANCE = 1e-10
#: Length-balancing of twist rows (rotation rows times L): balanced = SCALE * twist.
_SCALE = 1.0 / BALANCE


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
    """

    basis: FloatArray
    compliance: FloatArray
    actuator: FloatArray
    twist: FloatArray


def _vectors(value: ArrayLike, n: int) -> FloatArray:
    return np.broadcast_to(np.asarray(value, dtype=float), (n, 3))


def _frame(element: Joint | Link, n: int) -> tuple[FloatArray, list[FloatArray]]:
    """Point (n, 3) and axes [(n, 3)] * 3 of a joint frame or a link's tip frame."""
    if isinstance(element, Link):
        axis = np.asarray(element.end, dtype=float) - np.asarray(element.start, dtype=float)
        axes = frame_from_axis(axis)
        return _vectors(element.end, n), [_vectors(e, n) for e in axes]
    return _vectors(element.point, n), [_vectors(e, n) for e in element.frame()]


def _twists(
    point: FloatArray, axes: list[FloatArray], directions: Sequence[Direction]
) -> list[FloatArray]:
    """Unit twists (n, 6) of frame directions at a point."""
    out = []
    for kind, k in directions:
        e = axes[k]
        if kind == "r":
            out.append(np.concatenate([e, _cross(point, e)], axis=-1))
        else:
            out.append(np.concatenate([np.zeros_like(e), e], axis=-1))
    return out


def reciprocal_basis(passive: Sequence[FloatArray], n: int) -> FloatArray:
    """W (n, 6, 6 - p) reciprocal to the passive twists (each (n, 6)), orthonormal in
    length-balanced units; NaN where the twists are dependent (module doc).

    Gram-Schmidt on the balanced passive twists gives U (n, 6, p); the projector
    ``I - U U^T`` onto their complement then gives W column by column: the base vector
    with the largest remainder (the largest diagonal entry), normalised, then removed.
    """
    done: list[FloatArray] = []
    bad = np.zeros(n, dtype=bool)
    for q in passive:
        v = q * _SCALE
        size = _norm(v)
        for u in done:
            v = v - _dot(v, u)[:, None] * u
        norm = _norm(v)
        bad |= ~(norm > DEPENDENT_TOLERANCE * size)
        done.append(v / np.where(norm > 0, norm, 1.0)[:, None])
    r = 6 - len(done)
    projector = np.broadcast_to(np.eye(6), (n, 6, 6)).copy()
    if done:
        u = np.stack(done, axis=-1)
        projector -= u @ np.swapaxes(u, -1, -2)
    basis = np.empty((n, 6, r))
    rows = np.arange(n)
    for j in range(r):
        diagonal = np.einsum("nii->ni", projector)
        pick = np.argmax(diagonal, axis=1)
        w = projector[rows, :, pick] / np.sqrt(diagonal[rows, pick])[:, None]
        basis[:, :, j] = w
        if j + 1 < r:
            projector -= w[:, :, None] * w[:, None, :]
    basis *= _SCALE[None, :, None]
    if np.any(bad):
        basis[bad] = np.nan
    return basis


def _dot(a: FloatArray, b: FloatArray) -> FloatArray:
    return np.asarray(np.einsum("ni,ni->n", a, b))


def _norm(a: FloatArray) -> FloatArray:
    return np.sqrt(_dot(a, a))


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    """``a x b`` along axis 1 of (n, 3, ...) arrays (broadcasting)."""
    return np.stack(
        [
            a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1],
            a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
            a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0],
        ],
        axis=1,
    )


def _wrench_in_frame(
    basis: FloatArray, point: FloatArray, axes: list[FloatArray]
) -> tuple[list[FloatArray], list[FloatArray]]:
    """Components (n, r) of each wrench of W in a frame at ``point``: moments about
    e_k through the point, forces along e_k."""
    m, f = basis[:, :3, :], basis[:, 3:, :]
    m_c = m - _cross(point[:, :, None], f)
    rot = [np.einsum("ni,nir->nr", e, m_c) for e in axes]
    tra = [np.einsum("ni,nir->nr", e, f) for e in axes]
    return rot, tra


def _add_outer(
    acc: FloatArray, c: FloatArray | float, g: FloatArray, h: FloatArray | None = None
) -> None:
    """``acc += c g g^T`` (or ``c (g h^T + h g^T)``) for g, h (n, r), c (n,) or float."""
    cc = np.asarray(c, dtype=float)
    cc = cc[:, None, None] if cc.ndim else cc
    if h is None:
        acc += cc * (g[:, :, None] * g[:, None, :])
    else:
        acc += cc * (g[:, :, None] * h[:, None, :] + h[:, :, None] * g[:, None, :])


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
    passive: list[FloatArray] = []
    twist = np.zeros((n, 6))
    for element in chain:
        if isinstance(element, Joint):
            point, axes = _frame(element, n)
            free = _twists(point, axes, FREEDOM_DIRECTIONS[element.kind])
            if element.actuated:
                twist = free[0]
            else:
                passive += free
    basis = reciprocal_basis(passive, n)
    r = basis.shape[-1]
    acc = np.zeros((n, r, r))
    for element in chain:
        point, axes = _frame(element, n)
        rot, tra = _wrench_in_frame(basis, point, axes)
        if isinstance(element, Link):
            length = np.linalg.norm(
                np.asarray(element.end, dtype=float) - np.asarray(element.start, dtype=float),
                axis=-1,
            )
            c = cantilever_compliance(element.section, np.broadcast_to(length, (n,)))
            g = rot + tra
            for i in range(6):
                _add_outer(acc, c[:, i, i], g[i])
            _add_outer(acc, c[:, 2, 4], g[2], g[4])
            _add_outer(acc, c[:, 1, 5], g[1], g[5])
            continue
        if element.springs is None:
            continue
        for k, (kind, axis) in zip(
            np.asarray(element.springs, dtype=float).tolist(),
            CONSTRAINED_DIRECTIONS[element.kind],
            strict=True,
        ):
            if np.isinf(k):
                continue
            _add_outer(acc, 1.0 / k, rot[axis] if kind == "r" else tra[axis])
    actuator = np.einsum("nir,ni->nr", basis, twist)
    return LegReduction(basis, acc, actuator, twist)


def _inverse(m: FloatArray) -> FloatArray:
    """Inverses of (n, r, r) symmetric matrices; NaN where singular or not finite."""
    r = m.shape[-1]
    if r == 0:
        return m.copy()
    if r == 1:
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.asarray(1.0 / m)
    ok = np.all(np.isfinite(m), axis=(1, 2))
    out = np.full(m.shape, np.nan)
    if np.any(ok):
        safe = m[ok]
        try:
            out[ok] = np.linalg.inv(safe)
        except np.linalg.LinAlgError:
            for i, idx in enumerate(np.flatnonzero(ok)):
                try:
                    out[idx] = np.linalg.inv(safe[i])
                except np.linalg.LinAlgError:
                    continue
    return out


def leg_stiffness(reduction: LegReduction, actuator_stiffness: ArrayLike | None) -> FloatArray:
    """A leg's stiffness (n, 6, 6) at P with the actuator stiffness (n,) or scalar
    [N/m or N·m/rad]; None: a rigid actuator."""
    m = reduction.compliance
    if actuator_stiffness is not None:
        k = np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), m.shape[:1])
        v = reduction.actuator
        m = m + (v[:, :, None] * v[:, None, :]) / k[:, None, None]
    w = reduction.basis
    k_leg = w @ _inverse(m) @ np.swapaxes(w, -1, -2)
    return np.asarray(0.5 * (k_leg + np.swapaxes(k_leg, -1, -2)))


def platform_stiffness(
    reductions: Sequence[LegReduction], actuator_stiffness: ArrayLike
) -> FloatArray:
    """K (n, 6, 6) at P: the sum of the legs' (eq. 4); ``actuator_stiffness`` (n, n_legs)
    or (n_legs,)."""
    k_act = np.asarray(actuator_stiffness, dtype=float)
    total = np.zeros(reductions[0].basis.shape[:1] + (6, 6))
    for i, red in enumerate(reductions):
        total += leg_stiffness(red, k_act[..., i])
    return total
