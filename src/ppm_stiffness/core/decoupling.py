"""Decoupling of the stiffness matrix by a shift of the reference point (eq. 12-19).

Shifting the reference point by ``d`` (the origin of the old frame seen from the new
one, ``D = hat(d)``, ``Q = 1``) changes the blocks as eq. (17):
``K'_rr = K_rr - K_rt D + D (K_rt^T - K_tt D)``, ``K'_rt = K_rt + D K_tt``,
``K'_tt = K_tt``. Exact decoupling needs ``K_rt + D K_tt = 0``, possible only when
``K_rt K_tt^{-1}`` is skew-symmetric; in general a residual coupling remains.

Two methods:

``"paper"``
    eq. (19) as printed: ``M d = vect(K_rt)`` with ``M = (tr(K_tt) 1 - K_tt) / 2``.
    It reproduces the paper's (28)-(32). Its sign contradicts (18b), so for the
    paper's (22) it leaves a coupling larger than K_rt itself; K'_rr is then the
    rotational block at a point that is not a centre of stiffness.
``"least-squares"``
    the ``d`` that minimises ``||K_rt + D K_tt||_F`` (linear least squares), with that
    minimum reported: the best decoupling a shift can give.

``residual_coupling = ||K_rt + D K_tt||_F / ||K_rt||_F`` (0 when decoupled exactly).

Already decoupled
    A symmetric design at its symmetric pose has ``K_rt = 0`` up to round-off (~1e-12
    N against ~1e3 N); the ratio above then divides round-off by round-off and says
    nothing. When ``||K_rt||_F <= DECOUPLED_TOLERANCE * sqrt(||K_rr||_F ||K_tt||_F)``
    (:func:`coupling_ratio`; N against N, whatever the unit of length) K is taken as
    decoupled already: no shift (``d = 0``), ``residual_coupling = 0`` and
    ``already_decoupled = True``.

Principal stiffnesses and directions are the eigen-pairs of K'_rr and K'_tt, ordered
as the paper (directions closest to x, y, z), so that ``k_phi = f_rr[2]``,
``k_x = f_tt[0]``, ``k_y = f_tt[1]`` for a planar design. Equal principal stiffnesses
(closer than :data:`~ppm_stiffness.core.eigenscrews.REPEATED_EIGENVALUE_TOLERANCE`,
e.g. k_x = k_y of a 3- or 4-fold symmetric design) have no unique directions: inside
such a group the directions closest to the coordinate axes are returned
(:func:`~ppm_stiffness.core.eigenscrews.basis_closest_to_axes`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, hat, vect
from ppm_stiffness.core.eigenscrews import REPEATED_EIGENVALUE_TOLERANCE, basis_closest_to_axes
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.inputs import validate_stiffness_matrix

Method = Literal["paper", "least-squares"]

#: K is decoupled already when its coupling block is round-off against its diagonal
#: blocks: ``coupling_ratio(K) <= DECOUPLED_TOLERANCE`` (module doc). The symmetric
#: shipped designs at their home pose have ratios of 1e-17 to 3e-10 (their joint
#: coordinates are printed to 10 digits); a design with any real coupling (the
#: paper's, 0.33) lies orders of magnitude above.
DECOUPLED_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Decoupling:
    """Result of :func:`decouple` (SI).

    Attributes
    ----------
    method : str
    M : ndarray (3, 3) [N/m]
        eq. (19)'s matrix (reported for both methods).
    d : ndarray (3,) [m]
        The shift: the old reference point P seen from the new one.
    D : ndarray (3, 3) [m]
    K_rr, K_tt : ndarray (3, 3)
        K'_rr [N·m/rad] and K'_tt [N/m] at the new point.
    K_rt : ndarray (3, 3) [N]
        The coupling left at the new point, ``K_rt + D K_tt``.
    residual_coupling : float
        ``||K'_rt||_F / ||K_rt||_F``; 0 when K is decoupled already.
    rotational_values, translational_values : ndarray (3,)
        Principal stiffnesses f_rr [N·m/rad], f_tt [N/m].
    rotational_directions, translational_directions : ndarray (3, 3)
        Unit eigenvectors as columns (Lambda_rr, Lambda_tt).
    already_decoupled : bool
        K_rt is round-off (:data:`DECOUPLED_TOLERANCE`): no shift was made, ``d = 0``.
    """

    method: str
    M: FloatArray
    d: FloatArray
    D: FloatArray
    K_rr: FloatArray
    K_tt: FloatArray
    K_rt: FloatArray
    residual_coupling: float
    rotational_values: FloatArray
    rotational_directions: FloatArray
    translational_values: FloatArray
    translational_directions: FloatArray
    already_decoupled: bool = False


def coupling_ratio(stiffness: ArrayLike) -> float:
    """``||K_rt||_F / sqrt(||K_rr||_F ||K_tt||_F)`` of a 6x6 K (dimensionless: N against
    N, the same for any unit of length); 0 for a decoupled K."""
    k = np.asarray(stiffness, dtype=float)
    scale = math.sqrt(float(np.linalg.norm(k[:3, :3]) * np.linalg.norm(k[3:, 3:])))
    return float(np.linalg.norm(k[:3, 3:])) / scale if scale > 0 else math.inf


def shift_blocks(stiffness: ArrayLike, d: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Blocks (K'_rr, K'_rt, K'_tt) after a shift ``d`` with Q = 1 (eq. 17)."""
    k = np.asarray(stiffness, dtype=float)
    krr, krt, ktt = k[:3, :3], k[:3, 3:], k[3:, 3:]
    dd = hat(d)
    new_rr = krr - krt @ dd + dd @ (krt.T - ktt @ dd)
    return new_rr, krt + dd @ ktt, ktt.copy()


