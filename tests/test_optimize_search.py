"""The optimiser against brute force, and what it may never report.

Each known answer is established in the test by a brute-force sweep of the same
objective (:func:`ppm_stiffness.optimize.sweep.sweep_designs` on a fine grid); the
optimiser must do at least as well as the brute force at the brute force's resolution.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import ppm_stiffness as pps
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.optimize.executors import SerialExecutor
from ppm_stiffness.optimize.objectives import OBJECTIVES, parse_constraint
from ppm_stiffness.optimize.optimizer import optimize_design
from ppm_stiffness.optimize.region import make_region
from ppm_stiffness.optimize.summary import summarize
from ppm_stiffness.optimize.sweep import sweep_designs
from ppm_stiffness.optimize.variables import parse_variable

ROOT = Path(__file__).parents[1]
WORST_K = OBJECTIVES["worst-k-translational"]
#: 5 x 5 x 3 poses: x, y in +-10 mm, phi in +-0.1 rad (the examples' region, coarser).
REGION = make_region((-0.01, 0.01), (-0.01, 0.01), (-0.1, 0.1), (5, 5, 3))


def _symmetric(**values: float) -> pps.Design:
    design = pps.load_design(ROOT / "examples/symmetric_3ppr.toml")
    return design.with_parameters(values) if values else design


def _brute_force(design: pps.Design, spec: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Grid values, worst-k-translational and coverage of a 1-parameter sweep."""
    result = sweep_designs(design, [parse_variable(spec, design, True)], REGION, frequencies=False)
    f = np.array([WORST_K.value(s) for s in result.summaries])
    return result.points[:, 0], f, np.array([s.covers for s in result.summaries])


def test_interior_optimum_at_a_kink_found_as_brute_force_finds_it() -> None:
    """Rail angle of leg 1 of the symmetric 3-PPR, started off at 0.03 rad: the worst
    translational stiffness peaks at the symmetric layout, alpha = 0 (a kink: min of two
    branches), which the 41-point brute force over [-0.05, 0.05] rad finds."""
    design = _symmetric(**{"leg1.alpha": 0.03})
    x, f, covers = _brute_force(design, "leg1.alpha=-0.05:0.05:41")
    assert covers.all()
    best = int(np.argmax(f))
    assert x[best] == pytest.approx(0.0, abs=1e-15) and 0 < best < len(x) - 1  # interior
    variable = parse_variable("leg1.alpha=-0.05:0.05", design, False)
    result = optimize_design(design, [variable], WORST_K, REGION, budget=60, seed=1)
    step = x[1] - x[0]
    assert abs(result.best_parameters["leg1.alpha"] - x[best]) <= step
    assert result.best_objective >= max(f[best - 1], f[best + 1])  # beats the neighbours
    assert result.best_objective <= f[best] * (1 + 1e-12)  # and not the brute-force peak
    assert result.evaluations <= 60 and result.initial_objective < result.best_objective


def test_optimum_on_a_bound() -> None:
    """Leg 1's locked actuator stiffness: stiffer is better, so the optimum is the upper
    bound, 5e5 N/m (brute force: monotone over 21 values)."""
    design = _symmetric()
    x, f, _ = _brute_force(design, "leg1.actuator.locked_stiffness=5e4:5e5:21")
    assert np.all(np.diff(f) > 0)  # monotone: the optimum is the bound
    variable = parse_variable("leg1.actuator.locked_stiffness=5e4:5e5", design, False)
    result = optimize_design(design, [variable], WORST_K, REGION, budget=60, seed=1)
    assert result.best_parameters["leg1.actuator.locked_stiffness"] >= x[-2]
    assert f[-2] <= result.best_objective <= f[-1]


def test_candidates_that_do_not_cover_the_region_are_never_optimal() -> None:
    """A larger platform radius is stiffer, but beyond ~0.1018 m the design no longer
    covers the region: the best feasible radius is on that edge, and the stiffer
    non-covering designs are not reported."""
    design = _symmetric()
    x, f, covers = _brute_force(design, "leg*.platform_radius=0.1:0.104:9")
    last = int(np.flatnonzero(covers)[-1])
    assert covers[: last + 1].all() and not covers[last + 1 :].any()
    assert np.nanmax(f[~covers]) > f[last]  # infeasible designs look better
    variable = parse_variable("leg*.platform_radius=0.02:0.14", design, False)
    result = optimize_design(design, [variable], WORST_K, REGION, budget=60, seed=1)
    assert result.best_summary.covers
    assert x[last] <= result.best_parameters["leg*.platform_radius"] < x[last + 1]
    assert result.best_objective >= f[last]
    again = summarize(result.best_design, REGION, frequencies=False)  # the design found
    assert again.covers and WORST_K.value(again) == result.best_objective


