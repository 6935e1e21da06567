"""Stiffness of legs and of the platform from virtual springs (paper eq. 1, 4).

The solver knows nothing of the architecture. A leg is given as arrays:

``screws`` (..., 6, m)
    unit twists (at the reference point P, axes of F_b) of its m virtual springs,
    the actuator included;
``compliance`` (..., m, m)
    the compliance of those springs in their own coordinates (block diagonal:
    ``1/k`` for a single spring, eq. 3c for a beam);
``passive`` (..., 6, p)
    unit twists of its passive joints.

The leg's compliance seen at P is ``J C J^T``; its stiffness ``K_i`` is the upper-left
6x6 block of the inverse of the bordered matrix ``[[J C J^T, J_q], [J_q^T, 0]]``
(eq. 1), which eliminates the passive joints exactly (``K_i @ J_q == 0``). The
platform stiffness is the sum over legs (eq. 4). Leading dimensions are batch
dimensions: one call evaluates many poses.

:func:`leg_stiffness` computes the same matrix as
``K_i = W (W^T J C J^T W)^{-1} W^T`` with W a basis of the wrenches the leg transmits
(reciprocal to its passive twists, ``J_q^T W = 0``; K does not depend on the basis),
forming ``G = J^T W`` first and ``W^T J C J^T W = G^T C G``. That order keeps the
compliances of the springs that carry the leg's load when others are orders of
magnitude softer (a two-force strut with slender links: forming ``J C J^T`` first
buries its axial compliance under the rounding of the bending terms, 1e-8 relative
where this gives 1e-14). :func:`bordered_stiffness` is eq. (1) as printed, kept as
the reference the tests compare with.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ppm_stiffness.core.conventions import BALANCE, FloatArray
from ppm_stiffness.core.errors import SingularConfigurationError


@dataclass(frozen=True)
class LegSprings:
    """Virtual springs and passive joints of one leg, as arrays (see module doc).

    Attributes
    ----------
    screws : ndarray, shape (..., 6, m)
    compliance : ndarray, shape (..., m, m)
    passive : ndarray, shape (..., 6, p)
    actuator_index : int or None
        Column of ``screws`` that is the actuator spring; None for a passive
        constraining leg (no actuated joint).
    """

    screws: FloatArray
    compliance: FloatArray
    passive: FloatArray
    actuator_index: int | None = 0


def leg_compliance_at_platform(screws: FloatArray, compliance: FloatArray) -> FloatArray:
    """Compliance ``J C J^T`` of a leg's springs seen at P, shape (..., 6, 6)."""
    return np.asarray(screws @ compliance @ np.swapaxes(screws, -1, -2))


def bordered_stiffness(compliance6: FloatArray, passive: FloatArray) -> FloatArray:
    """Leg stiffness by the bordered inverse of eq. (1).

    Parameters
    ----------
    compliance6 : ndarray, shape (..., 6, 6)
        ``J C J^T`` of the leg [rad/(N·m), rad/N, m/N].
    passive : ndarray, shape (..., 6, p)
        Unit twists of the passive joints.

    Returns
    -------
    ndarray, shape (..., 6, 6)
        Symmetric stiffness of the leg at P, with ``K @ passive == 0``.

    Raises
    ------
    SingularConfigurationError
        If the bordered matrix is singular (dependent passive joints, or a leg whose
        springs leave a transmitted wrench without compliance).
    """
    # Balanced units (conventions.LENGTH_SCALE): the compliance S^-1 C S^-1 and the
    # passive twists S^-1 J_q; the bordered inverse then gives S K S. This changes the
    # conditioning of the inverse, not the result.
    scale = 1.0 / BALANCE
    c = compliance6 * scale[:, None] * scale[None, :]
    q = passive * scale[:, None]
    p = q.shape[-1]
    n = 6 + p
    batch = c.shape[:-2]
    bordered = np.zeros(batch + (n, n))
    bordered[..., :6, :6] = c
    bordered[..., :6, 6:] = q
    bordered[..., 6:, :6] = np.swapaxes(q, -1, -2)
    try:
        inv = np.linalg.inv(bordered)
    except np.linalg.LinAlgError as exc:
        raise SingularConfigurationError(
            "a leg's passive joints are dependent or its springs leave a wrench uncompliant"
        ) from exc
    k = inv[..., :6, :6] * scale[:, None] * scale[None, :]  # S^-1 (S K S) S^-1
    return np.asarray(0.5 * (k + np.swapaxes(k, -1, -2)))


def reciprocal_basis(passive: FloatArray) -> FloatArray:
    """A basis W (..., 6, 6 - p) of the wrenches reciprocal to the passive twists
    (``passive^T W = 0``), orthonormal in length-balanced units (W = S^-1 W_b).

    Raises
    ------
    SingularConfigurationError
        If the passive twists are dependent (rank below p).
    """
    q = np.asarray(passive, dtype=float)
    p = q.shape[-1]
    scale = 1.0 / BALANCE
    if p == 0:
        return np.asarray(np.broadcast_to(np.diag(scale), q.shape[:-2] + (6, 6)))
    u, sv, _ = np.linalg.svd(q * scale[:, None], full_matrices=True)
    if np.any(~(sv[..., -1] > 1e-12 * sv[..., 0])):
        raise SingularConfigurationError("a leg's passive joints are dependent")
    return np.asarray(u[..., :, p:] * scale[:, None])


def leg_stiffness(leg: LegSprings) -> FloatArray:
    """Cartesian stiffness of one leg at P, shape (..., 6, 6) (eq. 1, module doc).

    Raises
    ------
    SingularConfigurationError
        Dependent passive joints, or a transmitted wrench no spring yields to.
    """
    w = reciprocal_basis(leg.passive)
    g = np.swapaxes(leg.screws, -1, -2) @ w  # (..., m, r)
    reduced = np.swapaxes(g, -1, -2) @ leg.compliance @ g  # (..., r, r)
    reduced = 0.5 * (reduced + np.swapaxes(reduced, -1, -2))
    try:
        inv = np.linalg.inv(reduced)
    except np.linalg.LinAlgError as exc:
        raise SingularConfigurationError(
            "a leg's springs leave a wrench it transmits uncompliant"
        ) from exc
    k = w @ inv @ np.swapaxes(w, -1, -2)
    return np.asarray(0.5 * (k + np.swapaxes(k, -1, -2)))


def cartesian_stiffness(legs: Sequence[LegSprings]) -> FloatArray:
    """Cartesian stiffness of the platform at P, axes of F_b: the sum of eq. (4).

    Parameters
    ----------
    legs : sequence of LegSprings
        All with the same batch shape.

    Returns
    -------
    ndarray, shape (..., 6, 6)
        [[K_rr, K_rt], [K_rt^T, K_tt]] in N·m/rad, N, N/m.
    """
    total = leg_stiffness(legs[0])
    for leg in legs[1:]:
        total = total + leg_stiffness(leg)
    return total


def transmitted_wrench_basis(passive: FloatArray) -> FloatArray:
    """Orthonormal basis of the wrenches a leg can transmit (reciprocal to its passive
    joints: ``passive^T @ W == 0``), shape (..., 6, 6 - p). Used by tests as an
    independent route to the leg stiffness: ``K = W (W^T C W)^{-1} W^T``."""
    u, _, _ = np.linalg.svd(passive, full_matrices=True)
    return np.asarray(u[..., :, passive.shape[-1] :])
