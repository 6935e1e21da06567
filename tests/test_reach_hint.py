"""The reachable intervals that an unreachable pose's error names (maps/reach.py) for
designs that are not planar: the same whatever unreachable value was asked for, and
their ends are the workspace's boundary (checked by the single-pose API on both sides),
also where the asked value lies far outside (the window used to follow it and cut the
interval: 3-PRS z in [126.2, 600] mm for z = 100 mm while 624 mm is reachable)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from helpers import design_named
from ppm_stiffness.core.errors import UnreachablePoseError
from ppm_stiffness.core.pose import POSE_INDEX
from ppm_stiffness.maps.reach import reach_hint, reachable_along
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.poses import full_pose, home_pose, task_values

#: Distances of the probes inside and outside an interval's end [m or rad].
INSIDE, OUTSIDE = 1e-6, 1e-4


def _pose_with(design, name: str, value: float) -> np.ndarray:
    task = task_values(design, home_pose(design))
    task[list(design.task_coordinates).index(name)] = value
    return task


def _reachable(design, name: str, value: float) -> bool:
    try:
        stiffness_at_pose(design, full_pose(design, _pose_with(design, name, value)))
    except UnreachablePoseError:
        return False
    return True


@pytest.mark.parametrize(
    ("name", "coordinate", "asked"),
    [
        ("3rps", "rx", (math.radians(80), math.radians(60), math.radians(-30))),
        ("3prs", "z", (0.1, 0.64, 0.7)),
        ("3prs", "rx", (math.radians(-90), math.radians(60))),
    ],
)
def test_the_interval_is_the_workspace_boundary_whatever_was_asked(
    name: str, coordinate: str, asked: tuple[float, ...]
) -> None:
    design = design_named(name)
    spans = []
    for value in asked:
        pose = home_pose(design).copy()
        pose[POSE_INDEX[coordinate]] = value  # unreachable: not completed
        spans.append(reachable_along(design, pose, coordinate))
    assert all(s == spans[0] for s in spans)
    assert len(spans[0]) == 1
    lo, hi = spans[0][0]
    home = float(home_pose(design)[POSE_INDEX[coordinate]])
    assert lo < home < hi
    assert _reachable(design, coordinate, lo + INSIDE)
    assert _reachable(design, coordinate, hi - INSIDE)
    assert not _reachable(design, coordinate, lo - OUTSIDE)
    assert not _reachable(design, coordinate, hi + OUTSIDE)


def test_the_hint_names_every_task_coordinate_in_mm_and_deg() -> None:
    design = design_named("3prs")
    pose = home_pose(design).copy()
    pose[POSE_INDEX["z"]] = 0.1
    hint = reach_hint(design, pose)
    lo, hi = reachable_along(design, pose, "z")[0]
    assert f"z in [{lo * 1e3:.4g}, {hi * 1e3:.4g}] mm" in hint
    assert "rx: none" in hint and "ry: none" in hint  # at z = 100 mm no tilt is reachable
