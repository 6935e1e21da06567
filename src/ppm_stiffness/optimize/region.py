"""The required workspace region: a grid of poses a design must cover.

A region is a :class:`~ppm_stiffness.design.schema.RequiredRegionModel` (the design
file's ``[workspace.required]`` table, or the commands' ``--region`` override): ranges
of x, y [m] and phi [rad] and the number of grid values along each, ends included.
A design *covers* the region when every grid pose is reachable (every leg's inverse
kinematics solvable, joint coordinates within limits) and not singular (the
transmission index of :mod:`ppm_stiffness.core.singularity` above its
``SINGULARITY_TOLERANCE``).
Only the grid poses are tested: a singularity or a workspace hole between grid points
can be missed.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import RequiredRegionModel

__all__ = [
    "RequiredRegionModel",
    "make_region",
    "region_axes",
    "region_of",
    "region_poses",
    "with_region",
]


def make_region(
    x: tuple[float, float],
    y: tuple[float, float],
    phi: tuple[float, float],
    grid: tuple[int, int, int],
) -> RequiredRegionModel:
    """A validated region from ranges [m, m, rad] and grid counts.

    Raises
    ------
    DesignError
        A range inverted or out of the plausible SI values, a grid count below 1, or a
        grid inconsistent with its range (the message names the key).
    """
    from pydantic import ValidationError

    data: dict[str, Any] = {"x": x, "y": y, "phi": phi, "grid": grid}
    try:
        return RequiredRegionModel.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        key = ".".join(str(p) for p in first["loc"])
        msg = str(first["msg"]).removeprefix("Value error, ")
        raise DesignError(f"region: {key + ': ' if key else ''}{msg}") from None


def region_of(design: Design, override: RequiredRegionModel | None = None) -> RequiredRegionModel:
    """The region to evaluate: ``override`` if given, else ``[workspace.required]``.

    Raises
    ------
    DesignError
        If neither is given.
    """
    if override is not None:
        return override
    region = design.workspace.required
    if region is None:
        raise DesignError(
            f"design {design.name!r} has no required region: add a [workspace.required] "
            "table (x, y, phi ranges [m, rad] and grid) or pass --region"
        )
    return region


def with_region(design: Design, region: RequiredRegionModel) -> Design:
    """A copy of ``design`` whose ``[workspace.required]`` is ``region``."""
    workspace = design.workspace.model_copy(update={"required": region})
    return design.model_copy(update={"workspace": workspace})


def region_axes(region: RequiredRegionModel) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The grid values x (nx,), y (ny,) [m] and phi (nphi,) [rad]."""
    nx, ny, nphi = region.grid
    return (
        np.linspace(region.range("x")[0], region.range("x")[1], nx),
        np.linspace(region.range("y")[0], region.range("y")[1], ny),
        np.linspace(region.range("phi")[0], region.range("phi")[1], nphi),
    )


def region_poses(region: RequiredRegionModel) -> FloatArray:
    """Every grid pose of the region, shape (nphi, ny, nx, 3): (x [m], y [m], phi [rad])."""
    x, y, phi = region_axes(region)
    pp, yy, xx = np.meshgrid(phi, y, x, indexing="ij")
    return np.stack([xx, yy, pp], axis=-1)
