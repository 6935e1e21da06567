"""The slice a map covers: two task coordinates over a grid, the others fixed.

A map of a design is a 2-D slice of its task space (:attr:`Design.task_coordinates`):
two of the task coordinates, the *axes*, vary over a grid; the others are *fixed*; the
dependent coordinates (a tripod's x, y and rz) follow at every grid point from the legs'
constraints (:func:`ppm_stiffness.poses.full_poses`). Planar designs: x-y at a given
phi (rz), as ever; a hexapod: x-y at a given z and orientation, or rx-ry at a given
position, ...; a tripod: rx-ry at a given z, or z-rx at a given ry.

Defaults (:func:`map_slice`): the axes x, y when both are task coordinates, else the
first two task coordinates; each fixed coordinate the home pose's value
(:func:`ppm_stiffness.poses.home_pose`), except a planar design's rz, 0 when not
given (the library's default orientation, as before).

Bounds of a slice (:func:`slice_bounds`), when none are given: the reachable extent
along the slice. For a planar design's x-y slice the exact or sampled box of
:mod:`ppm_stiffness.maps.bounds`. For any other slice, sampled: reachability (the
pose completed, every leg's inverse kinematics solvable and its joint coordinates
within limits, U and S joint angle limits included) on a :data:`SEARCH` x
:data:`SEARCH` grid around the base pose's values of the two axes, over a half-width of
twice the largest distance from P to a named leg point for a length and 0.5 rad for an
angle (angles within [-pi, pi]), doubled along an axis while reachable samples touch
its edges (a window with no reachable sample is sampled again at :data:`COARSE` and
4 :data:`COARSE` points per axis before the slice is declared unreachable); then the
grid is resampled :data:`TIGHTEN` times on the box of its reachable samples (one cell
wider each side), the last time at :data:`COARSE` x :data:`COARSE` points. The result
is the box of the last grid's reachable samples: an inner box, within one cell (1 % of
its size) of the sampled extent; a part of the slice narrower than a search cell and
disconnected from the rest may be missed. Singular
poses are not excluded (as for the planar bounds). Boxes are cached per design object.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import DesignError, InputDataError, UnreachablePoseError
from ppm_stiffness.core.pose import ANGLE_COORDINATES, POSE_COORDINATES, POSE_INDEX
from ppm_stiffness.design import Design
from ppm_stiffness.maps.bounds import workspace_bounds
from ppm_stiffness.poses import full_poses, home_pose

#: Sampled slice bounds: grid points per axis of the search (most of its samples lie
#: far outside the reachable extent, where a chain leg's inverse kinematics continues
#: longest) and of the last resampling, resamplings, most doublings of a window.
SEARCH = 31
COARSE = 101
TIGHTEN = 2
MAX_DOUBLINGS = 12
#: First half-width of the search window of an angle axis [rad].
ANGLE_HALF_WIDTH = 0.5
#: Relative inward margin of the grid so that no grid point lies on a joint limit.
EDGE_MARGIN = 1e-9


def unit_of(name: str) -> str:
    """The SI unit of a pose coordinate: "m" or "rad"."""
    return "rad" if name in ANGLE_COORDINATES else "m"


def cli_scale(name: str) -> tuple[float, str]:
    """Factor and unit of a coordinate in the CLI's units: (1e3, "mm") or (deg, "deg")."""
    return (180.0 / math.pi, "deg") if name in ANGLE_COORDINATES else (1e3, "mm")


@dataclass(frozen=True)
class MapSlice:
    """Two task coordinates over a grid, the others fixed.

    Attributes
    ----------
    axes : (str, str)
        The two task coordinates that vary (pose names: x, y, z, rx, ry, rz).
    fixed : dict of str to float
        The other task coordinates [m or rad], in pose order.
    base : ndarray (n_task,)
        The task values of the slice's base pose: the fixed values, and the home pose's
        values of the axes (the centre of the search for bounds).
    task : tuple of str
        The design's task coordinates.
    """

    axes: tuple[str, str]
    fixed: dict[str, float]
    base: FloatArray
    task: tuple[str, ...]

    def task_values(self, u: ArrayLike, v: ArrayLike) -> FloatArray:
        """Task values (..., n_task) of the grid points (u, v) (broadcast) of the axes."""
        ub, vb = np.broadcast_arrays(np.asarray(u, dtype=float), np.asarray(v, dtype=float))
        out = np.empty(ub.shape + (len(self.task),))
        out[...] = self.base
        out[..., self.task.index(self.axes[0])] = ub
        out[..., self.task.index(self.axes[1])] = vb
        return out

    def label(self) -> str:
        """``"z = 200 mm, rx = 0 deg"``: the fixed coordinates in the CLI's units."""
        parts = []
        for name, value in self.fixed.items():
            scale, unit = cli_scale(name)
            parts.append(f"{name} = {value * scale:.4g} {unit}")
        return ", ".join(parts)


def _name(text: str) -> str:
    return "rz" if text == "phi" else text


