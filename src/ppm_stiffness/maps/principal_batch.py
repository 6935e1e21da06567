"""The spatial principal stiffnesses of many matrices, in closed form.

The definitions are those of :mod:`ppm_stiffness.core.principal` (C = K^-1):
rotational, the eigenvalues of ``C_rr^-1`` [N·m/rad]; translational, those of
``C_tt^-1`` [N/m] at the reference point of K; each set ascending, index 0 the worst
direction. :func:`ppm_stiffness.core.principal.principal_compliance_values` computes them
with numpy's batched 6x6 inverse and 3x3 ``eigvalsh``; here, for the maps, without
either (about 0.3 us per pose against 1.7 us):

- ``C_rr^-1`` and ``C_tt^-1`` are the Schur complements
  ``K_rr - K_rt K_tt^-1 K_tr`` and ``K_tt - K_tr K_rr^-1 K_rt``, each formed as
  ``A - Y^T Y`` with ``Y = L^-1 B`` and ``L`` the Cholesky factor of the other diagonal
  block (exactly symmetric);
- the eigenvalues of a symmetric 3x3 matrix by the trigonometric method:
  ``lambda = q + p beta`` with ``q`` the mean eigenvalue, ``p^2 = |A - q 1|_F^2 / 6``
  and ``beta = 2 cos(theta + 2 pi k / 3)`` the eigenvalues of ``B = (A - q 1) / p``,
  ``theta = atan2(s, r) / 3``, ``r = det(B) / 2``. The textbook form takes
  ``theta = acos(r) / 3``, which loses half the digits near repeated eigenvalues (a
  rounding error e in r moves acos by sqrt(e)): a 3-fold symmetric design at its home
  pose has exactly repeated ones. Here ``s = sqrt(1 - r^2)`` comes from the
  discriminant ``prod (beta_i - beta_j)^2 = 108 (1 - r^2)``, computed as a sum of
  squares (the Gram determinant of I, B, B^2 by the Cauchy-Binet formula), so that it
  is accurate where it is small and ``theta`` keeps every digit.

Against the linalg route the values agree to 1e-12 relative to the largest of their set
(``tests/test_principal_batch.py`` measures the residual on the shipped designs' poses,
symmetric home poses included). Entries are arrays of one batch shape (...). NaN where
K is not finite or a diagonal block is not positive definite.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, hat
from ppm_stiffness.core.pose import platform_offset

#: Upper-triangle index pairs of a 3x3 block (00, 01, 02, 11, 12, 22).
_PAIRS = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))
Sym = list[FloatArray]


def _block(k: FloatArray, rows: int, cols: int) -> list[list[FloatArray]]:
    """The 3x3 block of K (..., 6, 6) at (rows, cols) as nested entries (...)."""
    return [[k[..., rows + i, cols + j] for j in range(3)] for i in range(3)]


def _schur(a: list[list[FloatArray]], b: list[list[FloatArray]], d: list[list[FloatArray]]) -> Sym:
    """``A - B D^-1 B^T`` (upper triangle) for symmetric A, D (3x3 entries), D by its
    Cholesky factor: ``A - Y^T Y``, ``Y = L^-1 B^T``; NaN where D is not positive
    definite."""
    with np.errstate(invalid="ignore", divide="ignore"):
        l00 = np.sqrt(d[0][0])
        l10 = d[1][0] / l00
        l20 = d[2][0] / l00
        l11 = np.sqrt(d[1][1] - l10 * l10)
        l21 = (d[2][1] - l20 * l10) / l11
        l22 = np.sqrt(d[2][2] - l20 * l20 - l21 * l21)
        y = []
        for c in range(3):  # column c of Y = L^-1 B^T: B^T[:, c] = row c of B
            y0 = b[c][0] / l00
            y1 = (b[c][1] - l10 * y0) / l11
            y2 = (b[c][2] - l20 * y0 - l21 * y1) / l22
            y.append((y0, y1, y2))
        return [
            a[i][j] - (y[i][0] * y[j][0] + y[i][1] * y[j][1] + y[i][2] * y[j][2]) for i, j in _PAIRS
        ]


def sym3_eigenvalues(s: Sym) -> FloatArray:
    """Eigenvalues (..., 3), ascending, of symmetric 3x3 matrices given by their upper
    triangles ``(a00, a01, a02, a11, a12, a22)`` (module doc: the trigonometric method
    with the discriminant as a sum of squares)."""
    a00, a01, a02, a11, a12, a22 = (np.asarray(v, dtype=float) for v in s)
    q = (a00 + a11 + a22) / 3.0
    b00, b11, b22 = a00 - q, a11 - q, a22 - q
    off = a01 * a01 + a02 * a02 + a12 * a12
    p = np.sqrt((b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * off) / 6.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        inv = np.where(p > 0, 1.0 / p, 0.0)
    c00, c11, c22 = b00 * inv, b11 * inv, b22 * inv
    c01, c02, c12 = a01 * inv, a02 * inv, a12 * inv
    # D = C^2 (symmetric)
    d00 = c00 * c00 + c01 * c01 + c02 * c02
    d11 = c01 * c01 + c11 * c11 + c12 * c12
    d22 = c02 * c02 + c12 * c12 + c22 * c22
    d01 = c00 * c01 + c01 * c11 + c02 * c12
    d02 = c00 * c02 + c01 * c12 + c02 * c22
    d12 = c01 * c02 + c11 * c12 + c12 * c22
    cd = ((c00, d00), (c11, d11), (c22, d22))
    co = ((c01, d01), (c02, d02), (c12, d12))
    # Cauchy-Binet: det Gram(I, C, C^2) = sum of squared 3x3 minors of the rows
    # (1, c_ii, d_ii) and (0, sqrt2 c_kl, sqrt2 d_kl)
    m = (cd[1][0] - cd[0][0]) * (cd[2][1] - cd[0][1]) - (cd[2][0] - cd[0][0]) * (
        cd[1][1] - cd[0][1]
    )
    disc = m * m
    for i, j in ((0, 1), (0, 2), (1, 2)):
        dc, dd = cd[j][0] - cd[i][0], cd[j][1] - cd[i][1]
        for ck, dk in co:
            t = dc * dk - dd * ck
            disc = disc + 2.0 * t * t
    for k, ll in ((0, 1), (0, 2), (1, 2)):
        t = co[k][0] * co[ll][1] - co[ll][0] * co[k][1]
        disc = disc + 12.0 * t * t
    det = (
        c00 * (c11 * c22 - c12 * c12)
        - c01 * (c01 * c22 - c12 * c02)
        + c02 * (c01 * c12 - c11 * c02)
    )
    theta = np.arctan2(np.sqrt(disc / 108.0), 0.5 * det) / 3.0
    two_p = 2.0 * p
    out = np.empty(q.shape + (3,))
    out[..., 2] = q + two_p * np.cos(theta)
    out[..., 1] = q + two_p * np.cos(theta - 2.0 * math.pi / 3.0)
    out[..., 0] = q + two_p * np.cos(theta + 2.0 * math.pi / 3.0)
    return out


def principal_values(stiffness: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The rotational [N·m/rad] and translational [N/m] principal stiffnesses of
    matrices (..., 6, 6) at their reference point, each (..., 3) ascending (module
    doc); NaN where K is not finite or a diagonal block not positive definite. The same
    numbers as :func:`ppm_stiffness.core.principal.principal_compliance_values`."""
    k = np.asarray(stiffness, dtype=float)
    ok = np.all(np.isfinite(k), axis=(-2, -1))
    safe = np.where(ok[..., None, None], k, np.eye(6)) if not np.all(ok) else k
    krr, krt, ktt = _block(safe, 0, 0), _block(safe, 0, 3), _block(safe, 3, 3)
    ktr = [[krt[j][i] for j in range(3)] for i in range(3)]
    with np.errstate(invalid="ignore"):
        rot = sym3_eigenvalues(_schur(krr, krt, ktt))
        tra = sym3_eigenvalues(_schur(ktt, ktr, krr))
    if not np.all(ok):
        rot[~ok] = np.nan
        tra[~ok] = np.nan
    return rot, tra


