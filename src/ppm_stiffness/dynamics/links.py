"""A link's kinetic energy from the twists of its two ends (Euler-Bernoulli shape).

A link of the virtual-joint model is a beam clamped at its start, whose compliance is
lumped in six springs at its end (eq. 3c). When the leg follows the platform
statically (:mod:`ppm_stiffness.dynamics.condensation`), its start moves with the body
before it (twist t_s at P) and its end with its own springs added (t_e); between them
the beam takes the static shape of a cantilever loaded at its tip: axial displacement
and twist linear along it, bending deflections cubic (the Hermite shape functions of
an Euler-Bernoulli element, which the cantilever's tip loads produce exactly). Its
kinetic energy on that shape:

- a uniform link (no ``centre`` and no ``transverse`` given: the default uniform
  slender rod of its current length L): ``integral of (m / L) |u(s)|^2 + (I_a / L)
  theta_x(s)^2 ds`` / 2 (the consistent mass of the element, no rotary inertia of the
  section), by 4-point Gauss-Legendre quadrature (exact for these degree-6
  polynomials), done once for L = 1: the displacements depend on L only through the
  nodal bending rotations, which scale by L;
- a link given as a body (its centre of mass or transverse inertia given): a rigid body
  riding on that shape at its centre of mass s_c, moving with the section's
  displacement and rotation there: ``(m |u(s_c)|^2 + omega(s_c)^T I omega(s_c)) / 2``
  (an approximation of its elastic motion; exact for a rigid one). A centre outside
  the link (s_c < 0: behind its start, as the rod of a strut inside its cylinder;
  s_c > L: past its end) moves rigidly with the section at that end: its rotation, and
  the end's displacement plus that rotation times the offset (a rigid continuation of
  the clamp or tip section; the axial displacement is the end section's, since the
  offset is along the link).

Both are exact for a rigid motion of the link (t_s = t_e), where they are the spatial
inertia of the body (:func:`ppm_stiffness.dynamics.inertia.spatial_inertia`). The
link's local axes are those of its tip frame (:func:`ppm_stiffness.legs.chain
.link_screws`: x along the link from its start). Batched over leading axes (...).
"""

from __future__ import annotations

import numpy as np

from ppm_stiffness.core.conventions import FloatArray, hat
from ppm_stiffness.legs.chain import Link, frame_from_axis

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(4)
#: Gauss-Legendre points and weights on [0, 1] (4 points: exact to degree 7).
GAUSS_POINTS = 0.5 * (_GAUSS_X + 1.0)
GAUSS_WEIGHTS = 0.5 * _GAUSS_W


def section_motion(xi: FloatArray, length: FloatArray) -> FloatArray:
    """The map (..., 6, 12) from a beam's nodal displacements (PyNite's local order:
    Dx, Dy, Dz, Rx, Ry, Rz at the start, then at the end) to the displacement (u, v,
    w) and rotation (theta_x, theta_y, theta_z) of its section at ``xi = s / L``, local
    axes; dv/ds = theta_z, dw/ds = -theta_y (module doc).

    Parameters
    ----------
    xi : array_like (...)
        Position along the link over its length (0: start, 1: end). Outside [0, 1] the
        section at the nearer end continued rigidly (module doc): its rotation, and its
        displacement plus that rotation times the offset ``(xi - end) L`` along x.
    length : array_like (...) [m]
    """
    xi_given = np.asarray(xi, dtype=float)
    ell = np.asarray(length, dtype=float)
    xi_given, ell = np.broadcast_arrays(xi_given, ell)
    x = np.clip(xi_given, 0.0, 1.0)
    offset = (xi_given - x) * ell  # [m] along the link, zero on it
    n1 = 1 - 3 * x**2 + 2 * x**3
    n2 = ell * (x - 2 * x**2 + x**3)
    n3 = 3 * x**2 - 2 * x**3
    n4 = ell * (x**3 - x**2)
    d1 = 6 * (x**2 - x) / ell
    d2 = 1 - 4 * x + 3 * x**2
    d3 = 6 * (x - x**2) / ell
    d4 = 3 * x**2 - 2 * x
    out = np.zeros(x.shape + (6, 12))
    out[..., 0, 0], out[..., 0, 6] = 1 - x, x
    out[..., 1, 1], out[..., 1, 5], out[..., 1, 7], out[..., 1, 11] = n1, n2, n3, n4
    out[..., 2, 2], out[..., 2, 4], out[..., 2, 8], out[..., 2, 10] = n1, -n2, n3, -n4
    out[..., 3, 3], out[..., 3, 9] = 1 - x, x
    out[..., 4, 2], out[..., 4, 4], out[..., 4, 8], out[..., 4, 10] = -d1, d2, -d3, d4
    out[..., 5, 1], out[..., 5, 5], out[..., 5, 7], out[..., 5, 11] = d1, d2, d3, d4
    # theta x (offset e_x) = (0, theta_z offset, -theta_y offset)
    out[..., 1, :] += offset[..., None] * out[..., 5, :]
    out[..., 2, :] -= offset[..., None] * out[..., 4, :]
    return out


