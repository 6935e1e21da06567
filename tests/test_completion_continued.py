"""The completion continues a joint-list leg's inverse kinematics from its previous
iterate (legs/completion.py): the same completed poses as a completion that solves
every iterate from home again, and the continuation's start honoured row by row
(legs/kinematics.py, ``solve(..., start=...)``)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from numpy.typing import ArrayLike
from tests.helpers import design_named, example_designs, flexure_jointed

from ppm_stiffness.design import Design
from ppm_stiffness.legs import kinematics as kin
from ppm_stiffness.legs.completion import complete_poses
from ppm_stiffness.poses import dependent_indices, home_pose, task_indices


class FromHome:
    """A leg whose completion residuals are solved from home at every iterate (the
    completion before the continuation)."""

    def __init__(self, leg: Any) -> None:
        self.leg = leg

    def constraint(self, poses: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        return self.leg.constraint(poses)  # type: ignore[no-any-return]

    def constraint_continued(self, poses: ArrayLike, start: object) -> tuple[Any, Any, None]:
        residual, wrenches = self.leg.constraint(poses)
        return residual, wrenches, None


def continued(design: Design) -> bool:
    """Dependent coordinates completed through a joint-list leg's continuation."""
    return bool(dependent_indices(design)) and any(
        leg.type == "chain" and leg.constraint_count() > 0 for leg in design.legs
    )


def start_poses(design: Design, n: int, seed: int) -> np.ndarray:
    """Full-pose starts: the task coordinates drawn around home (+-0.3 m, +-0.8 rad, a
    twentieth for a flexure-jointed design), the dependent ones at home."""
    rng = np.random.default_rng(seed)
    home = home_pose(design)
    half = np.array([0.3, 0.3, 0.3, 0.8, 0.8, 0.8])
    if flexure_jointed(design):
        half *= 0.05
    poses = np.tile(home, (n, 1))
    idx = list(task_indices(design))
    poses[:, idx] += rng.uniform(-1.0, 1.0, (n, len(idx))) * half[idx]
    return poses


@pytest.mark.parametrize("name", example_designs(continued))
def test_the_continued_completion_equals_the_completion_from_home(name: str) -> None:
    """Same converged poses to 1e-12 (the Newton tolerance of both: the two paths reach
    the same branch; measured at most 2.2e-16 m or rad, on the Tricept), the same
    convergence mask, over a wide draw (poses up to 6 continuation steps from home)."""
    design = design_named(name)
    dep = dependent_indices(design)
    start = start_poses(design, 24, seed=7)
    fast, ok_fast = complete_poses(design.legs, dep, start)
    slow, ok_slow = complete_poses([FromHome(leg) for leg in design.legs], dep, start)
    assert ok_fast.any()
    np.testing.assert_array_equal(ok_fast, ok_slow)
    assert np.max(np.abs(fast[ok_fast] - slow[ok_slow])) <= 1e-12


def test_a_start_continues_each_row_from_its_own_pose() -> None:
    """The Tricept's first UPS leg: a start at home with zero coordinates is the solve
    from home bit for bit; a start elsewhere on the branch (a solved pose) reaches the
    same coordinates to 1e-12, and a row whose start is NaN continues from home."""
    design = design_named("tricept")
    leg = design.legs[0]
    freedoms, _ = leg.freedoms()
    home = home_pose(design)
    target = np.tile(home, (3, 1))
    target[:, 2] += [0.02, -0.03, 0.01]
    target[:, 3] += [0.05, 0.0, -0.04]
    cold = kin.solve(freedoms, home, target)
    zero = kin.solve(freedoms, home, target, start=(np.tile(home, (3, 1)), np.zeros_like(cold.q)))
    np.testing.assert_array_equal(zero.q, cold.q)
    middle = home + 0.5 * (target - home)
    mid = kin.solve(freedoms, home, middle)
    q0 = mid.q.copy()
    q0[1] = np.nan
    warm = kin.solve(freedoms, home, target, start=(middle, q0))
    assert warm.converged.all()
    assert np.max(np.abs(warm.q - cold.q)) <= 1e-12
    np.testing.assert_array_equal(warm.q[1], cold.q[1])


def test_a_pose_not_given_fails_without_a_warning() -> None:
    """A NaN row (a pose the completion could not give) is not solved: it fails in one
    step, the others are solved; numpy no longer warns of casting NaN steps to int."""
    import warnings

    design = design_named("tricept")
    freedoms, _ = design.legs[0].freedoms()
    home = home_pose(design)
    target = np.tile(home, (2, 1))
    target[1, 0] = np.nan
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        state = kin.solve(freedoms, home, target)
    np.testing.assert_array_equal(state.converged, [True, False])


def test_a_failed_solve_is_not_continued_from() -> None:
    """What a leg hands on to continue from: its converged joint coordinates, and NaN
    for a pose whose solve failed (that pose continues from home next time, not from
    its last Newton try)."""
    design = design_named("tricept")
    leg = design.legs[3]  # the passive central leg: it constrains the pose
    home = home_pose(design)
    poses = np.tile(home, (2, 1))
    poses[1, 0] = np.nan
    _, _, onward = leg.constraint_continued(poses, None)
    assert onward is not None
    assert np.all(np.isfinite(onward[1][0])) and np.all(np.isnan(onward[1][1]))
