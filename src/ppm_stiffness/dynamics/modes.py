"""Natural frequencies and mode shapes from a stiffness and a mass matrix.

The undamped free vibrations of the platform about a pose solve the generalised
eigenproblem ``K v = omega^2 M v`` (K, M symmetric positive definite 6x6 at one
reference point, axes of F_b, order (omega, v): :mod:`ppm_stiffness.dynamics.mass`).
The natural frequencies ``f = omega / (2 pi)`` [Hz] are given in ascending order; they
do not depend on the reference point (K and M transform by the same congruence). A
mode shape is a twist v (rad, m) of the platform at the reference point, scaled to
unit length-balanced norm ``|(omega L, v)| = 1`` (L = 0.1 m,
:data:`~ppm_stiffness.core.conventions.LENGTH_SCALE`) with its largest balanced
component positive, and named by that component (``"x translation"``, ``"rotation
about z"``) with its share of the balanced norm squared.

Repeated frequencies (closer than :data:`~ppm_stiffness.core.eigenscrews
.REPEATED_EIGENVALUE_TOLERANCE` of the largest omega^2: the x and y translations of a
3-fold symmetric design at its home pose) have no unique mode shapes: any
M-orthonormal basis of their space is as valid. The one given is fixed by a rule, as
for the screw springs: of the group's bases, the one whose balanced twists lie
closest to the coordinate axes (orthogonal Procrustes), members in axis order.

:func:`natural_frequencies` takes stacks (..., 6, 6) (a map's poses) by a Cholesky
factor of M; :func:`mode_shapes` solves one pair with ``scipy.linalg.eigh(K, M)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import DIRECTION_NAMES, TWIST_BALANCE, FloatArray
from ppm_stiffness.core.errors import InputDataError


@dataclass(frozen=True)
class Modes:
    """The six natural vibrations of the platform at one pose.

    Attributes
    ----------
    frequencies : ndarray (6,) [Hz]
        Ascending.
    shapes : ndarray (6, 6)
        ``shapes[j]`` is the j-th mode's twist (phi_x, phi_y, phi_z, x, y, z) [rad, m] at
        the reference point of K and M, unit length-balanced norm (module doc).
    directions : tuple of str
        The dominant component of each mode (:data:`DIRECTION_NAMES`).
    shares : ndarray (6,)
        Its share of the mode's balanced norm squared, in (1/6, 1].
    repeated : tuple of tuple of int
        Groups of modes (0-based) sharing a repeated frequency (module doc).
    platform_shares : ndarray (6,) or None
        With the legs' own modes (:func:`reduced_mode_shapes`): each mode's kinetic
        energy share carried by the platform body (0 for a mode of the legs alone);
        None without them.
    """

    frequencies: FloatArray
    shapes: FloatArray
    directions: tuple[str, ...]
    shares: FloatArray
    repeated: tuple[tuple[int, ...], ...] = ()
    platform_shares: FloatArray | None = None


#: The direction of a mode of the legs alone (their own vibration, no platform motion).
LEG_MODE_DIRECTION = "legs only"
#: Platform-twist kinetic energy share under which a mode is the legs' alone.
LEG_MODE_SHARE = 1e-9


def _check_pair(stiffness: ArrayLike, mass: ArrayLike) -> tuple[FloatArray, FloatArray]:
    k = np.asarray(stiffness, dtype=float)
    m = np.asarray(mass, dtype=float)
    if k.shape[-2:] != (6, 6) or m.shape[-2:] != (6, 6):
        raise InputDataError(
            f"stiffness and mass matrices are 6x6, got {k.shape[-2:]} and {m.shape[-2:]}"
        )
    return k, m


def natural_frequencies(stiffness: ArrayLike, mass: ArrayLike) -> FloatArray:
    """The six natural frequencies (..., 6) [Hz], ascending, of stacks of K and M.

    Parameters
    ----------
    stiffness, mass : array_like (..., 6, 6)
        At the same reference point (SI); broadcast against each other.

    Returns
    -------
    ndarray (..., 6)
        NaN where K or M is not finite, M is not positive definite, or K is not
        positive semi-definite.
    """
    k, m = _check_pair(stiffness, mass)
    shape = np.broadcast_shapes(k.shape[:-2], m.shape[:-2])
    kk = np.broadcast_to(k, shape + (6, 6)).reshape(-1, 6, 6)
    mm = np.broadcast_to(m, shape + (6, 6)).reshape(-1, 6, 6)
    out = np.full((kk.shape[0], 6), np.nan)
    good = np.isfinite(kk).all(axis=(1, 2)) & np.isfinite(mm).all(axis=(1, 2))
    idx = np.flatnonzero(good)
    if idx.size:
        ms = 0.5 * (mm[idx] + np.swapaxes(mm[idx], -1, -2))
        factor = np.full_like(ms, np.nan)
        try:
            factor = np.asarray(np.linalg.cholesky(ms), dtype=float)
        except np.linalg.LinAlgError:  # one M is not positive definite: one by one
            for j in range(ms.shape[0]):
                try:
                    factor[j] = np.linalg.cholesky(ms[j])
                except np.linalg.LinAlgError:
                    continue
        ok = np.isfinite(factor).all(axis=(1, 2))
        if ok.any():
            inv = np.linalg.inv(factor[ok])
            a = inv @ kk[idx[ok]] @ np.swapaxes(inv, -1, -2)
            lam = np.linalg.eigvalsh(0.5 * (a + np.swapaxes(a, -1, -2)))
            scale = np.max(np.abs(lam), axis=-1, keepdims=True)
            lam = np.where(np.abs(lam) <= 1e-12 * scale, 0.0, lam)  # round-off of a zero
            with np.errstate(invalid="ignore"):
                out[idx[ok]] = np.where(lam >= 0.0, np.sqrt(lam) / (2.0 * math.pi), np.nan)
    return out.reshape(shape + (6,))


def dominant_direction(twist: ArrayLike) -> tuple[int, float]:
    """Index (into phi_x, ..., z) of the largest length-balanced component of a twist
    (6,), and its share of the balanced norm squared."""
    b = np.asarray(twist, dtype=float) * TWIST_BALANCE
    sq = b**2
    i = int(np.argmax(sq))
    return i, float(sq[i] / np.sum(sq))


def normalised_shape(twist: ArrayLike) -> FloatArray:
    """A mode shape (6,) scaled to unit length-balanced norm, its largest balanced
    component positive."""
    t = np.asarray(twist, dtype=float)
    b = t * TWIST_BALANCE
    norm = float(np.linalg.norm(b))
    i = int(np.argmax(np.abs(b)))
    return np.asarray(t / norm * (1.0 if b[i] >= 0 else -1.0))


def _checked_eigh(
    k: FloatArray, m: FloatArray, subset: list[int] | None = None
) -> tuple[FloatArray, FloatArray]:
    """omega^2 and mass-normalised shapes of ``K v = omega^2 M v`` (symmetric parts;
    ``subset``: the indices of the lowest ones kept), round-off zeros set to 0.

    Raises
    ------
    InputDataError
        M not positive definite, or K with a negative omega^2.
    """
    from scipy.linalg import LinAlgError, eigh

    try:
        lam, vecs = eigh(0.5 * (k + k.T), 0.5 * (m + m.T), subset_by_index=subset)
    except LinAlgError:
        raise InputDataError("the mass matrix is not positive definite") from None
    scale = float(np.max(np.abs(lam)))
    lam = np.where(np.abs(lam) <= 1e-12 * scale, 0.0, lam)
    if np.any(lam < 0.0):
        raise InputDataError(
            f"the stiffness matrix is not positive definite (omega^2 = {lam.min():.3g})"
        )
    return lam, vecs


def mode_shapes(stiffness: ArrayLike, mass: ArrayLike) -> Modes:
    """Frequencies and mode shapes of one pair (6, 6) (module doc).

    Raises
    ------
    InputDataError
        If K or M is not finite, M is not positive definite or K has a negative
        eigenvalue.
    """
    k, m = _check_pair(stiffness, mass)
    if k.shape != (6, 6) or m.shape != (6, 6):
        raise InputDataError("mode_shapes takes one stiffness and one mass matrix (6, 6)")
    if not (np.all(np.isfinite(k)) and np.all(np.isfinite(m))):
        raise InputDataError("stiffness or mass matrix not finite")
    lam, vecs = _checked_eigh(k, m)
    groups = _groups(lam)
    for group in groups:
        vecs[:, group] = _closest_to_axes(vecs[:, group])
    shapes = np.array([normalised_shape(vecs[:, j]) for j in range(6)])
    dominant = [dominant_direction(s) for s in shapes]
    return Modes(
        frequencies=np.sqrt(lam) / (2.0 * math.pi),
        shapes=shapes,
        directions=tuple(DIRECTION_NAMES[i] for i, _ in dominant),
        shares=np.array([share for _, share in dominant]),
        repeated=tuple(tuple(g) for g in groups),
    )


def _groups(lam: FloatArray) -> list[list[int]]:
    """Runs of ascending eigenvalues closer than the tolerance of the largest."""
    from ppm_stiffness.core.eigenscrews import REPEATED_EIGENVALUE_TOLERANCE

    tol = REPEATED_EIGENVALUE_TOLERANCE * float(np.max(np.abs(lam)))
    groups: list[list[int]] = []
    run = [0]
    for j in range(1, lam.size):
        if lam[j] - lam[run[-1]] <= tol:
            run.append(j)
        else:
            if len(run) > 1:
                groups.append(run)
            run = [j]
    if len(run) > 1:
        groups.append(run)
    return groups


def _closest_to_axes(vectors: FloatArray) -> FloatArray:
    """The basis ``V Q`` (6, k) of a repeated group's space whose balanced twists lie
    closest to the k coordinate axes most represented in it (module doc), in axis
    order: ``Q = U W^T`` from the SVD ``B[axes] = W S U^T`` (B the balanced ``V``)."""
    return np.asarray(vectors @ _axes_rotation(vectors))


def _axes_rotation(vectors: FloatArray) -> FloatArray:
    """The orthogonal Q (k, k) of :func:`_closest_to_axes` for twists (6, k)."""
    b = TWIST_BALANCE[:, None] * vectors
    k = vectors.shape[1]
    norms = np.sum(b**2, axis=1)
    axes = sorted(np.argsort(-norms, kind="stable")[:k].tolist())
    w, _, ut = np.linalg.svd(b[axes])
    return np.asarray(ut.T @ w.T)


def reduced_mode_shapes(
    stiffness: ArrayLike,
    mass: ArrayLike,
    platform_mass: ArrayLike,
    to_tool: ArrayLike | None = None,
) -> Modes:
    """The six lowest modes of a Craig-Bampton pair (6 + k, 6 + k) whose first six
    coordinates are the platform twist at P (:mod:`ppm_stiffness.dynamics.legmodes`).

    Shapes, directions and shares are those of each mode's twist part, moved to the
    tool point by ``to_tool`` (6, 6) (``twist_tool = to_tool @ twist_P``; P if None),
    as :func:`mode_shapes` (module doc); a
    mode whose twist carries less than :data:`LEG_MODE_SHARE` of its kinetic energy
    is the legs' alone: a zero shape, direction :data:`LEG_MODE_DIRECTION`, share 0.
    ``platform_shares``: the platform body's kinetic energy (``platform_mass`` (6, 6)
    at P) over the mode's.

    Raises
    ------
    InputDataError
        As :func:`mode_shapes`.
    """

    k = np.asarray(stiffness, dtype=float)
    m = np.asarray(mass, dtype=float)
    if not (np.all(np.isfinite(k)) and np.all(np.isfinite(m))):
        raise InputDataError("stiffness or mass matrix not finite")
    lam, vecs = _checked_eigh(k, m, subset=[0, 5])
    move = np.eye(6) if to_tool is None else np.asarray(to_tool, dtype=float)
    groups = _groups(lam)
    for group in groups:
        vecs[:, group] = vecs[:, group] @ _axes_rotation(move @ vecs[:6, group])
    m6 = 0.5 * (m[:6, :6] + m[:6, :6].T)
    plat = np.asarray(platform_mass, dtype=float)
    shapes = np.zeros((6, 6))
    directions: list[str] = []
    shares = np.zeros(6)
    platform = np.zeros(6)
    for j in range(6):
        v = vecs[:, j]
        total = float(v @ m @ v)
        t = v[:6]
        platform[j] = float(t @ plat @ t) / total
        if float(t @ m6 @ t) <= LEG_MODE_SHARE * total:
            directions.append(LEG_MODE_DIRECTION)
            continue
        shapes[j] = normalised_shape(move @ t)
        i, share = dominant_direction(shapes[j])
        directions.append(DIRECTION_NAMES[i])
        shares[j] = share
    return Modes(
        frequencies=np.sqrt(lam) / (2.0 * math.pi),
        shapes=shapes,
        directions=tuple(directions),
        shares=shares,
        repeated=tuple(tuple(g) for g in groups),
        platform_shares=np.clip(platform, 0.0, 1.0),
    )
