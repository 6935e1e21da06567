"""Principal stiffnesses: the planar (paper) and the spatial definitions, side by side.

Planar (the paper, :mod:`ppm_stiffness.core.decoupling`)
    K is shifted to the point of eq. (19) and the eigen-pairs of the shifted blocks
    K'_rr and K'_tt are the principal stiffnesses; for a planar design ``k_phi =
    f_rr[2]`` [N·m/rad] is the stiffness about z at that point and ``k_x = f_tt[0]``,
    ``k_y = f_tt[1]`` [N/m]. They keep this meaning for planar designs (maps, summaries,
    optimisation objectives), and the decoupling (shift, K'_rr, K'_tt and its residual)
    is reported for every design.

Spatial (any design; this module)
    With the compliance ``C = K^-1`` (6 x 6, at the reference point of K, axes of F_b):

    - **rotational**: the eigen-pairs of ``C_rr^-1`` [N·m/rad]: the stiffness against
      a pure moment with the platform free to translate. A pure moment's rotation does
      not depend on the reference point, nor do these values;
    - **translational**: the eigen-pairs of ``C_tt^-1`` [N/m] at the reference point
      of K: the stiffness against a force applied there with the platform free to
      rotate. It depends on the point: every output states it (the tool point, P by
      default);
    - **worst direction**: ``1 / lambda_max(C_rr)`` and ``1 / lambda_max(C_tt)``, the
      smallest of each set: the least stiff direction for a moment and for a force.

    Values are ordered and their directions signed as the paper orders its principal
    stiffnesses (each direction assigned to the coordinate axis it is closest to,
    :func:`ppm_stiffness.core.decoupling.principal_axes`), so that for a planar design
    ``rotational[2]`` is about z and ``translational[0:2]`` along x and y. The batched
    form (:func:`principal_compliance_values`) returns the values in ascending order
    (for maps).

K must be symmetric positive definite (:mod:`ppm_stiffness.core.inputs`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.decoupling import principal_axes
from ppm_stiffness.core.inputs import validate_stiffness_matrix


@dataclass(frozen=True)
class PrincipalCompliance:
    """The spatial principal stiffnesses of one K (module doc), SI.

    Attributes
    ----------
    rotational_values : ndarray (3,) [N·m/rad]
        Eigenvalues of ``C_rr^-1``, ordered by the axis their direction is closest to.
    rotational_directions : ndarray (3, 3)
        Unit eigenvectors as columns (axes of F_b).
    translational_values : ndarray (3,) [N/m]
        Eigenvalues of ``C_tt^-1`` at the reference point of K.
    translational_directions : ndarray (3, 3)
        Unit eigenvectors as columns.
    worst_rotational : float [N·m/rad]
        ``1 / lambda_max(C_rr)``, the smallest rotational value.
    worst_translational : float [N/m]
        ``1 / lambda_max(C_tt)``, the smallest translational value.
    """

    rotational_values: FloatArray
    rotational_directions: FloatArray
    translational_values: FloatArray
    translational_directions: FloatArray
    worst_rotational: float
    worst_translational: float


def principal_compliance(stiffness: ArrayLike) -> PrincipalCompliance:
    """The spatial principal stiffnesses of one K (6, 6) (module doc).

    Raises
    ------
    InputDataError
        K not 6x6, not finite, not symmetric or not positive definite.
    """
    k = validate_stiffness_matrix(stiffness)
    c = np.linalg.inv(k)
    f_rr, l_rr = principal_axes(np.linalg.inv(c[:3, :3]))
    f_tt, l_tt = principal_axes(np.linalg.inv(c[3:, 3:]))
    return PrincipalCompliance(
        rotational_values=f_rr,
        rotational_directions=l_rr,
        translational_values=f_tt,
        translational_directions=l_tt,
        worst_rotational=float(np.min(f_rr)),
        worst_translational=float(np.min(f_tt)),
    )


def principal_compliance_values(stiffness: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The rotational and translational principal stiffnesses of matrices (..., 6, 6),
    each (..., 3) in ascending order (index 0: the worst direction); NaN where K is
    not finite or not invertible. No check of symmetry or definiteness (the batched
    model's matrices are both by construction)."""
    k = np.asarray(stiffness, dtype=float)
    ok = np.all(np.isfinite(k), axis=(-2, -1))
    safe = np.where(ok[..., None, None], k, np.eye(6))
    with np.errstate(all="ignore"):
        c = np.linalg.inv(safe)
        # eigenvalues of C_rr^-1 are the reciprocals of C_rr's (descending -> ascending)
        rot = 1.0 / np.linalg.eigvalsh(c[..., :3, :3])[..., ::-1]
        tra = 1.0 / np.linalg.eigvalsh(c[..., 3:, 3:])[..., ::-1]
    rot = np.where(ok[..., None], rot, np.nan)
    tra = np.where(ok[..., None], tra, np.nan)
    return np.asarray(rot), np.asarray(tra)