def principal_axes(block: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Eigen-pairs of a symmetric 3x3 block, ordered as the paper.

    Each eigenvector is assigned to the coordinate axis it is closest to (x, y, z) and
    signed so that its component along that axis is non-negative. Eigenvalues closer
    than :data:`~ppm_stiffness.core.eigenscrews.REPEATED_EIGENVALUE_TOLERANCE` of the
    largest |value| form a group whose eigenvectors are not unique: its basis is the
    one closest to the coordinate axes
    (:func:`~ppm_stiffness.core.eigenscrews.basis_closest_to_axes`), its values the
    block's ``v^T B v`` along those directions.

    Returns
    -------
    values : ndarray (3,)
    directions : ndarray (3, 3), unit eigenvectors as columns
    """
    b = np.asarray(block, dtype=float)
    vals, vecs = np.linalg.eigh(0.5 * (b + b.T))
    v = vals.tolist()
    gap = REPEATED_EIGENVALUE_TOLERANCE * max(abs(v[0]), abs(v[2]))
    first = 0 if v[1] - v[0] <= gap else 1
    end = 3 if v[2] - v[1] <= gap else 2
    if end - first > 1:  # a repeated eigenvalue (ascending values: a run)
        q = basis_closest_to_axes(vecs[:, first:end])[0]
        vecs[:, first:end] = vecs[:, first:end] @ q
        vals[first:end] = (q * q).T @ vals[first:end]
    # assign eigenvectors to axes greedily by the largest |component| (the first
    # largest in row-major order, as numpy's argmax), in plain Python: 3 x 3 entries
    weights = np.abs(vecs).tolist()
    order = [-1, -1, -1]
    taken = [False, False, False]
    for _ in range(3):
        best, best_ax, best_j = -1.0, 0, 0
        for ax in range(3):
            if order[ax] >= 0:
                continue
            row = weights[ax]
            for j in range(3):
                if not taken[j] and row[j] > best:
                    best, best_ax, best_j = row[j], ax, j
        order[best_ax] = best_j
        taken[best_j] = True
    vecs = vecs[:, order]
    vals = vals[order]
    flip = np.diagonal(vecs) < 0
    vecs[:, flip] = -vecs[:, flip]
    return vals, vecs


def decouple(stiffness: ArrayLike, method: Method = "paper") -> Decoupling:
    """Decouple a 6x6 stiffness matrix by shifting the reference point.

    Parameters
    ----------
    stiffness : array_like, shape (6, 6)
        SI, order of ``conventions``: symmetric positive definite (checked by
        :func:`~ppm_stiffness.core.inputs.validate_stiffness_matrix`).
    method : {"paper", "least-squares"}

    Returns
    -------
    Decoupling

    Raises
    ------
    InputDataError
        If the matrix is not 6x6, finite, symmetric and positive definite, or the
        method is unknown.
    """
    if method not in ("paper", "least-squares"):
        raise InputDataError(f"unknown decoupling method {method!r}")
    k = validate_stiffness_matrix(stiffness)
    krt, ktt = k[:3, 3:], k[3:, 3:]
    m = 0.5 * (np.trace(ktt) * np.eye(3) - ktt)
    already = coupling_ratio(k) <= DECOUPLED_TOLERANCE
    d: FloatArray
    if already:
        d = np.zeros(3)
    elif method == "paper":  # M is positive definite as K_tt is: a plain solve
        d = np.linalg.solve(m, vect(krt))
    else:
        # K_rt + hat(d) K_tt is linear in d: stack the three columns of hat(e_k) K_tt
        basis = np.stack([(hat(e) @ ktt).ravel() for e in np.eye(3)], axis=1)
        d = np.asarray(np.linalg.lstsq(basis, -krt.ravel(), rcond=None)[0], dtype=float)
    new_rr, new_rt, new_tt = shift_blocks(k, d)
    residual = 0.0 if already else float(np.linalg.norm(new_rt) / np.linalg.norm(krt))
    f_rr, l_rr = principal_axes(new_rr)
    f_tt, l_tt = principal_axes(new_tt)
    return Decoupling(
        method=method,
        M=m,
        d=d,
        D=hat(d),
        K_rr=new_rr,
        K_tt=new_tt,
        K_rt=new_rt,
        residual_coupling=residual,
        rotational_values=f_rr,
        rotational_directions=l_rr,
        translational_values=f_tt,
        translational_directions=l_tt,
        already_decoupled=already,
    )
