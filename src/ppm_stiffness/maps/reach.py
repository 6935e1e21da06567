"""What is reachable near a pose that is not: for error messages that teach.

:func:`reach_hint` says, for a pose outside the workspace, in the CLI's units (mm,
deg): for a planar design, the x and y extent of the workspace at its phi and the
range of phi reachable at its (x, y); for any other design, the reachable interval of
each task coordinate with the others fixed (sampled, :data:`LINE_SAMPLES` values over
:data:`LINE_SPAN`). Reachability is the joint-limit test of the legs (the pose
completed, every leg's inverse kinematics solvable and its joint coordinates within
limits); singular poses are not excluded.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.errors import PPMStiffnessError
from ppm_stiffness.core.pose import ANGLE_COORDINATES, POSE_INDEX
from ppm_stiffness.design import Design
from ppm_stiffness.legs.base import as_poses

#: Orientations sampled over one turn to find the reachable phi at a position (0.1 deg).
PHI_SAMPLES = 3600


def reachable_orientations(design: Design, x: float, y: float) -> list[tuple[float, float]]:
    """Intervals of phi [rad] in [-pi, pi) reachable at the position (x, y) [m].

    Sampled every 360/:data:`PHI_SAMPLES` degrees; each interval is (first, last)
    reachable sample.
    """
    phi = np.linspace(-math.pi, math.pi, PHI_SAMPLES, endpoint=False)
    poses = np.stack([np.full_like(phi, x), np.full_like(phi, y), phi], axis=-1)
    ok = np.ones(phi.size, dtype=bool)
    for leg in design.legs:
        ok &= np.asarray(leg.reachable(leg.solve(poses)), dtype=bool)
    intervals: list[tuple[float, float]] = []
    start = None
    for i, flag in enumerate(ok):
        if flag and start is None:
            start = i
        if start is not None and (not flag or i == ok.size - 1):
            end = i if flag else i - 1
            intervals.append((float(phi[start]), float(phi[end])))
            start = None
    return intervals


#: Samples along one task coordinate for the hint of a design that is not planar.
LINE_SAMPLES = 801
#: Half-span of those samples about the pose: lengths [m], angles [rad].
LINE_SPAN = {"length": 0.5, "angle": 1.2}


def reachable_along(design: Design, pose: ArrayLike, name: str) -> list[tuple[float, float]]:
    """Intervals of task coordinate ``name`` [m or rad] reachable with the other task
    coordinates of the full pose (6,) fixed (sampled, module doc)."""
    from ppm_stiffness.poses import full_poses, task_indices

    p = as_poses(pose)
    i = POSE_INDEX[name]
    half = LINE_SPAN["angle" if name in ANGLE_COORDINATES else "length"]
    values = p[i] + np.linspace(-half, half, LINE_SAMPLES)
    grid = np.tile(p, (LINE_SAMPLES, 1))
    grid[:, i] = values
    full, ok = full_poses(design, grid[:, list(task_indices(design))])
    for leg in design.legs:
        ok &= np.asarray(leg.reachable(leg.solve(full)), dtype=bool)
    return _intervals(values, ok)


def _intervals(values: np.ndarray, ok: np.ndarray) -> list[tuple[float, float]]:
    out: list[tuple[float, float]] = []
    start = None
    for i, flag in enumerate(ok):
        if flag and start is None:
            start = i
        if start is not None and (not flag or i == ok.size - 1):
            end = i if flag else i - 1
            out.append((float(values[start]), float(values[end])))
            start = None
    return out


def reach_hint(design: Design, pose: ArrayLike) -> str:
    """One sentence in mm and degrees: for a planar design the workspace's x and y extent
    at the pose's phi and the phi reachable at its (x, y); for any other design the
    reachable interval of each task coordinate with the others fixed."""
    if not design.planar:
        p6 = as_poses(pose)
        parts = []
        for name in design.task_coordinates:
            angle = name in ANGLE_COORDINATES
            scale, unit = (180 / math.pi, "deg") if angle else (1e3, "mm")
            spans = reachable_along(design, p6, name)
            text = ", ".join(f"[{lo * scale:.4g}, {hi * scale:.4g}]" for lo, hi in spans)
            parts.append(f"{name} in {text} {unit}" if spans else f"{name}: none")
        return "with the other task coordinates fixed, reachable: " + "; ".join(parts)
    p = as_poses(pose)[[0, 1, 5]]
    from ppm_stiffness.maps.workspace import workspace_bounds

    parts = []
    try:
        b = 1e3 * workspace_bounds(design, float(p[2]))
        parts.append(
            f"at phi = {math.degrees(p[2]):.4g} deg the workspace spans x in "
            f"[{b[0]:.2f}, {b[1]:.2f}] mm, y in [{b[2]:.2f}, {b[3]:.2f}] mm"
        )
    except PPMStiffnessError:
        parts.append(f"no position is reachable at phi = {math.degrees(p[2]):.4g} deg")
    intervals = reachable_orientations(design, float(p[0]), float(p[1]))
    where = f"({1e3 * p[0]:.2f}, {1e3 * p[1]:.2f}) mm"
    if intervals:
        text = ", ".join(
            f"[{math.degrees(lo):.1f}, {math.degrees(hi):.1f}]" for lo, hi in intervals
        )
        parts.append(f"at {where} phi may be in {text} deg")
    else:
        parts.append(f"no orientation is reachable at {where}")
    return "; ".join(parts)
