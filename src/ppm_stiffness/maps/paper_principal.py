"""The paper's decoupling (eq. 19) and principal stiffnesses k_phi, k_x, k_y, batched.

For a planar K (in-plane and out-of-plane blocks uncoupled, as every shipped planar leg
type gives) the paper's decoupling has a closed form (:func:`principal_from_entries`):
``d_z = 0``, ``k_phi = K'_rr[2, 2]`` and ``(k_x, k_y)`` the eigenvalues of the in-plane
2x2 block of K_tt, each assigned to the axis its eigenvector is closest to (as
:func:`~ppm_stiffness.core.decoupling.principal_axes`). A K that is not planar to
:data:`PLANAR_TOLERANCE` (length-balanced) is decoupled pose by pose with
:func:`~ppm_stiffness.core.decoupling.decouple`. These are the planar designs'
quantities; a spatial design's principal stiffnesses are those of
:mod:`ppm_stiffness.maps.principal_batch`. Matrices at P (or at the point they are
given at), axes of F_b, SI.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray, hat, length_balanced, vect
from ppm_stiffness.core.decoupling import decouple
from ppm_stiffness.maps.reduced_leg import IN_PLANE, OUT_OF_PLANE
from ppm_stiffness.maps.reduced_path import PlanarEntries, entries_from_matrices

#: Largest length-balanced in-plane/out-of-plane coupling, relative to the largest
#: entry, for which K counts as planar (closed-form decoupling).
PLANAR_TOLERANCE = 1e-12


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