def stiffness_at_points(stiffness: ArrayLike, offsets: ArrayLike) -> FloatArray:
    """K moved from P to points at ``offsets`` r = T - P (..., 3) or (3,) [m, axes of
    F_b], axes kept (eq. 16): ``K_T = A K A^T``, ``A = [[1, hat(-r)], [0, 1]]`` (two
    batched 6x6 products: faster than the products of its 3x3 blocks)."""
    k = np.asarray(stiffness, dtype=float)
    r = np.asarray(offsets, dtype=float)
    a = np.broadcast_to(np.eye(6), r.shape[:-1] + (6, 6)).copy()
    a[..., :3, 3:] = hat(-r)
    return np.asarray(a @ k @ np.swapaxes(a, -1, -2))


def tool_offsets(poses: ArrayLike, tool_point: ArrayLike) -> FloatArray:
    """``T - P = R t`` at full poses (n, 6) [m, axes of F_b] for a tool point t (3,) in
    the platform frame (:func:`ppm_stiffness.core.pose.platform_offset`): (n, 3), or
    one offset (3,) when every pose has the same (poses of one orientation)."""
    offsets = np.asarray(platform_offset(np.asarray(poses, dtype=float), np.asarray(tool_point)))
    if offsets.ndim == 2 and offsets.shape[0] and np.all(offsets == offsets[0]):
        return np.asarray(offsets[0])
    return offsets