def map_slice(
    design: Design,
    axes: tuple[str, str] | list[str] | None = None,
    fixed: Mapping[str, float] | None = None,
    phi: float | None = None,
) -> MapSlice:
    """The slice of a map (module doc: defaults).

    Parameters
    ----------
    design : Design
    axes : (str, str), optional
        Two distinct task coordinates ("phi" is a name of rz).
    fixed : mapping of str to float, optional
        Values [m or rad] of task coordinates that are not axes.
    phi : float, optional
        rz [rad] (the planar orientation), as ``fixed={"rz": phi}``.

    Raises
    ------
    InputDataError
        An axis or fixed coordinate that is not a task coordinate (the message names
        the task coordinates), two equal axes, a fixed coordinate that is an axis or
        given twice, a value that is not finite.
    """
    task = tuple(design.task_coordinates)
    names = ", ".join(task)
    if axes is None:
        chosen = ("x", "y") if {"x", "y"} <= set(task) else (task[0], task[1])
    else:
        if len(axes) != 2:
            raise InputDataError(f"a map has two axes, got {len(axes)}: {', '.join(axes)}")
        chosen = (_name(axes[0]), _name(axes[1]))
    for name in chosen:
        if name not in task:
            raise InputDataError(
                f"map axis {name!r} is not a task coordinate of {design.name!r}: its task "
                f"coordinates are {names}"
            )
    if chosen[0] == chosen[1]:
        raise InputDataError(f"the two axes of a map must differ, got {chosen[0]} twice")
    given: dict[str, float] = {}
    items = list((fixed or {}).items()) + ([] if phi is None else [("rz", phi)])
    for key, value in items:
        name = _name(key)
        if name not in task:
            raise InputDataError(
                f"fixed coordinate {name!r} is not a task coordinate of {design.name!r}: "
                f"fix only {', '.join(n for n in task if n not in chosen)} (the others "
                "follow from the legs)"
            )
        if name in chosen:
            raise InputDataError(
                f"{name} is an axis of the map: fix only the other task coordinates "
                f"({', '.join(n for n in task if n not in chosen) or 'none'})"
            )
        if name in given:
            raise InputDataError(f"fixed coordinate {name} given twice (phi is rz)")
        if not math.isfinite(float(value)):
            raise InputDataError(f"fixed coordinate {name} must be finite, got {value}")
        given[name] = float(value)
    if design.planar and "rz" not in given and "rz" not in chosen:
        given["rz"] = 0.0
    home = home_pose(design)
    base = np.array([given.get(name, float(home[POSE_INDEX[name]])) for name in task])
    ordered = {n: float(base[task.index(n)]) for n in POSE_COORDINATES if n in task}
    kept = {n: v for n, v in ordered.items() if n not in chosen}
    return MapSlice(chosen, kept, base, task)


def slice_reachable(design: Design, sl: MapSlice, u: ArrayLike, v: ArrayLike) -> BoolArray:
    """Mask (broadcast shape of u, v) of the grid points that are reachable: the pose
    completed, every leg's IK solvable and its joint coordinates within limits."""
    values = sl.task_values(u, v)
    full, ok = full_poses(design, values.reshape(-1, values.shape[-1]))
    with np.errstate(all="ignore"):
        for leg in design.legs:
            ok &= np.asarray(leg.reachable(leg.solve(full)), dtype=bool)
    return ok.reshape(values.shape[:-1])


def _half_width(design: Design, sl: MapSlice, name: str) -> float:
    """The first half-width of the search window along an axis [m or rad]."""
    if name in ANGLE_COORDINATES:
        return ANGLE_HALF_WIDTH
    size = 0.0
    full, _ = full_poses(design, sl.base)
    for pose in (full, home_pose(design)):
        for leg in design.legs:
            with np.errstate(all="ignore"):
                points = leg.solve(pose).points.values()
            for point in points:
                value = float(np.linalg.norm(point))
                if np.isfinite(value):
                    size = max(size, value)
        if size > 0:
            break
    return 2.0 * size if size > 0 else 1.0


def _window(centre: float, half: float, angle: bool, count: int = COARSE) -> FloatArray:
    lo, hi = centre - half, centre + half
    if angle:
        lo, hi = max(lo, -math.pi), min(hi, math.pi)
    return np.linspace(lo, hi, count)