def _unit_quadrature() -> tuple[FloatArray, FloatArray]:
    """``integral of H_u^T H_u`` and ``H_x^T H_x`` over xi in [0, 1] for L = 1 (the
    displacement rows u, v, w and the twist row of :func:`section_motion`)."""
    trans = np.zeros((12, 12))
    twist = np.zeros((12, 12))
    for xi, w in zip(GAUSS_POINTS, GAUSS_WEIGHTS, strict=True):
        h = section_motion(np.array(xi), np.array(1.0))
        trans += w * h[:3].T @ h[:3]
        twist += w * np.outer(h[3], h[3])
    return trans, twist


_UNIT_TRANS, _UNIT_TWIST = _unit_quadrature()
#: The nodal degrees of freedom whose shape functions carry a factor L (the bending
#: rotations about local y and z at both ends).
_BENDING_ROTATIONS = np.array([4, 5, 10, 11])


def _node_map(point: FloatArray, axes: FloatArray) -> FloatArray:
    """(..., 6, 6): a twist (omega, v) at P to a node's (displacement, rotation) in the
    link's local axes (``axes`` (..., 3, 3), columns ex, ey, ez)."""
    rt = np.swapaxes(axes, -1, -2)
    out = np.zeros(point.shape[:-1] + (6, 6))
    out[..., :3, :3] = -rt @ hat(point)
    out[..., :3, 3:] = rt
    out[..., 3:, :3] = rt
    return out


def link_mass_matrix(link: Link, start_twist: FloatArray, end_twist: FloatArray) -> FloatArray:
    """The link's mass matrix (..., 6, 6) over the platform twist at P (module doc);
    zeros for a massless link.

    Parameters
    ----------
    link : Link
        Its start and end (..., 3) or (3,) relative to P, axes of F_b, and its mass.
    start_twist, end_twist : ndarray (..., 6, 6)
        Maps from the platform twist to the twists (at P) of the link's start (the body
        before it) and of its end (its own springs added).
    """
    start = np.asarray(link.start, dtype=float)
    end = np.asarray(link.end, dtype=float)
    batch = np.broadcast_shapes(start.shape[:-1], end.shape[:-1], start_twist.shape[:-2])
    if link.mass is None:
        return np.zeros(batch + (6, 6))
    with np.errstate(divide="ignore", invalid="ignore"):  # a zero-length link: NaN
        return _link_mass_matrix(link, start, end, start_twist, end_twist, batch)


def _link_mass_matrix(
    link: Link,
    start: FloatArray,
    end: FloatArray,
    start_twist: FloatArray,
    end_twist: FloatArray,
    batch: tuple[int, ...],
) -> FloatArray:
    assert link.mass is not None
    start = np.broadcast_to(start, batch + (3,))
    end = np.broadcast_to(end, batch + (3,))
    d = end - start
    length = np.linalg.norm(d, axis=-1)
    axes = np.stack(frame_from_axis(d), axis=-1)  # columns ex, ey, ez
    g = np.concatenate(
        [_node_map(start, axes) @ start_twist, _node_map(end, axes) @ end_twist], axis=-2
    )  # (..., 12, 6)
    body = link.mass
    if body.centre is None and body.transverse is None:
        scale = np.ones(batch + (12,))
        scale[..., _BENDING_ROTATIONS] = length[..., None]
        unit = body.mass * _UNIT_TRANS + body.axial * _UNIT_TWIST
        local = unit * scale[..., :, None] * scale[..., None, :]
    if not (body.centre is None and body.transverse is None):
        if body.centre is None:
            s = 0.5 * length
        elif body.from_end:
            s = length - body.centre
        else:
            s = np.full(batch, body.centre)
        transverse = body.mass * length**2 / 12.0 if body.transverse is None else body.transverse
        weights = np.zeros(batch + (6,))
        weights[..., :3] = body.mass
        weights[..., 3] = body.axial
        weights[..., 4] = weights[..., 5] = transverse
        motion = section_motion(s / length, length) @ g  # the body's motion, (..., 6, 6)
        out = np.swapaxes(motion, -1, -2) @ (weights[..., :, None] * motion)
    else:
        out = np.swapaxes(g, -1, -2) @ local @ g
    return np.asarray(0.5 * (out + np.swapaxes(out, -1, -2)))
