"""Design optimisation over a required region: scipy's differential evolution.

:func:`optimize_design` searches the box of the variables
(:mod:`ppm_stiffness.optimize.variables`) for the design whose objective
(:mod:`ppm_stiffness.optimize.objectives`) is best among the *feasible* candidates,
those that cover the region and meet every constraint. Infeasible candidates are never
reported optimal.

The search is :func:`scipy.optimize.differential_evolution` with
``updating="deferred"``: each generation is one batch of candidates, evaluated on the
executor (one task per design, :func:`~ppm_stiffness.optimize.summary.summarize_candidate`)
and collected in order, so the decisions, and the best parameters and objective, are the
same bit for bit whatever the executor. The random numbers come from
``numpy.random.SeedSequence(seed)``: one stream draws the Latin-hypercube initial
population (its first member is the start design when its values lie in the box), the
other drives the mutation and crossover.

What the evolution minimises, per candidate: for a feasible one the objective in units
of the start design's (``-value / |initial|`` for a maximised objective,
``value / |initial|`` for a minimised one); for an infeasible one ``1e9 + violation``
(:func:`~ppm_stiffness.optimize.objectives.violation`), so that every feasible candidate
ranks above every infeasible one and the less infeasible above the more. A candidate
the cheap check refuses (:mod:`ppm_stiffness.optimize.precheck`) is not mapped
(``cheap_checks``); its violation comes from the check alone.

Budget: every evaluation of a design counts, the start design's included (it is
evaluated first, in full, and reused as the first member of the population when its
values lie in the box; a candidate the cheap check refuses counts as one). The
population has ``S = max(5, min(15 d, budget // 10))`` members for d variables and
the evolution runs ``(budget - e) // S - 1`` generations, e = 0 when the start design
is the population's first member and 1 when it lies outside the box (an evaluation
outside the population), so evaluations never exceed the budget and the
smallest budget, ``2 S + e`` = 10 or 11, runs one generation
(:func:`population_plan`). Polishing is off: the objectives are minima and maxima over
a grid of poses (not smooth), so a gradient polish would spend evaluations on finite
differences of kinks.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import RequiredRegionModel
from ppm_stiffness.optimize.executors import Interrupted, SerialExecutor, run_ordered
from ppm_stiffness.optimize.objectives import (
    Constraint,
    Quantity,
    check_quantities,
    violation,
)
from ppm_stiffness.optimize.region import with_region
from ppm_stiffness.optimize.summary import RegionSummary, candidate_task, summarize_candidate
from ppm_stiffness.optimize.variables import Variable, apply_values, assignments, check_distinct

#: Energy of an infeasible candidate before its violation is added.
INFEASIBLE = 1e9
#: Smallest population scipy's differential evolution accepts.
MIN_POPULATION = 5
#: Population members per variable when the budget allows (scipy's default popsize).
POPULATION_PER_VARIABLE = 15
#: Smallest budget when the start design lies in the box (it is then the population's
#: first member): a population of 5 and one generation. One more when it lies outside.
MIN_BUDGET = 2 * MIN_POPULATION


@dataclass(frozen=True)
class OptimizationResult:
    """The outcome of :func:`optimize_design` (SI).

    Attributes
    ----------
    objective : Quantity
    variables : list of Variable
    initial_parameters : dict
        Variable name -> the start design's value (None where a glob's matches differ).
    initial_objective : float
        The start design's objective [objective unit].
    initial_summary, best_summary : RegionSummary
    best_parameters : dict
        Variable name -> value of the best feasible candidate.
    best_objective : float
    best_design : Design
        The start design with the best parameters and the region evaluated as its
        ``[workspace.required]``.
    evaluations : int
        Designs evaluated, the start design included.
    history : list of (int, float)
        (evaluations so far, best objective so far) after the start design and after
        each generation.
    population, generations : int
        Population size and generations run.
    interrupted : bool
        Stopped by Ctrl-C: the best so far.
    budget : int
        The evaluations asked for.
    outside : list of (str, float or None)
        (variable name, the start design's value) of each variable whose start value
        lies outside its range (None: a glob's matches differ); empty when the start
        design is a candidate (the population's first member).
    refused_by_check : int
        Candidates the cheap check refused (:mod:`ppm_stiffness.optimize.precheck`):
        counted in ``evaluations``, their maps skipped.
    """

    objective: Quantity
    variables: list[Variable]
    initial_parameters: dict[str, float | None]
    initial_objective: float
    initial_summary: RegionSummary
    best_parameters: dict[str, float]
    best_objective: float
    best_summary: RegionSummary
    best_design: Design
    evaluations: int
    history: list[tuple[int, float]]
    population: int
    generations: int
    interrupted: bool = False
    constraints: list[Constraint] = field(default_factory=list)
    budget: int = 0
    outside: list[tuple[str, float | None]] = field(default_factory=list)
    refused_by_check: int = 0

    def partial_note(self) -> str | None:
        """One line saying that the result is partial (None when it is not): for a
        comment in the files written from it."""
        if not self.interrupted:
            return None
        return (
            f"partial: interrupted after {self.evaluations} of {self.budget} evaluations; "
            "the best design so far"
        )

    @property
    def improvement(self) -> float:
        """Best over initial objective for a maximised objective, initial over best for
        a minimised one (> 1: better); NaN when a denominator is 0."""
        num, den = (
            (self.best_objective, self.initial_objective)
            if self.objective.maximise
            else (self.initial_objective, self.best_objective)
        )
        return num / den if den != 0 else math.nan

    @property
    def worse_than_start(self) -> bool:
        """The best candidate's objective is worse than the start design's: possible
        only when the start design is not a candidate (outside the ranges) or not
        feasible (misses a constraint)."""
        if self.objective.maximise:
            return self.best_objective < self.initial_objective
        return self.best_objective > self.initial_objective


def outside_ranges(
    design: Design, variables: Sequence[Variable]
) -> list[tuple[Variable, float | None]]:
    """The variables whose value on ``design`` lies outside their range, with that
    value (None where a glob's matches differ): when there are any, the start design is
    not a candidate of the search (module doc)."""
    out = []
    for v in variables:
        value = v.start(design)
        if value is None or not v.lo <= value <= v.hi:
            out.append((v, value))
    return out


def outside_note(outside: Sequence[tuple[Variable, float | None]]) -> str:
    """One line saying why the start design is not a candidate (``outside_ranges``)."""
    parts = [
        f"{v.name} differs between its {len(v.matches)} matches"
        if value is None
        else f"{v.name} = {value:g} {v.unit} lies outside its --vary range "
        f"{v.lo:g}:{v.hi:g} {v.unit}"
        for v, value in outside
    ]
    return (
        "the start design is not a candidate: "
        + "; ".join(parts)
        + "; the best design found may be worse than the start"
    )


def population_plan(budget: int, n_variables: int, start_in_ranges: bool = True) -> tuple[int, int]:
    """Population size S and generations for a budget (module doc).

    Parameters
    ----------
    budget : int
        Most evaluations, the start design's included.
    n_variables : int
    start_in_ranges : bool
        The start design is the population's first member; otherwise its evaluation
        comes on top of the population's.

    Raises
    ------
    InputDataError
        Budget below 1, or below the smallest that runs one generation
        (:data:`MIN_BUDGET`, one more when ``start_in_ranges`` is false), saying which.
    """
    if budget < 1:
        raise InputDataError(f"--budget must be at least 1, got {budget}")
    extra = 0 if start_in_ranges else 1
    if budget < MIN_BUDGET + extra:
        what = (
            f"a population of {MIN_POPULATION} (the start design its first member)"
            if start_in_ranges
            else "the start design (outside the --vary ranges, so not in the population), "
            f"a population of {MIN_POPULATION}"
        )
        raise InputDataError(
            f"--budget {budget} is too small: differential evolution needs at least "
            f"{MIN_BUDGET + extra} evaluations here: {what} and one generation of "
            f"{MIN_POPULATION}"
        )
    size = max(MIN_POPULATION, min(POPULATION_PER_VARIABLE * n_variables, budget // 10))
    return size, (budget - extra) // size - 1


class _Evaluator:
    """The map-like callable scipy calls once per generation: evaluates candidates on
    the executor, counts them, and keeps the best feasible one so far."""

    def __init__(
        self,
        design: Design,
        variables: Sequence[Variable],
        region: RequiredRegionModel,
        wrench: FloatArray | None,
        objective: Quantity,
        constraints: Sequence[Constraint],
        executor: Executor,
        scale: float,
        advance: Callable[[float], None] | None,
        margin: bool = False,
        frequencies: bool = False,
        hinges: bool = False,
        reach: bool = False,
        condition: bool = False,
        check: str = "skip",
        link_modes: int = 0,
    ) -> None:
        self.design, self.variables, self.region, self.wrench = design, variables, region, wrench
        self.margin, self.frequencies, self.hinges = margin, frequencies, hinges
        self.condition, self.check = condition, check
        self.reach = reach
        self.link_modes = link_modes
        #: designs the cheap check refused (their maps skipped with ``check="skip"``)
        self.refused = 0
        self.objective, self.constraints = objective, constraints
        self.executor, self.scale, self.advance = executor, scale, advance
        self.cache: dict[tuple[float, ...], RegionSummary] = {}
        self.evaluations = 0
        self.best: tuple[float, tuple[float, ...], RegionSummary] | None = None
        self.history: list[tuple[int, float]] = []
        self.generations = -1  # the initial population is not a generation
        #: the start design's values when it is the initial population's first member
        self.start_key: tuple[float, ...] | None = None

    def energy(self, summary: RegionSummary) -> float:
        gap = violation(summary, self.constraints)
        value = self.objective.value(summary)
        if gap > 0 or not math.isfinite(value):
            return INFEASIBLE + (gap if gap > 0 else 1.0)
        signed = -value if self.objective.maximise else value
        return min(signed / self.scale, INFEASIBLE / 2)

    def record(self, key: tuple[float, ...], summary: RegionSummary) -> float:
        e = self.energy(summary)
        if e < INFEASIBLE and (self.best is None or e < self.best[0]):
            self.best = (e, key, summary)
        return e

    def _as_start(self, key: tuple[float, ...]) -> tuple[float, ...]:
        """The start design's key for the initial population's first member: scipy
        scales the population to [0, 1] and back, which may move a value by an ulp
        (0.03 in 0.012:0.043 comes back as 0.030000000000000002); without this the
        start design would be evaluated twice and the budget exceeded by one."""
        start = self.start_key
        assert start is not None
        span = [abs(v.hi - v.lo) for v in self.variables]
        close = all(
            abs(a - b) <= 1e-12 * max(w, abs(b)) for a, b, w in zip(key, start, span, strict=True)
        )
        return start if close else key

    def best_objective(self) -> float:
        return math.nan if self.best is None else self.objective.value(self.best[2])

    def __call__(self, func: Any, iterable: Iterable[ArrayLike]) -> list[float]:
        keys = [tuple(float(v) for v in np.asarray(x, dtype=float)) for x in iterable]
        if self.generations == -1 and self.start_key is not None and keys:
            keys[0] = self._as_start(keys[0])
        todo = [k for k in dict.fromkeys(keys) if k not in self.cache]
        args = [
            candidate_task(
                self.design,
                assignments(self.variables, k),
                self.region,
                self.wrench,
                margin=self.margin,
                frequencies=self.frequencies,
                hinges=self.hinges,
                reach=self.reach,
                condition=self.condition,
                check=self.check,
                link_modes=self.link_modes,
            )
            for k in todo
        ]
        try:
            results = run_ordered(self.executor, summarize_candidate, args, self.advance)
        except Interrupted as stop:
            for i in sorted(stop.done):
                self.evaluations += 1
                self.refused += stop.done[i].refused_by_check
                self.record(todo[i], stop.done[i])
            raise
        for k, summary in zip(todo, results, strict=True):
            self.cache[k] = summary
            self.evaluations += 1
            self.refused += summary.refused_by_check
        energies = [self.record(k, self.cache[k]) for k in keys]
        self.generations += 1
        self.history.append((self.evaluations, self.best_objective()))
        return energies


def _link_modes(link_modes: int | None) -> int:
    from ppm_stiffness.dynamics.legmodes import resolve_link_modes

    return resolve_link_modes(link_modes)


def optimize_design(
    design: Design,
    variables: Sequence[Variable],
    objective: Quantity,
    region: RequiredRegionModel,
    *,
    budget: int,
    seed: int,
    wrench: ArrayLike | None = None,
    constraints: Sequence[Constraint] = (),
    executor: Executor | None = None,
    progress: Callable[[float], None] | None = None,
    cheap_checks: bool = True,
    link_modes: int | None = None,
) -> OptimizationResult:
    """Optimise ``design`` over ``region`` (module doc).

    Parameters
    ----------
    design : Design
        The start design; it must cover the region.
    variables : sequence of Variable
        Continuous ranges (:func:`~ppm_stiffness.optimize.variables.parse_variable`).
    objective : Quantity
        One of :data:`~ppm_stiffness.optimize.objectives.OBJECTIVES`.
    region : RequiredRegionModel
    budget : int
        Most design evaluations, the start design's included.
    seed : int
        Seeds every random choice: the same seed gives the same result on every
        executor.
    wrench : array_like (6,), optional
        At the tool point [N·m, N]; needed by the loaded objectives and constraints.
    constraints : sequence of Constraint
    executor : concurrent.futures.Executor, optional
        Default :class:`~ppm_stiffness.optimize.executors.SerialExecutor`.
    progress : callable(amount), optional
        Called with 1 after each evaluation.
    cheap_checks : bool
        Skip the maps of a candidate that the cheap check refuses
        (:mod:`ppm_stiffness.optimize.precheck`); False computes them (the same
        ranking, at the maps' cost). The start design is always evaluated in full.
    link_modes : int, optional
        The f1 objective and constraints with each leg's own modes with the platform
        held (Craig-Bampton, :mod:`ppm_stiffness.dynamics.legmodes`), as ``analyze``;
        None: :data:`~ppm_stiffness.dynamics.legmodes.DEFAULT_LINK_MODES`; 0: the legs
        condensed statically (cheaper: measured figures in docs/optimization.md).

    Returns
    -------
    OptimizationResult
        ``interrupted`` when Ctrl-C stopped it (the best so far).

    Raises
    ------
    InputDataError
        Bad budget; a loaded quantity without a wrench; the start design does not cover
        the region (by how much) or its objective has no value.
    DesignError
        No candidate covers the region and meets the constraints; f1 asked of a design
        without a mass model (no [platform] table).
    KeyboardInterrupt
        Ctrl-C before any feasible design was found.
    """
    from scipy.optimize import differential_evolution
    from scipy.stats import qmc

    check_distinct(variables)
    outside = outside_ranges(design, variables)
    size, generations = population_plan(budget, len(variables), not outside)
    w = None if wrench is None else np.asarray(wrench, dtype=float)
    quantities = (objective, *(c.quantity for c in constraints))
    check_quantities(design, quantities, w is not None)
    margin = any(q.needs_margin for q in quantities)
    frequencies = any(q.needs_frequencies for q in quantities)  # f1 only when used: it costs
    hinges = any(q.needs_hinges for q in quantities)  # so do the hinge figures
    reach = any(q.needs_candidate for q in quantities)  # and the candidate region
    condition = any(q.needs_condition for q in quantities)
    count = _link_modes(link_modes) if frequencies else 0
    executor = SerialExecutor() if executor is None else executor

    try:
        args = [
            candidate_task(
                design,
                None,
                region,
                w,
                margin=margin,
                frequencies=frequencies,
                hinges=hinges,
                reach=reach,
                condition=condition,
                link_modes=count,
            )
        ]
        start = run_ordered(executor, summarize_candidate, args)[0]
    except Interrupted:
        raise KeyboardInterrupt from None
    if progress is not None:
        progress(1)
    _check_start(design, start, region, w, objective)
    initial = objective.value(start)
    scale = abs(initial) if initial != 0 else 1.0

    lo = np.array([v.lo for v in variables])
    hi = np.array([v.hi for v in variables])
    starts = [v.start(design) for v in variables]
    streams = np.random.SeedSequence(seed).spawn(2)
    unit = qmc.LatinHypercube(d=len(variables), seed=np.random.default_rng(streams[0])).random(size)
    init = lo + unit * (hi - lo)
    x0 = np.array([np.nan if s is None else s for s in starts])
    use_start = not outside  # otherwise an evaluation outside the population
    evaluator = _Evaluator(
        design,
        variables,
        region,
        w,
        objective,
        constraints,
        executor,
        scale,
        progress,
        margin,
        frequencies,
        hinges,
        reach,
        condition,
        "skip" if cheap_checks else "record",
        count,
    )
    evaluator.evaluations = 1
    evaluator.history.append((1, initial if violation(start, constraints) == 0 else math.nan))
    if use_start:
        init[0] = x0
        key = tuple(float(v) for v in x0)
        evaluator.cache[key] = start
        evaluator.record(key, start)
        evaluator.start_key = key

    interrupted = False
    try:
        differential_evolution(
            _unused,
            list(zip(lo, hi, strict=True)),
            maxiter=generations,
            popsize=1,
            init=init,
            rng=np.random.default_rng(streams[1]),
            tol=0.0,
            atol=0.0,
            polish=False,
            updating="deferred",
            workers=evaluator,
        )
    except Interrupted:
        interrupted = True
        if evaluator.best is None:
            raise KeyboardInterrupt from None
    if evaluator.best is None:
        candidates = evaluator.evaluations - (0 if use_start else 1)
        raise DesignError(
            f"none of the {candidates} candidates evaluated covers the region and meets "
            "the constraints; widen the --vary ranges, relax --constraint or shrink the region"
        )
    _, key, best_summary = evaluator.best
    best_parameters = assignments(variables, key)
    best_design = with_region(apply_values(design, best_parameters), region)
    return OptimizationResult(
        objective=objective,
        variables=list(variables),
        initial_parameters={v.name: s for v, s in zip(variables, starts, strict=True)},
        initial_objective=initial,
        initial_summary=start,
        best_parameters=best_parameters,
        best_objective=objective.value(best_summary),
        best_summary=best_summary,
        best_design=best_design,
        evaluations=evaluator.evaluations,
        history=evaluator.history,
        population=size,
        generations=max(evaluator.generations, 0),
        interrupted=interrupted,
        constraints=list(constraints),
        budget=budget,
        outside=[(v.name, value) for v, value in outside],
        refused_by_check=evaluator.refused,
    )


def _unused(x: FloatArray) -> float:  # pragma: no cover - the evaluator maps instead
    raise AssertionError("candidates are evaluated by the map-like evaluator")


def _check_start(
    design: Design,
    start: RegionSummary,
    region: RequiredRegionModel,
    wrench: FloatArray | None,
    objective: Quantity,
) -> None:
    """Refuse a start design that does not cover the region (saying by how much) or
    whose loaded state fails in it."""
    if start.error is not None:
        raise InputDataError(f"the start design cannot be evaluated: {start.error}")
    if not start.covers:
        missing = start.poses - start.covered
        raise InputDataError(
            f"the start design does not cover the required region: {missing} of "
            f"{start.poses} grid poses ({100 * missing / start.poses:.3g} %) are unreachable "
            "or singular; shrink the region (--region) or start from a design that reaches it"
        )
    if start.loaded_failures and start.first_loaded_failure is not None and wrench is not None:
        from ppm_stiffness.optimize.loaded import loaded_state_error

        reason = loaded_state_error(design, start.first_loaded_failure, wrench)
        raise InputDataError(
            f"the start design's loaded state fails at {start.loaded_failures} of "
            f"{start.covered} poses of the region: {reason}"
        )
    if not math.isfinite(objective.value(start)):
        raise InputDataError(f"the start design has no value of {objective.name}")
