"""The singularity mask of the batched paths: False exactly where the single-pose API
refuses a pose as singular (:func:`ppm_stiffness.model.stiffness_at_pose`).

The test is the single-pose API's: K finite and the transmission index of
:mod:`ppm_stiffness.core.singularity` above ``SINGULARITY_TOLERANCE``, decided on the
legs' summed projector ``Pi`` (length-balanced). By blocks for planar K
(:func:`nonsingular_from_entries`, through
:func:`~ppm_stiffness.core.singularity.nonsingular_blocks`, which clears most poses by a
cheap bound), or on the 6x6 ``Pi`` of any design (:func:`nonsingular_from_matrices`):
there a cheap sufficient test clears most poses too and only the others get the exact
index (:func:`nonsingular_projector`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.singularity import (
    SINGULARITY_TOLERANCE,
    nonsingular,
    nonsingular_blocks,
    transmission_index,
)
from ppm_stiffness.maps.reduced_path import PlanarEntries


def _finite(e: PlanarEntries) -> BoolArray:
    finite = np.isfinite(e.k22)
    for value in e[1:]:
        finite = finite & np.isfinite(value)
    return np.asarray(finite)


def nonsingular_from_entries(stiffness: PlanarEntries, projector: PlanarEntries) -> BoolArray:
    """Boolean array: False exactly where the single-pose API refuses the pose as singular
    (:func:`ppm_stiffness.model.stiffness_at_pose`): K not finite, or the transmission
    index of ``Pi`` at or below the tolerance (:mod:`ppm_stiffness.core.singularity`).

    Parameters
    ----------
    stiffness : PlanarEntries
        K's entries; their shape is the batch shape.
    projector : PlanarEntries
        ``Pi``'s entries (broadcastable to it): :func:`reduced_projector` or the planar
        engine's (:func:`planar_engine_entries`).
    """
    shape = np.shape(stiffness.k22)
    pi = [np.broadcast_to(np.asarray(v, dtype=float), shape) for v in projector]
    return np.asarray(_finite(stiffness) & nonsingular_blocks(list(pi[:6]), list(pi[6:]), shape))


def nonsingular_from_matrices(stiffness: ArrayLike, projector: ArrayLike) -> BoolArray:
    """Boolean array (...): False exactly where the single-pose API refuses the pose as
    singular, from K (..., 6, 6) and the legs' summed projector ``Pi`` (..., 6, 6) (any
    K, planar or not)."""
    k = np.asarray(stiffness, dtype=float)
    finite = np.all(np.isfinite(k), axis=(-2, -1))
    return np.asarray(finite & nonsingular_projector(projector))


#: The cheap bound clears a pose when it exceeds the tolerance by this factor (room for
#: the rounding of the determinant, a relative 1e-9 at a condition number of 1e6).
BOUND_MARGIN = 2.0


def nonsingular_projector(projector: ArrayLike) -> BoolArray:
    """:func:`~ppm_stiffness.core.singularity.nonsingular` of
    :func:`~ppm_stiffness.core.singularity.transmission_index` of ``Pi`` (..., 6, 6),
    cheaply where a bound decides.

    ``Pi`` is symmetric positive semi-definite (a sum of projectors). With its
    determinant ``det`` and trace ``t``, the product of its five largest eigenvalues
    is at most ``(t / 5)^5`` (arithmetic-geometric mean) and the largest is at most
    ``t``, so ``tau = lambda_min / lambda_max >= det (5 / t)^5 / t``. Poses where this
    bound exceeds :data:`BOUND_MARGIN` times the tolerance are nonsingular; the others
    (and non-finite ``Pi``) get the exact index. The bound costs a batched LU
    determinant (0.3 us per pose against 1.6 us for the eigenvalues).
    """
    p = np.asarray(projector, dtype=float)
    shape = p.shape[:-2]
    flat = p.reshape(-1, 6, 6)
    finite = np.all(np.isfinite(flat), axis=(1, 2))
    safe = flat if np.all(finite) else np.where(finite[:, None, None], flat, 0.0)
    with np.errstate(all="ignore"):
        trace = np.trace(safe, axis1=1, axis2=2)
        bound: FloatArray = np.linalg.det(safe) * (5.0 / trace) ** 5 / trace
        sure = finite & (bound > BOUND_MARGIN * SINGULARITY_TOLERANCE)
    result = np.array(sure, dtype=bool, copy=True)
    if not np.all(sure):
        unsure = ~sure
        result[unsure] = nonsingular(transmission_index(flat[unsure]))
    return result.reshape(shape)
