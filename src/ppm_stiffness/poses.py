"""Poses of a design: its task coordinates, the completed 6-D pose, the home pose.

A pose is six coordinates (x, y, z, rx, ry, rz) [m, rad] (:mod:`ppm_stiffness.core
.pose`). A design's task coordinates (:attr:`~ppm_stiffness.design.Design
.task_coordinates`) are those a user gives; the dependent ones follow from the legs'
constraints (:func:`ppm_stiffness.legs.completion.complete_poses`), solved by Newton
from the home pose's values. Functions of the library that take a pose take either

- the task coordinates, shape (..., n_task) in pose order: ``(x, y, phi)`` for a
  planar design (as ever), ``(z, rx, ry)`` for a tripod, all six for a hexapod; or
- a full pose, shape (..., 6), whose dependent coordinates must be the completed ones
  (to :data:`DEPENDENT_TOLERANCE`): giving a dependent coordinate another value is an
  error that names the task coordinates.

The home pose is the workspace centre of the design file (``centre_x``, ...,
``phi``), completed.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import InputDataError, UnreachablePoseError
from ppm_stiffness.core.pose import ANGLE_COORDINATES, POSE_COORDINATES, POSE_INDEX
from ppm_stiffness.design import Design
from ppm_stiffness.legs.completion import complete_poses

#: Largest difference [m or rad] between a given dependent coordinate and the
#: completed one.
DEPENDENT_TOLERANCE = 1e-9


def task_indices(design: Design) -> tuple[int, ...]:
    """Indices (into x, y, z, rx, ry, rz) of the design's task coordinates."""
    return tuple(POSE_INDEX[name] for name in design.task_coordinates)


def dependent_indices(design: Design) -> tuple[int, ...]:
    """Indices of the coordinates that follow from the legs' constraints."""
    task = set(task_indices(design))
    return tuple(i for i in range(6) if i not in task)


#: Completed home poses: id(design) -> (design, pose). A design is frozen, so its home
#: pose is computed once per design object (the entry keeps it alive).
_HOME: dict[int, tuple[Design, FloatArray]] = {}
_HOME_SIZE = 16


def home_pose(design: Design) -> FloatArray:
    """The completed home pose (6,) [m, rad] (module doc).

    Raises
    ------
    UnreachablePoseError
        If the legs' constraints cannot be met from the file's home values.
    """
    entry = _HOME.get(id(design))
    if entry is not None and entry[0] is design:
        return entry[1].copy()
    start = np.array(design.workspace.start(), dtype=float)
    pose, ok = complete_poses(design.legs, dependent_indices(design), start)
    if not bool(ok):
        raise UnreachablePoseError(
            f"the home pose of {design.name!r} ({format_pose(start)}): the legs' "
            "constraints cannot be met there (the completion did not converge)"
        )
    if len(_HOME) >= _HOME_SIZE:
        _HOME.pop(next(iter(_HOME)))
    _HOME[id(design)] = (design, pose)
    return pose.copy()


def full_poses(design: Design, poses: ArrayLike) -> tuple[FloatArray, BoolArray]:
    """Full poses (..., 6) from task coordinates (..., n_task) or full poses (..., 6).

    Returns
    -------
    poses : ndarray (..., 6)
        Completed (module doc); where the completion failed, the last iterate.
    completed : ndarray of bool (...)
        The legs' constraints are met (and, for full poses given, their dependent
        coordinates were the completed ones).

    Raises
    ------
    InputDataError
        Poses of another width, or not finite.
    """
    p = np.asarray(poses, dtype=float)
    task = task_indices(design)
    width = p.shape[-1] if p.ndim else 0
    if width not in (len(task), 6):
        names = ", ".join(design.task_coordinates)
        raise InputDataError(
            f"a pose of {design.name!r} has {len(task)} task coordinates ({names}) or "
            f"6 coordinates (x, y, z, rx, ry, rz), got shape {p.shape}"
        )
    if not np.all(np.isfinite(p)):
        raise InputDataError("pose coordinates must be finite")
    dependent = dependent_indices(design)
    if design.planar:
        # planar legs' residuals (z, n_x, n_y) vanish exactly at z = rx = ry = 0
        if width == 3:
            full = np.zeros(p.shape[:-1] + (6,))
            full[..., list(task)] = p
            return full, np.ones(p.shape[:-1], dtype=bool)
        ok = np.all(np.abs(p[..., list(dependent)]) <= DEPENDENT_TOLERANCE, axis=-1)
        full = p.copy()
        full[..., list(dependent)] = 0.0
        return full, ok
    if width == 6 and len(task) < 6:
        full = p.copy()
        given = p[..., list(dependent)]
    else:
        full = np.broadcast_to(home_pose(design), p.shape[:-1] + (6,)).copy()
        full[..., list(task)] = p
        given = None
    done, ok = complete_poses(design.legs, dependent, full)
    if given is not None:
        ok = ok & np.all(np.abs(done[..., list(dependent)] - given) <= DEPENDENT_TOLERANCE, -1)
    return done, np.asarray(ok)


def full_pose(design: Design, pose: ArrayLike | None = None) -> FloatArray:
    """One full pose (6,) from task coordinates or a full pose; the home pose if None.

    Raises
    ------
    InputDataError
        A pose of the wrong width, not finite, or a full pose whose dependent
        coordinates are not the ones the legs impose (the message names the task
        coordinates and the imposed values).
    UnreachablePoseError
        If the legs' constraints cannot be met (the completion did not converge).
    """
    if pose is None:
        return home_pose(design)
    p = np.asarray(pose, dtype=float)
    if p.ndim != 1:
        raise InputDataError(f"one pose is a vector, got shape {p.shape}")
    done, ok = full_poses(design, p)
    if bool(ok):
        return done
    if p.shape == (6,) and len(design.task_coordinates) < 6:
        dep = dependent_indices(design)
        imposed, converged = complete_poses(design.legs, dep, p)
        if bool(converged):
            wrong = [i for i in dep if abs(imposed[i] - p[i]) > DEPENDENT_TOLERANCE]
            raise InputDataError(
                f"pose ({format_pose(p)}): "
                + ", ".join(POSE_COORDINATES[i] for i in wrong)
                + " not free: the task coordinates of this design are "
                + ", ".join(design.task_coordinates)
                + f"; the legs impose {format_pose(imposed, wrong)}"
            )
    raise UnreachablePoseError(
        f"pose ({format_pose(done, task_indices(design))}): the legs' constraints cannot "
        "be met (no configuration of the legs reaches it)"
    )


def task_values(design: Design, poses: ArrayLike) -> FloatArray:
    """The task coordinates (..., n_task) of full poses (..., 6)."""
    return np.asarray(np.asarray(poses, dtype=float)[..., list(task_indices(design))])


def format_pose(pose: ArrayLike, indices: tuple[int, ...] | list[int] | None = None) -> str:
    """``"x = 1.00 mm, ..., rz = 2.00 deg"`` for the coordinates ``indices`` (all six by
    default) of a full pose [m, rad]: lengths in mm, angles in degrees."""
    p = np.asarray(pose, dtype=float).reshape(-1)
    chosen = range(6) if indices is None else indices
    parts = []
    for i in chosen:
        name = POSE_COORDINATES[i]
        if name in ANGLE_COORDINATES:
            parts.append(f"{name} = {math.degrees(p[i]):.2f} deg")
        else:
            parts.append(f"{name} = {p[i] * 1e3:.2f} mm")
    return ", ".join(parts)
