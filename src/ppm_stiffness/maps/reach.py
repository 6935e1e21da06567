"""What is reachable near a pose that is not: for error messages that teach.

:func:`reach_hint` says, for a pose (x, y, phi) outside the workspace, the x and y
extent of the workspace at that phi and the range of phi reachable at that (x, y), in
the CLI's units (mm, deg). Reachability is the joint-limit test of the legs
(every leg's inverse kinematics solvable and its joint coordinates within limits);
singular poses are not excluded.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.errors import PPMStiffnessError
from ppm_stiffness.design import Design

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


def reach_hint(design: Design, pose: ArrayLike) -> str:
    """One sentence: the workspace's x and y extent at the pose's phi, and the phi
    reachable at its (x, y); in mm and degrees."""
    p = np.asarray(pose, dtype=float)
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
