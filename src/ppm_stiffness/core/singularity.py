"""Singular poses, judged by the stiffness that is lost, not by its spread.

With its actuator rigid, leg i transmits the wrenches reciprocal to its passive-joint
twists ``Q_i`` (``q . w = 0`` for every passive twist q: the power is ``w . t``). Its
stiffness is ``K_i = W_i (W_i^T C_i W_i)^-1 W_i^T`` with ``W_i`` a basis of those
wrenches (eq. 1; the actuator is one of the springs in ``C_i``), and with every spring
of finite positive stiffness ``W_i^T C_i W_i`` is positive definite, so that
``x^T K x = 0`` iff ``W_i^T x = 0`` for every leg: **K = sum K_i is positive definite
iff the legs' transmitted wrenches together span R^6**. Whether a pose is singular is
therefore a question about the joints' geometry, not about how stiff the parts are.

The measure, the *transmission index*

    tau = lambda_min(Pi) / lambda_max(Pi),   Pi = sum_i Pi_i,

with ``Pi_i`` the orthogonal projector onto leg i's transmitted wrenches in
length-balanced components (:data:`~ppm_stiffness.core.conventions.BALANCE`: wrenches
``(m / L, f)``, twists ``(omega L, v)``, so that reciprocity is orthogonality and
``Pi_i = 1 - Q~_i Q~_i^+``). ``tau`` lies in [0, 1], is 0 exactly at a singular pose,
does not depend on the basis chosen for each leg's wrenches, and does not depend on
the springs at all: a structure 10^12 times stiffer has the same ``tau`` (the
rigid-structure limit is accepted, where the spread of K's eigenvalues grows without
bound). It bounds the stiffness the platform keeps: ``K~_i >= k_i Pi_i`` with ``k_i``
the leg's softest stiffness along the wrenches it transmits, so
``lambda_min(K~) >= min_i k_i * tau * lambda_max(Pi)`` (K~ the length-balanced K).

A pose is singular when ``tau <= SINGULARITY_TOLERANCE`` (a condition number of Pi
above 10^6: of the matrix of unit transmitted wrenches, above 10^3), or when K is not
finite (a leg whose passive twists are dependent, or that is rigid along a wrench it
transmits). :func:`nonsingular` is that decision; :func:`transmission_index` computes
``tau`` for any joint chain in 3-D from the 6x6 sum of projectors
(:func:`leg_projector`). Planar legs split into in-plane (phi_z, x, y) and
out-of-plane (phi_x, phi_y, z) blocks; the fast paths build ``Pi`` by blocks
(:func:`block_projector`) and decide with :func:`nonsingular_blocks`, which clears most
poses by a cheap bound and hands the others to :func:`transmission_index`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BALANCE, BoolArray, FloatArray

#: A pose is singular when the transmission index (module doc) is at or below this.
SINGULARITY_TOLERANCE = 1e-6

#: One entry of a block: an array over poses, or a float that holds at every pose.
Scalar = FloatArray | float
#: A block vector (three components of a twist or wrench).
Vec3 = tuple[Scalar, Scalar, Scalar]
#: A symmetric 3x3 block as its upper triangle (00, 01, 02, 11, 12, 22).
Sym3 = list[Scalar]

_PAIRS = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


def basis_projector(basis: ArrayLike) -> FloatArray:
    """Projector ``Pi_i`` from a basis W (..., 6, r) of the leg's transmitted wrenches
    (m, f) [N·m, N] that is orthonormal in length-balanced components (as
    :mod:`ppm_stiffness.legs.engine` gives it): ``W~ W~^T`` with ``W~ = (m / L, f)``;
    NaN where the basis is."""
    w = np.asarray(basis, dtype=float) * BALANCE[:, None]
    return np.asarray(w @ np.swapaxes(w, -1, -2))


def leg_projector(passive: ArrayLike) -> FloatArray:
    """Projector ``Pi_i`` onto the wrenches a leg transmits with its actuator rigid.

    Parameters
    ----------
    passive : array_like, shape (..., 6, p)
        Unit twists of the leg's passive joints at P, axes of F_b [rad, m].

    Returns
    -------
    ndarray, shape (..., 6, 6)
        ``1 - Q~ Q~^+`` in length-balanced components (module doc), dimensionless.
    """
    q = np.asarray(passive, dtype=float) / BALANCE[:, None]  # (omega L, v)
    eye = np.eye(6)
    if q.shape[-1] == 0:
        return np.broadcast_to(eye, q.shape[:-2] + (6, 6)).copy()
    return np.asarray(eye - q @ np.linalg.pinv(q))


def block_projector(basis: Sequence[Vec3], components: Sequence[int]) -> Sym3:
    """Projector onto the span of one block's transmitted wrenches (upper triangle).

    Parameters
    ----------
    basis : sequence of 0 to 3 block vectors
        A basis of the wrenches a leg transmits in this block (components of the
        6-vector ``components``, in that order), entries arrays (n,) or floats.
    components : sequence of 3 int
        Which wrench components the block holds (e.g. (2, 3, 4): m_z, f_x, f_y).

    Returns
    -------
    list of 6 entries
        The length-balanced projector: 0 for no wrench, ``u u^T`` for one (u the unit
        balanced wrench), ``1 - n n^T`` for two (n the unit normal of their plane),
        1 for three.
    """
    s = [float(BALANCE[c]) for c in components]
    w = [tuple(s[k] * v[k] for k in range(3)) for v in basis]
    if len(w) == 0:
        return [0.0] * 6
    if len(w) == 3:
        return [1.0, 0.0, 0.0, 1.0, 0.0, 1.0]
    if len(w) == 1:
        u = w[0]
    else:
        a, b = w
        u = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    norm2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2]
    outer = [u[i] * u[j] / norm2 for i, j in _PAIRS]
    if len(w) == 1:
        return outer
    eye = [1.0, 0.0, 0.0, 1.0, 0.0, 1.0]
    return [e - o for e, o in zip(eye, outer, strict=True)]


def transmission_index(projector: ArrayLike) -> FloatArray:
    """The transmission index ``tau = lambda_min / lambda_max`` of ``Pi`` (module doc).

    Parameters
    ----------
    projector : array_like, shape (..., 6, 6)
        ``Pi``, the sum of the legs' :func:`leg_projector`.

    Returns
    -------
    ndarray, shape (...)
        In [0, 1] (to rounding); NaN where ``Pi`` is not finite or is zero.
    """
    p = np.asarray(projector, dtype=float)
    finite = np.all(np.isfinite(p), axis=(-2, -1))
    safe = np.where(finite[..., None, None], p, 0.0)
    eig = np.linalg.eigvalsh(safe)
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = eig[..., 0] / eig[..., -1]
    return np.asarray(np.where(finite & (eig[..., -1] > 0), tau, np.nan))


def nonsingular(index: ArrayLike) -> BoolArray:
    """The decision: True where ``tau > SINGULARITY_TOLERANCE`` (False where NaN)."""
    tau = np.asarray(index, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.asarray(tau > SINGULARITY_TOLERANCE)


def assemble_blocks(
    inplane: Sym3, outplane: Sym3, shape: tuple[int, ...], out: FloatArray | None = None
) -> FloatArray:
    """The full symmetric matrices (*shape, 6, 6) of two blocks (upper triangles): the
    in-plane block on components (2, 3, 4), the out-of-plane one on (0, 1, 5); written
    into ``out`` (zeros elsewhere) when given."""
    if out is None:
        out = np.zeros(shape + (6, 6))
    for block, idx in ((inplane, (2, 3, 4)), (outplane, (0, 1, 5))):
        for value, (i, j) in zip(block, _PAIRS, strict=True):
            out[..., idx[i], idx[j]] = value
            out[..., idx[j], idx[i]] = value
    return out


def _block_bounds(s: Sym3) -> tuple[FloatArray, FloatArray]:
    """For a symmetric 3x3 block: ``4 det / tr^2``, a lower bound of its smallest
    eigenvalue when it is positive definite (-inf otherwise), and its trace, an upper
    bound of its largest eigenvalue when positive semi-definite."""
    a, b, c, d, f, g = (np.asarray(v, dtype=float) for v in s)
    det = a * (d * g - f * f) - b * (b * g - f * c) + c * (b * f - d * c)
    trace = a + d + g
    pd = (a > 0) & (a * d - b * b > 0) & (det > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        bound = np.where(pd, 4.0 * det / (trace * trace), -np.inf)
    return bound, trace


def _float_bounds(
    a: float, b: float, c: float, d: float, f: float, g: float
) -> tuple[float, float]:
    """:func:`_block_bounds` of one block of Python floats."""
    det = a * (d * g - f * f) - b * (b * g - f * c) + c * (b * f - d * c)
    trace = a + d + g
    pd = a > 0 and a * d - b * b > 0 and det > 0
    return (4.0 * det / (trace * trace) if pd else -math.inf), trace


def nonsingular_blocks(inplane: Sym3, outplane: Sym3, shape: tuple[int, ...]) -> BoolArray:
    """:func:`nonsingular` of :func:`transmission_index` for a block-diagonal ``Pi``.

    ``tau >= min(4 det / tr^2 over both blocks) / max(trace)``: poses where that
    bound exceeds the tolerance are nonsingular at once; the others get the exact
    index of the assembled 6x6 matrix.

    Parameters
    ----------
    inplane, outplane : Sym3
        The blocks of ``Pi`` (:func:`block_projector` summed over legs), entries
        broadcastable to ``shape``.
    shape : tuple of int
        The batch shape.
    """
    if shape == () and all(type(v) is float for v in (*inplane, *outplane)):
        # one pose in plain float arithmetic (the single-pose API): the same bound
        bounds = [_float_bounds(*blk) for blk in (inplane, outplane)]  # type: ignore[arg-type]
        if min(b[0] for b in bounds) > SINGULARITY_TOLERANCE * max(b[1] for b in bounds):
            return np.array(True)
        return nonsingular(transmission_index(assemble_blocks(inplane, outplane, ())))
    lb_in, tr_in = _block_bounds(inplane)
    lb_out, tr_out = _block_bounds(outplane)
    with np.errstate(invalid="ignore"):
        sure = np.minimum(lb_in, lb_out) > SINGULARITY_TOLERANCE * np.maximum(tr_in, tr_out)
    sure = np.broadcast_to(sure, shape)
    result = np.array(sure, dtype=bool, copy=True)
    if not np.all(sure):
        unsure = ~sure
        blocks = [
            [np.broadcast_to(np.asarray(v, dtype=float), shape)[unsure] for v in blk]
            for blk in (inplane, outplane)
        ]
        count = int(np.count_nonzero(unsure))
        pi = assemble_blocks(list(blocks[0]), list(blocks[1]), (count,))
        result[unsure] = nonsingular(transmission_index(pi))
    return result
