"""Cheap checks of a candidate design before its maps over the required region.

An optimiser's candidate is first evaluated at a few poses only, the *check poses*:
the corners of the required region (every combination of each task coordinate's two
ends; 2^k poses for k ranges that are not a single value) and the home pose (the design
file's ``[workspace]`` centre, completed). A check pose is refused when it is
unreachable (a leg's inverse kinematics has no solution or leaves its joint limits,
or the completion fails) or singular, by the same test as the region's grid
(:func:`ppm_stiffness.maps.batch.evaluate_poses`, its ``valid`` mask). A design with a
refused corner cannot cover the region; one whose home pose is refused is infeasible
too (issue 31: a design whose home pose is unreachable is infeasible, not an error).
Such a design is returned without its maps (stiffness, f1, loaded states, hinges) by
:func:`~ppm_stiffness.optimize.summary.summarize_candidate` with ``check=True``; its
violation (:func:`check_violation`) depends on the check alone, so an optimiser ranks
it the same whether or not its maps were computed.
"""

from __future__ import annotations

import itertools

import numpy as np

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import RequiredRegionModel

#: Added to the violation of a design the check refuses: more than any design that
#: passes it (whose uncovered fraction + 1e-3 is at most 1.001).
REFUSED_BASE = 1.001


def check_poses(design: Design, region: RequiredRegionModel) -> FloatArray:
    """The check poses (n, n_task) [m, rad]: the region's distinct corners, then the
    home pose's task coordinates (module doc)."""
    from ppm_stiffness.poses import task_indices

    ends = [sorted({lo, hi}) for lo, hi in region.ranges().values()]
    corners = np.array(list(itertools.product(*ends)), dtype=float)
    home = np.asarray(design.workspace.start(), dtype=float)[list(task_indices(design))]
    return np.vstack([corners, home[None]])


def refused_check_poses(design: Design, region: RequiredRegionModel) -> tuple[int, int]:
    """(check poses, refused among them) of ``design`` (module doc)."""
    from ppm_stiffness.maps.batch import evaluate_poses

    poses = check_poses(design, region)
    res = evaluate_poses(design, poses, principal=False)
    refused = int(np.count_nonzero(~np.asarray(res.valid, dtype=bool)))
    return int(poses.shape[0]), refused


def check_violation(poses: int, refused: int) -> float:
    """The coverage violation of a design the check refuses: :data:`REFUSED_BASE` plus
    the refused share of the check poses, in (1.001, 2.001]."""
    return REFUSED_BASE + refused / poses
