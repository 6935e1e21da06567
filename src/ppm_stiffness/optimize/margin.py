"""The load margin over a required region, on a coarse sub-grid of it.

The load margin of a wrench at a pose (:mod:`ppm_stiffness.statics.margin`, docs/statics.md)
is the smallest factor lambda at which the loaded tangent stiffness along the load path
``lambda w`` becomes singular; it is found by continuation, about 0.1 s per pose on this
project's examples, far more than the stiffness (microseconds per pose). The region
summary therefore evaluates it on the **margin sub-grid**: along each coordinate of the
region the :data:`MARGIN_VALUES` grid values at its ends (one where the range is a single
value), i.e. the 2^d corner poses of the region for d coordinates that vary (8 for a
planar or tripod region, 64 for a hexapod's). These are grid poses of the region. Between
them the margin is not checked: a minimum inside the region can be missed (the outputs say
so).

The figure of a pose is the factor at the first instability (a bifurcation or a limit
point); where none is found it is the largest factor with a stable equilibrium:
:data:`~ppm_stiffness.statics.margin.MAX_FACTOR` ("no instability up to 1000 times the
load") or, when an actuator reaches its whole stroke first, the factor where it does. A
constraint ``load-margin>=VALUE`` with VALUE up to those is met by them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import RequiredRegionModel
from ppm_stiffness.optimize.region import region_axes

#: Grid values per coordinate of the margin sub-grid: its two ends.
MARGIN_VALUES = 2


def margin_indices(region: RequiredRegionModel) -> tuple[FloatArray, ...]:
    """The indices (into each coordinate's grid values) of the margin sub-grid."""
    return tuple(
        np.unique(np.linspace(0, n - 1, min(n, MARGIN_VALUES)).round().astype(int))
        for n in region.grid
    )


def margin_poses(region: RequiredRegionModel) -> FloatArray:
    """The margin sub-grid (m, n_task) in task coordinates [m, rad], first coordinate
    fastest (the order of :func:`~ppm_stiffness.optimize.region.region_poses`)."""
    axes = [a[i] for a, i in zip(region_axes(region), margin_indices(region), strict=True)]
    mesh = np.meshgrid(*axes[::-1], indexing="ij")
    return np.stack(mesh[::-1], axis=-1).reshape(-1, len(axes))


def region_margins(
    design: Design, poses: ArrayLike, wrench: ArrayLike
) -> tuple[FloatArray, BoolArray]:
    """The load margin of ``wrench`` at the tool point at each pose (module doc).

    Parameters
    ----------
    design : Design
    poses : array_like (m, n_task)
        Task coordinates [m, rad].
    wrench : array_like (6,)
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at the design's tool point, axes of F_b.

    Returns
    -------
    margins : ndarray (m,)
        The factor [1] (module doc); NaN where the unloaded pose is refused.
    refused : ndarray of bool (m,)
        The unloaded pose is unreachable or singular.
    """
    from ppm_stiffness.statics.margin import MarginKind, margin_batch

    batch = margin_batch(design, poses, wrench, tool_point=design.tool_point)
    found = np.isfinite(batch.factor)
    refused = np.asarray(batch.kind) == int(MarginKind.REFUSED)
    margins = np.where(found, batch.factor, batch.searched_up_to)
    return np.where(refused, np.nan, margins), refused