def test_a_constraint_excludes_candidates() -> None:
    design = _symmetric()
    variable = parse_variable("leg*.platform_radius=0.02:0.06", design, False)
    bound = 60e3  # N/m: k_y must stay below it, which caps the radius
    constraint = parse_constraint(f"k_y_min<={bound}")
    result = optimize_design(
        design, [variable], WORST_K, REGION, budget=40, seed=2, constraints=[constraint]
    )
    assert result.best_summary["k_y_min"] <= bound
    assert result.best_objective <= bound


def test_no_covering_candidate_is_an_error() -> None:
    design = _symmetric()  # covers at alpha = 0; nothing in [0.3, 0.5] does
    variable = parse_variable("leg1.alpha=0.3:0.5", design, False)
    # the start design (alpha = 0) is outside the range: it and 5 + 5 candidates, of
    # which repeats are evaluated once
    with pytest.raises(DesignError, match=r"none of the \d+ candidates evaluated covers the"):
        optimize_design(design, [variable], WORST_K, REGION, budget=11, seed=0)


@pytest.mark.parametrize(
    ("spec", "minimum"),
    [("leg*.platform_radius=0.02:0.06", 10), ("leg*.platform_radius=0.04:0.06", 11)],
)
def test_the_stated_minimum_budget_runs_one_generation(spec: str, minimum: int) -> None:
    """The refusal of a budget one below the minimum states the minimum, and that budget
    runs a population of 5 and one generation of 5: 10 evaluations when the start
    design (platform radius 0.03 m) is the population's first member, 11 when it lies
    outside the range and is evaluated on top of the population. Before the fix, 10 was
    the stated minimum in both cases and gave 6 evaluations and 0 generations outside."""
    design = _symmetric()
    variable = parse_variable(spec, design, False)
    with pytest.raises(InputDataError, match=f"needs at least {minimum} evaluations here"):
        optimize_design(design, [variable], WORST_K, REGION, budget=minimum - 1, seed=1)
    result = optimize_design(design, [variable], WORST_K, REGION, budget=minimum, seed=1)
    assert (result.population, result.generations, result.evaluations) == (5, 1, minimum)
    # start, initial population, one generation
    assert [n for n, _ in result.history] == [1, minimum - 5, minimum]
    assert result.outside == ([] if minimum == 10 else [("leg*.platform_radius", 0.03)])


class _Counting(SerialExecutor):
    """Counts the design evaluations actually submitted."""

    def __init__(self) -> None:
        self.tasks = 0

    def submit(self, fn, /, *args, **kwargs):  # type: ignore[no-untyped-def]
        self.tasks += 1
        return super().submit(fn, *args, **kwargs)


@pytest.mark.parametrize(
    "spec", ["leg*.platform_radius=0.012:0.043", "leg*.platform_radius=0.014:0.059"]
)
def test_the_budget_bounds_the_evaluations_when_the_start_does_not_round_trip(spec: str) -> None:
    """scipy scales the population to [0, 1] and back: the start radius 0.03 m in these
    ranges comes back as 0.030000000000000002 or 0.029999999999999995. The start design
    is then still the population's first member, not a new candidate: budget 10 gives
    at most 10 evaluations, counted at the executor (before the fix: 11, the start
    design evaluated twice, history 1, 6, 11)."""
    design = _symmetric()
    variable = parse_variable(spec, design, False)
    counting = _Counting()
    result = optimize_design(
        design, [variable], WORST_K, REGION, budget=10, seed=1, executor=counting
    )
    assert counting.tasks == result.evaluations <= 10
    assert [n for n, _ in result.history][:2] == [1, 5]  # start, then 4 new members


class _InterruptAfter(SerialExecutor):
    """Ctrl-C after ``n`` tasks."""

    def __init__(self, n: int) -> None:
        self.left = n

    def submit(self, fn, /, *args, **kwargs):  # type: ignore[no-untyped-def]
        if self.left == 0:
            raise KeyboardInterrupt
        self.left -= 1
        return super().submit(fn, *args, **kwargs)


def test_ctrl_c_keeps_the_best_so_far() -> None:
    design = _symmetric()
    variable = parse_variable("leg*.platform_radius=0.02:0.06", design, False)
    result = optimize_design(
        design, [variable], WORST_K, REGION, budget=60, seed=1, executor=_InterruptAfter(15)
    )
    assert result.interrupted and result.evaluations == 15
    assert result.best_summary.covers and result.best_objective >= result.initial_objective
    with pytest.raises(KeyboardInterrupt):  # before any design: nothing to keep
        optimize_design(
            design, [variable], WORST_K, REGION, budget=60, seed=1, executor=_InterruptAfter(0)
        )


def test_same_seed_same_result_and_another_seed_another_path() -> None:
    design = _symmetric()
    variable = parse_variable("leg*.platform_radius=0.02:0.06", design, False)
    runs = [
        optimize_design(design, [variable], WORST_K, REGION, budget=20, seed=s) for s in (4, 4, 5)
    ]
    assert runs[0].best_parameters == runs[1].best_parameters
    assert runs[0].history == runs[1].history
    assert runs[0].history != runs[2].history
