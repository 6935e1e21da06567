"""Eigenscrew decomposition of a stiffness matrix (paper eq. 5-11, Tables 4-5).

The principal screws solve ``K zeta = lambda Gamma zeta`` (eq. 5). K is symmetric
positive definite, so this is solved as a symmetric problem: with ``K = L L^T``
(Cholesky) and ``L^T Gamma L = U diag(nu) U^T`` (``U`` orthogonal),
``zeta_i = Gamma L u_i`` and ``lambda_i = nu_i``, since
``K zeta_i = L (L^T Gamma L) u_i = nu_i L u_i = nu_i Gamma zeta_i``. The eigenvectors are
then reciprocal (Gamma-orthogonal), ``zeta_i^T Gamma zeta_j = nu_i delta_ij``, and the
six springs rebuild K exactly, ``K = sum_i Gamma zeta_i zeta_i^T Gamma`` (see
:func:`stiffness_from_screw_springs`). Each eigenvector ``zeta = (eta, xi)`` is a
twist; it is returned with unit 2-norm, as the paper's (24) is printed. From it:

- eigenforce ``kappa = lambda |eta|`` [N] (eq. 8),
- axis ``e = eta / |eta|`` (eq. 9),
- position ``p = eta x xi / |eta|^2`` [m], the point of the axis nearest P (eq. 10),
- pitch ``h = eta . xi / |eta|^2`` [m/rad] (eq. 11; the paper prints rad/m),
- spring constant ``k = lambda / (2 h)`` [N/m],
- normalised screw ``S = zeta / |eta| = (e, p x e + h e)`` (eq. 27).

``lambda`` carries N. For a design symmetric about its plane the eigenvalues come in
+- pairs.

Repeated eigenvalues
    A 3- or 4-fold symmetric design has, at its symmetric pose, eigenvalues of
    multiplicity two: any reciprocal basis of that eigenspace is as valid as another,
    so its screw springs are not unique (K is). Eigenvalues closer than
    :data:`REPEATED_EIGENVALUE_TOLERANCE` of the largest |lambda| form a group
    (:attr:`ScrewSprings.repeated`); inside a group the basis is fixed by one rule
    (:func:`basis_closest_to_axes`): of the reciprocal bases of the group, the one whose
    axes lie closest to the coordinate axes of F_b (springs ordered x, y, z). A
    group's eigenvalues are then the weighted means ``zeta_i^T Gamma zeta_i`` of its
    members, so the springs still rebuild K to round-off; they are reciprocal to the
    spread of the group's eigenvalues (round-off for an exactly symmetric design).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import GAMMA, FloatArray
from ppm_stiffness.core.errors import SingularConfigurationError
from ppm_stiffness.core.inputs import stiffness_and_cholesky

#: Two eigenvalues are one repeated eigenvalue when they differ by at most this
#: fraction of the largest |eigenvalue|. It matches the symmetry accepted of K
#: (:data:`~ppm_stiffness.core.inputs.SYMMETRY_TOLERANCE`): K is taken as known to that
#: precision, so closer eigenvalues cannot be told apart. A computed K of an exactly
#: symmetric design splits its repeated eigenvalues by ~1e-15; the shipped examples
#: whose joint coordinates are printed to 10 digits by ~1e-10.
REPEATED_EIGENVALUE_TOLERANCE = 1e-9

#: Rows of ``Gamma @ M``: Gamma swaps the rotational and translational halves.
_SWAP = [3, 4, 5, 0, 1, 2]
_COLUMNS = np.arange(6)


@dataclass(frozen=True)
class ScrewSprings:
    """Six screw springs of a stiffness matrix, ordered as the paper: the three
    positive eigenvalues in decreasing order, then their negative partners.

    Attributes
    ----------
    eigenvalues : ndarray, shape (6,) [N]
    eigenvectors : ndarray, shape (6, 6)
        Columns zeta_i, unit 2-norm, reciprocal (``zeta_i^T Gamma zeta_j = 0``,
        i != j), sign fixed so that the largest |component| of eta is positive.
    eigenforces : ndarray, shape (6,) [N]
    pitches : ndarray, shape (6,) [m/rad]
    axes : ndarray, shape (6, 3)
    positions : ndarray, shape (6, 3) [m], from P in F_b
    spring_constants : ndarray, shape (6,) [N/m]
    screws : ndarray, shape (6, 6)
        Columns ``zeta_i / |eta_i|``.
    repeated : tuple of tuple of int
        Groups of springs (0-based indices in this order) that share one repeated
        eigenvalue, e.g. ``((0, 1), (3, 4))``; empty when every eigenvalue is simple.
        Inside a group the springs are one choice among equally valid ones (module
        doc).
    """

    eigenvalues: FloatArray
    eigenvectors: FloatArray
    eigenforces: FloatArray
    pitches: FloatArray
    axes: FloatArray
    positions: FloatArray
    spring_constants: FloatArray
    screws: FloatArray
    repeated: tuple[tuple[int, ...], ...] = ()


def basis_closest_to_axes(directions: ArrayLike) -> tuple[FloatArray, list[int]]:
    """The rotation of a group's basis that brings its directions closest to the axes.

    Parameters
    ----------
    directions : array_like, shape (3, m)
        Column j: the direction part (a 3-vector in F_b) of the group's basis vector j,
        for m = 1, 2 or 3 members.

    Returns
    -------
    rotation : ndarray, shape (m, m)
        Orthogonal ``Q``: the basis ``B Q`` replaces ``B``. Of all orthogonal Q, the
        one that maximises ``sum_k (directions @ Q)[a_k, k]``: member k points as far as
        it can along axis a_k (orthogonal Procrustes: ``Q = V W^T`` from the SVD
        ``directions[axes] = W S V^T``, so that ``directions[axes] @ Q`` is symmetric
        positive semi-definite).
    axes : list of int
        a_1 < ... < a_m: the m coordinate axes (0 = x, 1 = y, 2 = z) nearest the span
        of the directions (the largest row norms; ties to the lower index).

    Notes
    -----
    The result does not depend on the basis it is given: for any orthogonal R,
    ``B R`` yields ``R^T Q``, hence the same ``B Q``. It is unique when
    ``directions[axes]`` is not singular.
    """
    h = np.asarray(directions, dtype=float)
    m = h.shape[1]
    rows = h.tolist()
    norms = [sum(x * x for x in row) for row in rows]
    axes = sorted(sorted(range(3), key=lambda i: -norms[i])[:m])
    if m == 2:  # the 2 x 2 polar factor in closed form (faster than an SVD)
        (h11, h12), (h21, h22) = rows[axes[0]], rows[axes[1]]
        if h11 * h22 - h12 * h21 >= 0:  # a rotation [[c, -s], [s, c]]
            c, s = h11 + h22, h12 - h21
            r = math.hypot(c, s)
            return np.array([[c / r, -s / r], [s / r, c / r]]), axes
        c, s = h11 - h22, h12 + h21  # a reflection [[c, s], [s, -c]]
        r = math.hypot(c, s)
        return np.array([[c / r, s / r], [s / r, -c / r]]), axes
    w, _, vt = np.linalg.svd(h[axes])
    return np.asarray(vt.T @ w.T), axes


def _groups(values: list[float], tolerance: float) -> list[list[int]]:
    """Runs of ascending ``values`` of one sign closer than ``tolerance * max|value|``."""
    gap = tolerance * max(abs(v) for v in values)
    out = [[0]]
    for i in range(1, len(values)):
        if values[i] - values[i - 1] <= gap and values[i] * values[i - 1] > 0:
            out[-1].append(i)
        else:
            out.append([i])
    return out


def _order(level: list[float], rank: list[int]) -> list[int]:
    """The paper's order: positive eigenvalues decreasing, then for each the negative
    one closest to its opposite; members of a group (equal ``level``) by ``rank``."""
    n = range(len(level))
    pos = sorted((i for i in n if level[i] > 0), key=lambda i: (-level[i], rank[i]))
    remaining = sorted((i for i in n if level[i] <= 0), key=lambda i: (level[i], rank[i]))
    ordered_neg: list[int] = []
    for i in pos:
        if not remaining:
            break
        j = min(remaining, key=lambda k: (abs(level[k] + level[i]), rank[k]))
        ordered_neg.append(j)
        remaining.remove(j)
    return pos + ordered_neg + remaining


def eigenscrews(stiffness: ArrayLike) -> ScrewSprings:
    """Eigenscrew decomposition of a 6x6 stiffness matrix.

    Parameters
    ----------
    stiffness : array_like, shape (6, 6)
        Symmetric positive definite, SI, at the reference point, twist order of
        ``conventions`` (checked by
        :func:`~ppm_stiffness.core.inputs.stiffness_and_cholesky`).

    Returns
    -------
    ScrewSprings

    Raises
    ------
    InputDataError
        If the matrix is not 6x6, finite, symmetric and positive definite.
    SingularConfigurationError
        If an eigenvector has no rotational part (a pure translation: its axis and
        pitch are undefined).
    """
    _, lower = stiffness_and_cholesky(stiffness)
    gl = lower[_SWAP]  # Gamma L
    a = lower.T @ gl  # L^T Gamma L, symmetric
    nu, u = np.linalg.eigh(0.5 * (a + a.T))  # ascending
    vec = gl @ u  # zeta_i = Gamma L u_i
    values = nu.tolist()
    groups = _groups(values, REPEATED_EIGENVALUE_TOLERANCE)
    level, rank = list(values), [0] * 6  # the group's eigenvalue, rank inside it
    for g in groups:
        if len(g) > 1:
            first, end = g[0], g[-1] + 1  # a group is a run of the ascending values
            q = basis_closest_to_axes(vec[:3, first:end])[0]
            vec[:, first:end] = vec[:, first:end] @ q
            w = (q * q).tolist()  # new zeta_i^T Gamma zeta_i = sum_k q_ki^2 nu_k
            mean = sum(values[first:end]) / len(g)
            for r, i in enumerate(g):
                nu[i] = sum(w[j][r] * values[first + j] for j in range(len(g)))
                level[i], rank[i] = mean, r
    idx = _order(level, rank)
    where = {j: n for n, j in enumerate(idx)}
    repeated = tuple(sorted(tuple(sorted(where[j] for j in g)) for g in groups if len(g) > 1))
    lam = nu[idx]
    vec = vec[:, idx]
    vec /= np.sqrt(np.einsum("ij,ij->j", vec, vec))
    eta2 = np.einsum("ij,ij->j", vec[:3], vec[:3])  # |eta|^2
    if float(eta2.min()) < 1e-24:
        raise SingularConfigurationError("an eigenscrew is a pure translation (infinite pitch)")
    lead = np.abs(vec[:3]).argmax(axis=0)
    vec *= np.sign(vec[lead, _COLUMNS])
    eta, xi = vec[:3], vec[3:]
    eta_norm = np.sqrt(eta2)
    # eta x xi, column by column (np.cross costs more than the rest of this function)
    cross = eta[[1, 2, 0]] * xi[[2, 0, 1]] - eta[[2, 0, 1]] * xi[[1, 2, 0]]
    pitches = np.einsum("ij,ij->j", eta, xi) / eta2
    spring = [  # lambda / (2 h): infinite for a zero pitch
        v / (2.0 * h) if h != 0 else math.inf
        for v, h in zip(lam.tolist(), pitches.tolist(), strict=True)
    ]
    return ScrewSprings(
        eigenvalues=lam,
        eigenvectors=vec,
        eigenforces=lam * eta_norm,
        pitches=pitches,
        axes=(eta / eta_norm).T,
        positions=(cross / eta2).T,
        spring_constants=np.array(spring),
        screws=vec / eta_norm,
        repeated=repeated,
    )


def stiffness_from_screw_springs(springs: ScrewSprings) -> FloatArray:
    """Rebuild K from its six screw springs (a check of the decomposition).

    The eigenvectors are reciprocal, ``Z^T Gamma Z = diag(g_i)`` (columns zeta_i), and
    ``K = Gamma Z diag(lambda_i / g_i) Z^T Gamma``: a sum of six rank-one springs, each
    acting along its wrench ``Gamma zeta_i``.

    Returns
    -------
    ndarray, shape (6, 6)
        K [N·m/rad, N, N/m], at the reference point of the springs.
    """
    z = springs.eigenvectors
    g = np.einsum("ij,ik,kj->j", z, GAMMA, z)
    return np.asarray(GAMMA @ z @ np.diag(springs.eigenvalues / g) @ z.T @ GAMMA)
