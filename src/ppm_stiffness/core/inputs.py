"""Checks of numeric input handed to the library: stiffness matrices and wrenches.

One set of rules for the Python API and the CLI (``analyze --matrix``, ``calibrate
--target``): each failure is an :class:`~ppm_stiffness.core.errors.InputDataError`
with one line naming the input and what is valid.

A stiffness matrix is valid when it is 6x6, finite, symmetric and positive definite.
Symmetry and definiteness are judged on the length-balanced matrix
(:func:`~ppm_stiffness.core.conventions.length_balanced`, every entry in N/m), so that
the verdict does not depend on the units of the blocks.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BALANCE, FloatArray
from ppm_stiffness.core.errors import InputDataError

#: Largest ``|K - K^T|`` accepted, relative to the largest entry of the length-balanced
#: K, for a matrix handed to the library: a computed K is symmetric to round-off
#: (~1e-16), and the eigen-solvers read one triangle only, so a larger asymmetry would
#: be dropped without a word.
SYMMETRY_TOLERANCE = 1e-9
#: The same for a matrix read from a text file (``analyze --matrix``, ``calibrate
#: --target``): printed with about six significant digits, its two triangles agree
#: to that precision only. The symmetric part ``(K + K^T) / 2`` is used.
PRINTED_SYMMETRY_TOLERANCE = 1e-6

#: ``S_i S_j``: the length-balanced matrix is ``K * _BALANCE_OUTER`` (conventions).
_BALANCE_OUTER: FloatArray = np.outer(BALANCE, BALANCE)


def as_float_array(value: ArrayLike, what: str) -> FloatArray:
    """``value`` as a float array, or :class:`InputDataError` if it holds anything but
    numbers (strings, ragged nested lists, ...)."""
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputDataError(f"{what} must be an array of numbers") from None


def stiffness_and_cholesky(
    matrix: ArrayLike,
    what: str = "stiffness matrix",
    symmetry_tolerance: float = SYMMETRY_TOLERANCE,
) -> tuple[FloatArray, FloatArray]:
    """Check a stiffness matrix and return it with its Cholesky factor.

    Parameters
    ----------
    matrix : array_like, shape (6, 6)
        SI (N·m/rad, N, N/m), order of :mod:`~ppm_stiffness.core.conventions`.
    what : str
        Names the input in messages ("stiffness matrix", a file name, "target").
    symmetry_tolerance : float
        :data:`SYMMETRY_TOLERANCE` or :data:`PRINTED_SYMMETRY_TOLERANCE`.

    Returns
    -------
    stiffness : ndarray, shape (6, 6)
        The symmetric part ``(K + K^T) / 2``.
    lower : ndarray, shape (6, 6)
        Lower triangular ``L`` with ``L L^T = K`` (SI: rows 0-2 in sqrt(N·m), rows
        3-5 in sqrt(N/m)), computed on the length-balanced matrix.

    Raises
    ------
    InputDataError
        If the matrix is not 6x6, not finite, not symmetric or not positive definite.
    """
    k = as_float_array(matrix, what)
    if k.shape != (6, 6):
        raise InputDataError(f"{what} must be 6x6, got shape {k.shape}")
    balanced = k * _BALANCE_OUTER
    scale = float(np.max(np.abs(balanced)))  # NaN or inf if an entry is not finite
    if not math.isfinite(scale):
        raise InputDataError(f"{what} has entries that are not finite")
    asymmetry = float(np.max(np.abs(balanced - balanced.T)))
    if asymmetry > symmetry_tolerance * scale:
        raise InputDataError(
            f"{what} is not symmetric: the largest |K - K^T| is {asymmetry / scale:.1e} of "
            f"its largest entry (length-balanced), above {symmetry_tolerance:.0e}"
        )
    balanced = 0.5 * (balanced + balanced.T)
    try:
        lower = np.linalg.cholesky(balanced)
    except np.linalg.LinAlgError:
        smallest = float(np.linalg.eigvalsh(balanced)[0])
        raise InputDataError(
            f"{what} is not positive definite: smallest eigenvalue {smallest:.3g} N/m "
            "(length-balanced)"
        ) from None
    return 0.5 * (k + k.T), lower / BALANCE[:, None]


def validate_stiffness_matrix(
    matrix: ArrayLike,
    what: str = "stiffness matrix",
    symmetry_tolerance: float = SYMMETRY_TOLERANCE,
) -> FloatArray:
    """Return ``matrix`` as a symmetric positive definite (6, 6) float array, or raise
    :class:`InputDataError` (the checks of :func:`stiffness_and_cholesky`)."""
    return stiffness_and_cholesky(matrix, what, symmetry_tolerance)[0]


def validate_wrench(wrench: ArrayLike) -> FloatArray:
    """A wrench as a finite (6,) array (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N], or raise."""
    w = as_float_array(wrench, "a wrench")
    if w.shape != (6,):
        raise InputDataError(
            f"a wrench has 6 components (m_x, m_y, m_z, f_x, f_y, f_z), got shape {w.shape}"
        )
    if not np.all(np.isfinite(w)):
        raise InputDataError("wrench components must be finite")
    return w
