"""Eigenscrew decomposition of a stiffness matrix (paper eq. 5-11, Tables 4-5).

The principal screws solve ``K zeta = lambda Gamma zeta`` (eq. 5). Each eigenvector
``zeta = (eta, xi)`` is a twist; it is returned with unit 2-norm, as a generic
eigen-solver does and as the paper's (24) is printed. From it:

- eigenforce ``kappa = lambda |eta|`` [N] (eq. 8),
- axis ``e = eta / |eta|`` (eq. 9),
- position ``p = eta x xi / |eta|^2`` [m], the point of the axis nearest P (eq. 10),
- pitch ``h = eta . xi / |eta|^2`` [m/rad] (eq. 11; the paper prints rad/m),
- spring constant ``k = lambda / (2 h)`` [N/m],
- normalised screw ``S = zeta / |eta| = (e, p x e + h e)`` (eq. 27).

``lambda`` carries N. The six screw springs rebuild K:
``K = sum_i lambda_i (Gamma s_i)(Gamma s_i)^T / (s_i^T Gamma s_i)`` with the
eigenvectors made Gamma-orthogonal (see :func:`stiffness_from_screw_springs`).
For a design symmetric about its plane the eigenvalues come in +- pairs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import GAMMA, FloatArray
from ppm_stiffness.core.errors import SingularConfigurationError
from ppm_stiffness.core.inputs import validate_stiffness_matrix


@dataclass(frozen=True)
class ScrewSprings:
    """Six screw springs of a stiffness matrix, ordered as the paper: the three
    positive eigenvalues in decreasing order, then their negative partners.

    Attributes
    ----------
    eigenvalues : ndarray, shape (6,) [N]
    eigenvectors : ndarray, shape (6, 6)
        Columns zeta_i, unit 2-norm, sign fixed so that the largest |component| of
        eta is positive.
    eigenforces : ndarray, shape (6,) [N]
    pitches : ndarray, shape (6,) [m/rad]
    axes : ndarray, shape (6, 3)
    positions : ndarray, shape (6, 3) [m], from P in F_b
    spring_constants : ndarray, shape (6,) [N/m]
    screws : ndarray, shape (6, 6)
        Columns ``zeta_i / |eta_i|``.
    """

    eigenvalues: FloatArray
    eigenvectors: FloatArray
    eigenforces: FloatArray
    pitches: FloatArray
    axes: FloatArray
    positions: FloatArray
    spring_constants: FloatArray
    screws: FloatArray


def _order(eigenvalues: FloatArray) -> FloatArray:
    pos = [i for i in np.argsort(-eigenvalues) if eigenvalues[i] > 0]
    neg = [i for i in np.argsort(eigenvalues) if eigenvalues[i] <= 0]
    # pair each positive eigenvalue with the negative one closest to its opposite
    ordered_neg: list[int] = []
    remaining = list(neg)
    for i in pos:
        if not remaining:
            break
        j = min(remaining, key=lambda k: abs(eigenvalues[k] + eigenvalues[i]))
        ordered_neg.append(j)
        remaining.remove(j)
    return np.array(pos + ordered_neg + remaining)


def eigenscrews(stiffness: ArrayLike) -> ScrewSprings:
    """Eigenscrew decomposition of a 6x6 stiffness matrix.

    Parameters
    ----------
    stiffness : array_like, shape (6, 6)
        Symmetric positive definite, SI, twist order of ``conventions``.

    Returns
    -------
    ScrewSprings

    Raises
    ------
    InputDataError
        If the matrix is not 6x6, finite, symmetric and positive definite.
    SingularConfigurationError
        If an eigenvalue is complex or an eigenvector has no rotational part
        (a pure translation: its axis and pitch are undefined).
    """
    k = validate_stiffness_matrix(stiffness)
    lam, vec = np.linalg.eig(GAMMA @ k)  # K z = lam Gamma z  <=>  Gamma K z = lam z
    if np.max(np.abs(lam.imag)) > 1e-8 * np.max(np.abs(lam.real)):
        raise SingularConfigurationError("eigenscrew problem has complex eigenvalues")
    lam = lam.real
    vec = vec.real
    idx = _order(lam)
    lam = lam[idx]
    vec = vec[:, idx]
    vec = vec / np.linalg.norm(vec, axis=0)
    eta = vec[:3]
    xi = vec[3:]
    eta_norm = np.linalg.norm(eta, axis=0)
    if np.any(eta_norm < 1e-12):
        raise SingularConfigurationError("an eigenscrew is a pure translation (infinite pitch)")
    lead = np.argmax(np.abs(eta), axis=0)
    sign = np.sign(eta[lead, np.arange(6)])
    vec = vec * sign
    eta = vec[:3]
    xi = vec[3:]
    axes = (eta / eta_norm).T
    # eta x xi, column by column (np.cross costs more than the rest of this function)
    cross = np.stack(
        [
            eta[1] * xi[2] - eta[2] * xi[1],
            eta[2] * xi[0] - eta[0] * xi[2],
            eta[0] * xi[1] - eta[1] * xi[0],
        ],
        axis=1,
    )
    positions = cross / eta_norm[:, None] ** 2
    pitches = np.einsum("ij,ij->j", eta, xi) / eta_norm**2
    with np.errstate(divide="ignore"):
        spring = np.where(pitches != 0, lam / (2.0 * pitches), np.inf)
    return ScrewSprings(
        eigenvalues=lam,
        eigenvectors=vec,
        eigenforces=lam * eta_norm,
        pitches=pitches,
        axes=axes,
        positions=positions,
        spring_constants=spring,
        screws=vec / eta_norm,
    )


def stiffness_from_screw_springs(springs: ScrewSprings) -> FloatArray:
    """Rebuild K from its six screw springs (a check of the decomposition).

    With ``Gamma K`` diagonalised by ``Z`` (columns zeta_i) the eigenvectors are
    Gamma-orthogonal, ``Z^T Gamma Z = diag(g_i)``, and
    ``K = Gamma Z diag(lambda_i / g_i) Z^T Gamma``: a sum of six rank-one springs,
    each acting along its wrench ``Gamma zeta_i``.
    """
    z = springs.eigenvectors
    g = np.einsum("ij,ik,kj->j", z, GAMMA, z)
    return np.asarray(GAMMA @ z @ np.diag(springs.eigenvalues / g) @ z.T @ GAMMA)
