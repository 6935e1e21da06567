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

Elastic freedoms. A joint freedom may be elastic (a flexure, a torsion spring): a
coordinate e with unit twists ``J_e`` (..., 6, n_e) and stiffness ``K_e`` along it
(diagonal, N·m/rad or N/m). It is neither eliminated (passive) nor a spring of
``C``: its generalised force ``J_e^T w`` enters the bordered solve with its stiffness,

    [[J C J^T, J_q, J_e], [J_q^T, 0, 0], [J_e^T, 0, -K_e]],

whose upper-left block of the inverse is K (``K_e -> 0``: the freedom is passive;
``K_e -> inf``: locked). :func:`leg_stiffness` evaluates it in the W basis, as the
passive joints' case (:func:`elastic_stiffness`): ``K = W X W^T`` with X the upper-left
block of ``[[A, H], [H^T, -K_e]]^-1``, ``A = G^T C G`` and ``H = W^T J_e``. ``K_e``
enters as a stiffness, never as ``1/K_e`` added to a compliance: a weak flexure keeps
full precision, where adding ``J_e K_e^-1 J_e^T`` to ``J C J^T`` loses
(structural stiffness / K_e) x 1e-16 (``tests/test_elastic_joints.py`` measures both).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

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
    elastic : ndarray, shape (..., 6, e), optional
        Unit twists of the elastic freedoms (module doc); None: none.
    elastic_stiffness : ndarray, shape (..., e), optional
        Their stiffnesses [N·m/rad or N/m], positive.
    """

    screws: FloatArray
    compliance: FloatArray
    passive: FloatArray
    actuator_index: int | None = 0
    elastic: FloatArray | None = None
    elastic_stiffness: FloatArray | None = None

    @property
    def elastic_count(self) -> int:
        """Number of elastic freedoms e."""
        return 0 if self.elastic is None else int(self.elastic.shape[-1])


def leg_compliance_at_platform(screws: FloatArray, compliance: FloatArray) -> FloatArray:
    """Compliance ``J C J^T`` of a leg's springs seen at P, shape (..., 6, 6)."""
    return np.asarray(screws @ compliance @ np.swapaxes(screws, -1, -2))


def bordered_stiffness(
    compliance6: FloatArray,
    passive: FloatArray,
    elastic: FloatArray | None = None,
    elastic_stiffness: FloatArray | None = None,
) -> FloatArray:
    """Leg stiffness by the bordered inverse of eq. (1) (with elastic freedoms: the
    bordered matrix of the module doc).

    Parameters
    ----------
    compliance6 : ndarray, shape (..., 6, 6)
        ``J C J^T`` of the leg [rad/(N·m), rad/N, m/N].
    passive : ndarray, shape (..., 6, p)
        Unit twists of the passive joints.
    elastic, elastic_stiffness : ndarray, shape (..., 6, e) and (..., e), optional
        Unit twists of the elastic freedoms and their stiffnesses.

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
    if elastic is not None and elastic_stiffness is not None:
        q = np.concatenate([q, elastic * scale[:, None]], axis=-1)
    p = q.shape[-1]
    n = 6 + p
    batch = c.shape[:-2]
    bordered = np.zeros(batch + (n, n))
    bordered[..., :6, :6] = c
    bordered[..., :6, 6:] = q
    bordered[..., 6:, :6] = np.swapaxes(q, -1, -2)
    if elastic is not None and elastic_stiffness is not None:
        e = np.shape(elastic_stiffness)[-1]
        k_e = np.asarray(elastic_stiffness, dtype=float)
        idx = np.arange(n - e, n)
        bordered[..., idx, idx] = -k_e
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
    if leg.elastic_count:
        assert leg.elastic is not None and leg.elastic_stiffness is not None
        h = np.swapaxes(w, -1, -2) @ leg.elastic  # (..., r, e)
        return elastic_stiffness(w, reduced, h, leg.elastic_stiffness)
    reduced = 0.5 * (reduced + np.swapaxes(reduced, -1, -2))
    try:
        inv = np.linalg.inv(reduced)
    except np.linalg.LinAlgError as exc:
        raise SingularConfigurationError(
            "a leg's springs leave a wrench it transmits uncompliant"
        ) from exc
    k = w @ inv @ np.swapaxes(w, -1, -2)
    return np.asarray(0.5 * (k + np.swapaxes(k, -1, -2)))


def elastic_stiffness(
    basis: FloatArray, compliance: FloatArray, elastic: FloatArray, stiffness: ArrayLike
) -> FloatArray:
    """K (..., 6, 6) of a leg with e elastic freedoms by the bordered form in the W
    basis (module doc): ``K = W X W^T`` with X the upper-left r x r block of
    ``[[A, H], [H^T, -K_e]]^-1``.

    Parameters
    ----------
    basis : ndarray, shape (..., 6, r)
        W, reciprocal to the passive twists (:func:`reciprocal_basis`).
    compliance : ndarray, shape (..., r, r)
        ``A = W^T J C J^T W`` (the actuator's compliance included), symmetric.
    elastic : ndarray, shape (..., r, e)
        ``H = W^T J_e``: the generalised force on each elastic freedom per basis wrench.
    stiffness : array_like, shape (..., e)
        K_e [N·m/rad or N/m], positive and finite.

    Raises
    ------
    SingularConfigurationError
        The bordered matrix is singular (elastic freedoms dependent on each other or on
        the passive joints, or a transmitted wrench that no spring yields to).
    """
    r, e = compliance.shape[-1], elastic.shape[-1]
    k_e = np.broadcast_to(np.asarray(stiffness, dtype=float), compliance.shape[:-2] + (e,))
    bordered = np.zeros(compliance.shape[:-2] + (r + e, r + e))
    bordered[..., :r, :r] = 0.5 * (compliance + np.swapaxes(compliance, -1, -2))
    bordered[..., :r, r:] = elastic
    bordered[..., r:, :r] = np.swapaxes(elastic, -1, -2)
    idx = np.arange(r, r + e)
    bordered[..., idx, idx] = -k_e
    try:
        inv = np.linalg.inv(bordered)
    except np.linalg.LinAlgError as exc:
        raise SingularConfigurationError(
            "a leg's elastic freedoms are dependent (on each other or its passive joints) "
            "or its springs leave a wrench it transmits uncompliant"
        ) from exc
    k = basis @ inv[..., :r, :r] @ np.swapaxes(basis, -1, -2)
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