def _sampled_slice_bounds(design: Design, sl: MapSlice) -> FloatArray:
    """Box (u_min, u_max, v_min, v_max) of the reachable samples of a slice (module doc)."""
    angle = [name in ANGLE_COORDINATES for name in sl.axes]
    centre = [float(sl.base[sl.task.index(name)]) for name in sl.axes]
    half = [_half_width(design, sl, name) for name in sl.axes]
    for _ in range(MAX_DOUBLINGS):
        for count in (SEARCH, COARSE, 4 * COARSE):
            us, vs = (_window(centre[k], half[k], angle[k], count) for k in range(2))
            mask = slice_reachable(design, sl, us[None, :], vs[:, None])
            if mask.any():
                break
        else:
            raise UnreachablePoseError(
                f"no reachable pose of the {sl.axes[0]}-{sl.axes[1]} slice"
                + (f" at {sl.label()}" if sl.fixed else "")
                + ": the joint limits of the design exclude it"
            )
        grow = False
        for k, (edges, values) in enumerate(
            (((mask[:, 0], mask[:, -1]), us), ((mask[0], mask[-1]), vs))
        ):
            at_limit = angle[k] and values[0] <= -math.pi and values[-1] >= math.pi
            if (edges[0].any() or edges[1].any()) and not at_limit:
                half[k] *= 2.0
                grow = True
        if not grow:
            break
    else:
        raise DesignError(
            f"the {sl.axes[0]}-{sl.axes[1]} slice reaches beyond the search window: check "
            "the joint limits"
        )
    for count in [SEARCH] * (TIGHTEN - 1) + [COARSE]:
        cols, rows = np.flatnonzero(mask.any(axis=0)), np.flatnonzero(mask.any(axis=1))
        du, dv = us[1] - us[0], vs[1] - vs[0]
        lo_u, hi_u = us[cols[0]] - du, us[cols[-1]] + du
        lo_v, hi_v = vs[rows[0]] - dv, vs[rows[-1]] + dv
        if angle[0]:
            lo_u, hi_u = max(lo_u, -math.pi), min(hi_u, math.pi)
        if angle[1]:
            lo_v, hi_v = max(lo_v, -math.pi), min(hi_v, math.pi)
        u_new, v_new = np.linspace(lo_u, hi_u, count), np.linspace(lo_v, hi_v, count)
        m_new = slice_reachable(design, sl, u_new[None, :], v_new[:, None])
        if not m_new.any():  # thinner than the new cells: keep the last samples
            break
        us, vs, mask = u_new, v_new, m_new
    cols, rows = np.flatnonzero(mask.any(axis=0)), np.flatnonzero(mask.any(axis=1))
    return np.array([us[cols[0]], us[cols[-1]], vs[rows[0]], vs[rows[-1]]])


#: Sampled slice boxes: id(design) -> (design, {(axes, fixed): box}) (as the planar ones).
_CACHE: dict[int, tuple[Design, dict[tuple[object, ...], FloatArray]]] = {}
_CACHE_DESIGNS = 8
_CACHE_SLICES = 64


def slice_bounds(design: Design, sl: MapSlice) -> FloatArray:
    """Box (u_min, u_max, v_min, v_max) [m or rad] of the reachable extent of a slice
    (module doc).

    Raises
    ------
    UnreachablePoseError
        If no pose of the slice is reachable.
    """
    if design.planar and sl.axes == ("x", "y"):
        return workspace_bounds(design, sl.fixed["rz"])
    entry = _CACHE.get(id(design))
    if entry is None or entry[0] is not design:
        if len(_CACHE) >= _CACHE_DESIGNS:
            _CACHE.pop(next(iter(_CACHE)))
        entry = (design, {})
        _CACHE[id(design)] = entry
    key = (sl.axes, tuple(sl.base.tolist()))
    box = entry[1].get(key)
    if box is None:
        box = _sampled_slice_bounds(design, sl)
        if len(entry[1]) >= _CACHE_SLICES:
            entry[1].pop(next(iter(entry[1])))
        entry[1][key] = box
    return box.copy()


def slice_grid(
    design: Design,
    sl: MapSlice,
    grid: int | tuple[int, int] = 200,
    bounds: ArrayLike | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Grid values of the two axes, (nu,) and (nv,) [m or rad], over ``bounds`` (u_min,
    u_max, v_min, v_max) or the slice's reachable extent (:func:`slice_bounds`, shrunk
    by a relative 1e-9 so that no grid point sits exactly on a limit)."""
    nu, nv = (grid, grid) if isinstance(grid, (int, np.integer)) else grid
    if int(nu) < 2 or int(nv) < 2:
        raise InputDataError(f"a map grid needs at least 2 x 2 points, got {nu} x {nv}")
    if bounds is None:
        box = slice_bounds(design, sl)
        spans = [box[1] - box[0], box[3] - box[2]]
        same = unit_of(sl.axes[0]) == unit_of(sl.axes[1])
        for k in range(2):
            margin = EDGE_MARGIN * max(*(spans if same else spans[k : k + 1]), 1e-6)
            box[2 * k] += margin
            box[2 * k + 1] -= margin
    else:
        box = np.asarray(bounds, dtype=float)
        a, b = sl.axes
        if box.shape != (4,) or not np.all(np.isfinite(box)):
            raise InputDataError(
                f"bounds must be 4 finite numbers {a}_min, {a}_max, {b}_min, {b}_max"
            )
        if not (box[0] < box[1] and box[2] < box[3]):
            raise InputDataError(f"bounds must have {a}_min < {a}_max and {b}_min < {b}_max")
    return np.linspace(box[0], box[1], int(nu)), np.linspace(box[2], box[3], int(nv))
