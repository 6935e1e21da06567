"""The required workspace region: a grid of poses a design must cover.

A region is a :class:`~ppm_stiffness.design.schema.RequiredRegionModel` (the design
file's ``[workspace.required]`` table, or the commands' ``--region`` override): ranges
of the design's task coordinates (x, y [m] and phi [rad] for a planar design; all six
for a hexapod; z [m], rx, ry [rad] for a 3-PRS or 3-RPS tripod) and the number of grid
values along each, ends included. The dependent coordinates of a grid pose (a tripod's
parasitic x, y, rz) follow from the legs (:func:`ppm_stiffness.poses.full_poses`).
A design *covers* the region when every grid pose is reachable (every leg's inverse
kinematics solvable, joint coordinates within limits) and not singular (the
transmission index of :mod:`ppm_stiffness.core.singularity` above its
``SINGULARITY_TOLERANCE``).
Only the grid poses are tested: a singularity or a workspace hole between grid points
can be missed.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.core.pose import POSE_COORDINATES
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import REGION_KEYS, RequiredRegionModel

__all__ = [
    "RequiredRegionModel",
    "make_region",
    "region_axes",
    "region_coordinates",
    "region_of",
    "region_poses",
    "region_from_ranges",
    "with_region",
]


def make_region(
    x: tuple[float, float],
    y: tuple[float, float],
    phi: tuple[float, float],
    grid: tuple[int, int, int],
) -> RequiredRegionModel:
    """A validated planar region from ranges [m, m, rad] and grid counts.

    Raises
    ------
    DesignError
        A range inverted or out of the plausible SI values, a grid count below 1, or a
        grid inconsistent with its range (the message names the key).
    """
    return region_from_ranges({"x": x, "y": y, "rz": phi}, grid)


def region_from_ranges(
    ranges: Mapping[str, tuple[float, float]], grid: Sequence[int]
) -> RequiredRegionModel:
    """A validated region from ranges of task coordinates and their grid counts.

    Parameters
    ----------
    ranges : mapping of str to (lo, hi)
        Pose coordinate name (x, y, z [m], rx, ry, rz [rad]; ``phi`` for rz) -> range,
        in pose order.
    grid : sequence of int
        Grid values along each range, in the same order.

    Raises
    ------
    DesignError
        A range inverted or out of the plausible SI values, a grid count below 1, or a
        grid inconsistent with its range (the message names the key).
    """
    from pydantic import ValidationError

    data: dict[str, Any] = {
        REGION_KEYS[POSE_COORDINATES.index("rz" if k == "phi" else k)]: tuple(v)
        for k, v in ranges.items()
    }
    data["grid"] = tuple(grid)
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
            f"table (ranges of {', '.join(design.task_coordinates)} [m, rad] and grid) or "
            "pass --region"
        )
    _check_angles_in_radians(design, region)
    return region


def _check_angles_in_radians(design: Design, region: RequiredRegionModel) -> None:
    """Refuse an angle range of ``[workspace.required]`` typed in degrees: neither end
    reachable (the other task coordinates at the home pose) while both ends read as
    degrees are (``rz = [-3, 3]`` on the hexapod, meant as +-3 deg, passed the |angle|
    <= pi check of the schema and covered a third of the region).

    Raises
    ------
    DesignError
        Naming the key, the range and the likely range in radians.
    """
    import math

    from ppm_stiffness.core.pose import ANGLE_COORDINATES
    from ppm_stiffness.maps.reach import reachable_values
    from ppm_stiffness.poses import home_pose

    for name, (lo, hi) in region.ranges().items():
        if name not in ANGLE_COORDINATES or lo == hi:
            continue
        meant = (math.radians(lo), math.radians(hi))
        home = home_pose(design)
        ends, ends_meant = (reachable_values(design, home, name, v) for v in ((lo, hi), meant))
        if not ends.any() and ends_meant.all():
            key = (
                "rz"
                if name == "rz" and not design.planar
                else REGION_KEYS[POSE_COORDINATES.index(name)]
            )
            raise DesignError(
                f"design {design.name!r}: key 'workspace.required.{key}': {key} = [{lo:g}, "
                f"{hi:g}]: neither end is reachable (the other task coordinates at the "
                f"home pose), while both are read as degrees; angles in design files are "
                f"in radians: did you mean [{meant[0]:.6g}, {meant[1]:.6g}]?"
            )


def with_region(design: Design, region: RequiredRegionModel) -> Design:
    """A copy of ``design`` whose ``[workspace.required]`` is ``region``."""
    workspace = design.workspace.model_copy(update={"required": region})
    return design.model_copy(update={"workspace": workspace})


def region_coordinates(region: RequiredRegionModel) -> tuple[str, ...]:
    """The pose coordinates the region ranges over, in pose order (``("x", "y", "rz")``
    for a planar region)."""
    return tuple(region.ranges())


def region_axes(region: RequiredRegionModel) -> tuple[FloatArray, ...]:
    """The grid values along each range [m or rad], in pose order (x (nx,), y (ny,),
    phi (nphi,) for a planar region)."""
    return tuple(
        np.linspace(lo, hi, n)
        for (lo, hi), n in zip(region.ranges().values(), region.grid, strict=True)
    )


def region_poses(region: RequiredRegionModel) -> FloatArray:
    """Every grid pose of the region in task coordinates, shape (n_last, ..., n_first,
    n_task): the last coordinate varies slowest (a planar region: (nphi, ny, nx, 3) of
    (x [m], y [m], phi [rad]))."""
    axes = region_axes(region)
    mesh = np.meshgrid(*axes[::-1], indexing="ij")
    return np.stack(mesh[::-1], axis=-1)
