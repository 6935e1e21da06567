"""What is reachable near a pose that is not: for error messages that teach.

:func:`reach_hint` says, for a pose outside the workspace, in the CLI's units (mm,
deg): for a planar design, the x and y extent of the workspace at its phi and the
range of phi reachable at its (x, y); for any other design, the reachable interval of
each task coordinate with the others fixed (:func:`reachable_along`: sampled about
the home pose, the ends refined by bisection). Reachability is the joint-limit test of
the legs (the pose completed, every leg's inverse kinematics solvable and its joint
coordinates within limits); singular poses are not excluded.
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
LINE_SAMPLES = 2001
#: Half-span of those samples about the home pose's value: lengths [m], angles [rad].
LINE_SPAN = {"length": 1.0, "angle": math.pi}
#: Bisection steps that refine each end of a sampled interval (to span / 2^steps).
REFINE_STEPS = 30


def reachable_values(design: Design, pose: ArrayLike, name: str, values: ArrayLike) -> np.ndarray:
    """Mask (n,) of the ``values`` (n,) of task coordinate ``name`` [m or rad] that are
    reachable with the other task coordinates of the full pose (6,) fixed (the pose
    completed, every leg within its limits; module doc)."""
    from ppm_stiffness.poses import full_poses, task_indices

    values = np.asarray(values, dtype=float).reshape(-1)
    grid = np.tile(as_poses(pose), (values.size, 1))
    grid[:, POSE_INDEX[name]] = values
    full, ok = full_poses(design, grid[:, list(task_indices(design))])
    for leg in design.legs:
        ok &= np.asarray(leg.reachable(leg.solve(full)), dtype=bool)
    return np.asarray(ok, dtype=bool)


def reachable_along(design: Design, pose: ArrayLike, name: str) -> list[tuple[float, float]]:
    """Intervals of task coordinate ``name`` [m or rad] reachable with the other task
    coordinates of the full pose (6,) fixed.

    Sampled over :data:`LINE_SPAN` about the home pose's value of ``name`` (not about
    the pose's: an unreachable value far out would shift the window off the workspace),
    each end then refined by bisection to well below a micrometre or microradian.
    """
    from ppm_stiffness.poses import home_pose

    i = POSE_INDEX[name]

    def reachable(values: np.ndarray) -> np.ndarray:
        return reachable_values(design, pose, name, values)

    half = LINE_SPAN["angle" if name in ANGLE_COORDINATES else "length"]
    centre = float(home_pose(design)[i])
    values = centre + np.linspace(-half, half, LINE_SAMPLES)
    ok = reachable(values)
    spans = _intervals(values, ok)
    if not spans:
        return spans
    # refine every end that has an unreachable neighbour sample: inside (reachable) and
    # outside (not) bracket the boundary
    step = values[1] - values[0]
    ends = np.array([v for span in spans for v in span])
    outward = np.tile([-step, step], len(spans))
    inside, outside = ends.copy(), ends + outward
    open_end = (outside >= values[0]) & (outside <= values[-1])
    for _ in range(REFINE_STEPS):
        mid = 0.5 * (inside + outside)
        good = reachable(mid)
        inside = np.where(good, mid, inside)
        outside = np.where(good, outside, mid)
    ends = np.where(open_end, inside, ends)
    return [(float(ends[2 * k]), float(ends[2 * k + 1])) for k in range(len(spans))]


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
