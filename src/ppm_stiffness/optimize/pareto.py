"""Multi-objective design optimisation: a Pareto front by pymoo's NSGA-II / NSGA-III.

:func:`optimize_front` searches the box of the variables for the designs that no other
feasible design beats in every objective at once. Feasibility first: pymoo's constraint
handling takes the constraints as ``G <= 0`` (:func:`constraint_values`), so a feasible
design always ranks above an infeasible one and the less infeasible above the more
(Deb's rules in the survival's non-dominated sort). The columns of G:

- coverage: 0 when the design covers the region, else the uncovered fraction + 1e-3;
- values: 0 when every objective has a finite value, else 1 (f1 of a design with a
  singular M, a loaded objective whose loaded state fails);
- each ``--constraint``: its excess relative to its bound, ``(value - bound) / |bound|``
  for ``<=`` and ``(bound - value) / |bound|`` for ``>=`` (1 when not finite), as in
  :func:`~ppm_stiffness.optimize.objectives.violation`.

A design the cheap check refuses (:mod:`ppm_stiffness.optimize.precheck`: a corner of
the region or the home pose unreachable or singular) has G = (1.001 + refused share of
the check poses, 1, 1, ...), from the check alone, its maps not computed
(``cheap_checks``).

What pymoo minimises, per design: each objective in units of the start design's,
``-value / |initial|`` for a maximised one and ``value / |initial|`` for a minimised
one (:func:`scaled_objectives`).

Algorithm: NSGA-II (simulated binary crossover, polynomial mutation, pymoo's
defaults) for two objectives; NSGA-III for three or more, with Das and Dennis's
reference directions, the most partitions whose count of directions does not exceed
the population. The population is evaluated as one batch per generation on the
executor (:func:`~ppm_stiffness.optimize.executors.run_ordered`, one task per design,
results in order), so the same seed gives the same front on every executor. The random
numbers: the initial population is uniform in the box, drawn from
``numpy.random.default_rng(SeedSequence(seed))`` (its first member the start design when
its values lie in the box); the crossover, mutation and selection use pymoo's generator
seeded with ``seed``.

The front reported is the non-dominated set of every feasible design evaluated (an
archive over the whole run, not only the last population), sorted by the first
objective; designs with equal objectives appear once (the first evaluated).

Budget: every evaluation of a design counts, the start design's included (it is
evaluated first, and is the initial population's first member when its values lie in
the box). The population has ``S = max(8, min(100, budget // 10))`` members and the run
``(budget - e) // S - 1`` generations after the initial population, e = 1 when the start
design lies outside the box (:func:`front_plan`); pymoo removes duplicate offspring,
and a design met again is not evaluated again, so evaluations never exceed the budget.
A design the cheap check refuses counts as one evaluation.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import RequiredRegionModel
from ppm_stiffness.optimize.catalogue import Choice, choice_values
from ppm_stiffness.optimize.executors import Interrupted, SerialExecutor, run_ordered
from ppm_stiffness.optimize.objectives import Constraint, Quantity, check_quantities
from ppm_stiffness.optimize.optimizer import _check_start, outside_ranges
from ppm_stiffness.optimize.region import with_region
from ppm_stiffness.optimize.summary import RegionSummary, candidate_task, summarize_candidate
from ppm_stiffness.optimize.variables import Variable, apply_values, assignments, check_distinct

#: Smallest population of a multi-objective run.
MIN_FRONT_POPULATION = 8
#: Largest population (a larger budget buys generations).
MAX_FRONT_POPULATION = 100
#: Scaled objective of a design without a finite value (it is infeasible anyway).
NO_VALUE = 1e9
#: The choice rules of :func:`choose`.
RULES = ("knee", "weights")


@dataclass(frozen=True)
class FrontDesign:
    """One evaluated design (SI).

    Attributes
    ----------
    parameters : dict
        Variable name -> value.
    summary : RegionSummary
    objectives : tuple of float
        Each objective's value [its unit], in the order of the objectives.
    constraints : tuple of float
        Each ``--constraint``'s quantity [its unit].
    evaluation : int
        Its rank among the evaluations (1: the start design).
    choices : dict
        Catalogue choice (part) -> the chosen entry's name (None: the start design's
        part matches no entry).
    settings : dict
        Every parameter value set on the start design (name or glob -> SI value): the
        variables' and the chosen entries'.
    """

    parameters: dict[str, float]
    summary: RegionSummary
    objectives: tuple[float, ...]
    constraints: tuple[float, ...]
    evaluation: int
    choices: dict[str, str | None] = field(default_factory=dict)
    settings: dict[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class FrontResult:
    """The outcome of :func:`optimize_front` (SI).

    Attributes
    ----------
    objectives : list of Quantity
    variables : list of Variable
    constraints : list of Constraint
    choices : list of Choice
        The catalogue choices (discrete variables).
    start : FrontDesign
        The start design (its parameters None where a glob's matches differ).
    front : list of FrontDesign
        The non-dominated feasible designs, sorted by the first objective (module doc).
    feasible : ndarray (n, m)
        The objectives [their units] of every feasible design evaluated (the picture's
        cloud).
    evaluations, population, generations, budget : int
    algorithm : str
        ``"NSGA-II"`` or ``"NSGA-III"``.
    interrupted : bool
        Stopped by Ctrl-C: the front so far.
    outside : list of (str, float or None)
        Variables whose start value lies outside their range.
    history : list of (int, int)
        (evaluations so far, front size) after the start design and each generation.
    refused_by_check : int
        Designs the cheap check refused (:mod:`ppm_stiffness.optimize.precheck`):
        counted in ``evaluations``, their maps skipped.
    """

    objectives: list[Quantity]
    variables: list[Variable]
    constraints: list[Constraint]
    choices: list[Choice]
    start: FrontDesign
    front: list[FrontDesign]
    feasible: FloatArray
    evaluations: int
    population: int
    generations: int
    budget: int
    algorithm: str
    interrupted: bool = False
    outside: list[tuple[str, float | None]] = field(default_factory=list)
    history: list[tuple[int, int]] = field(default_factory=list)
    refused_by_check: int = 0

    def minimised(self) -> FloatArray:
        """The front's objectives (k, m) signed so that smaller is better [units]."""
        return signed(self.objectives, [d.objectives for d in self.front])

    def design(self, index: int, design: Design, region: RequiredRegionModel) -> Design:
        """Front design ``index`` as a design file's design: ``design`` with its
        parameters and ``region`` as its ``[workspace.required]``."""
        return with_region(apply_values(design, self.front[index].settings), region)

    def partial_note(self) -> str | None:
        """One line saying that the result is partial (None when it is not)."""
        if not self.interrupted:
            return None
        return (
            f"partial: interrupted after {self.evaluations} of {self.budget} evaluations; "
            "the front so far"
        )


def signed(objectives: Sequence[Quantity], values: ArrayLike) -> FloatArray:
    """Objective values (k, m) [units] with maximised ones negated: smaller is better."""
    v = np.asarray(values, dtype=float).reshape(-1, len(objectives))
    sign = np.array([-1.0 if q.maximise else 1.0 for q in objectives])
    return np.asarray(v * sign)


def front_plan(budget: int, start_in_ranges: bool = True) -> tuple[int, int]:
    """Population size S and generations after the initial population (module doc).

    Raises
    ------
    InputDataError
        A budget below the smallest that runs one generation, ``2 * 8`` (one more when
        the start design lies outside the ranges), saying which.
    """
    extra = 0 if start_in_ranges else 1
    smallest = 2 * MIN_FRONT_POPULATION + extra
    if budget < smallest:
        why = "" if start_in_ranges else " (the start design lies outside the --vary ranges)"
        raise InputDataError(
            f"--budget {budget} is too small for a Pareto front: it needs at least "
            f"{smallest} evaluations here{why}: a population of {MIN_FRONT_POPULATION} and "
            "one generation"
        )
    size = max(MIN_FRONT_POPULATION, min(MAX_FRONT_POPULATION, budget // 10))
    return size, (budget - extra) // size - 1


def scaled_objectives(
    objectives: Sequence[Quantity], summary: RegionSummary, scales: Sequence[float]
) -> FloatArray:
    """What pymoo minimises (m,): each objective signed and over |its start value|;
    :data:`NO_VALUE` where there is no finite value."""
    out = np.empty(len(objectives))
    for i, (q, s) in enumerate(zip(objectives, scales, strict=True)):
        value = q.value(summary)
        if not math.isfinite(value):
            out[i] = NO_VALUE
        else:
            out[i] = (-value if q.maximise else value) / s
    return out


def constraint_values(
    objectives: Sequence[Quantity], constraints: Sequence[Constraint], summary: RegionSummary
) -> FloatArray:
    """G (2 + number of constraints,): feasible when every entry is <= 0 (module doc)."""
    if summary.refused_by_check:
        from ppm_stiffness.optimize.precheck import check_violation

        gap = check_violation(summary.check_poses, summary.check_refused)
        return np.asarray([gap, 1.0, *([1.0] * len(constraints))])
    g = [0.0 if summary.covers else 1.0 - summary.covered_fraction + 1e-3]
    finite = all(math.isfinite(q.value(summary)) for q in objectives)
    g.append(0.0 if finite and summary.error is None else 1.0)
    for c in constraints:
        value = c.quantity.value(summary)
        if not math.isfinite(value):
            g.append(1.0)
            continue
        excess = value - c.bound if c.upper else c.bound - value
        g.append(excess / max(abs(c.bound), 1e-300))
    return np.asarray(g)


def non_dominated(values: ArrayLike) -> list[int]:
    """Indices of the rows of ``values`` (n, m) (smaller is better) that no other row
    dominates, the first of equal rows only, in row order."""
    f = np.asarray(values, dtype=float)
    keep: list[int] = []
    for i in range(f.shape[0]):
        le = np.all(f <= f[i], axis=1)
        lt = np.any(f < f[i], axis=1)
        if np.any(le & lt):
            continue
        if any(np.array_equal(f[j], f[i]) for j in keep):
            continue
        keep.append(i)
    return keep


def normalised(values: ArrayLike) -> FloatArray:
    """Front values (k, m) (smaller is better) mapped to [0, 1] per objective: 0 the
    front's best, 1 its worst (0 everywhere for an objective constant on the front)."""
    f = np.asarray(values, dtype=float)
    lo, hi = f.min(axis=0), f.max(axis=0)
    span = np.where(hi > lo, hi - lo, 1.0)
    return np.asarray((f - lo) / span)


def knee_index(values: ArrayLike) -> int:
    """The knee of a front (k, m) (smaller is better): in objectives normalised over the
    front (:func:`normalised`), the design farthest below the hyperplane through the
    extremes, ``sum(f) = 1`` (for two objectives the line between the two extreme
    designs), i.e. the largest ``1 - sum(f)``; the first of equals."""
    f = normalised(values)
    return int(np.argmax(1.0 - f.sum(axis=1)))


def weighted_index(values: ArrayLike, weights: Sequence[float]) -> int:
    """Achievement scalarisation: the design with the smallest ``max_i w_i f_i`` in
    normalised objectives (:func:`normalised`, 0 the front's best): a larger weight
    pulls the choice towards that objective's best; the first of equals."""
    f = normalised(values)
    w = np.asarray(weights, dtype=float)
    return int(np.argmin(np.max(f * w, axis=1)))


def parse_rule(text: str, n_objectives: int) -> tuple[str, tuple[float, ...]]:
    """``knee`` or ``weights=W1,W2,...`` (one positive weight per objective), or
    InputDataError."""
    if text.strip() == "knee":
        return "knee", ()
    name, sep, rest = text.partition("=")
    if name.strip() != "weights" or not sep:
        raise InputDataError(f"--pick must be knee or weights=W1,W2,..., got {text!r}")
    try:
        weights = tuple(float(w) for w in rest.split(","))
    except ValueError:
        raise InputDataError(f"--pick {text}: the weights must be numbers") from None
    if len(weights) != n_objectives:
        raise InputDataError(
            f"--pick {text}: give one weight per --objective ({n_objectives}), got {len(weights)}"
        )
    if not all(math.isfinite(w) and w > 0 for w in weights):
        raise InputDataError(f"--pick {text}: the weights must be finite and > 0")
    return "weights", weights


def choose(result: FrontResult, rule: tuple[str, tuple[float, ...]]) -> int:
    """The index in ``result.front`` of the design the rule picks (:func:`parse_rule`)."""
    f = result.minimised()
    if rule[0] == "knee":
        return knee_index(f)
    return weighted_index(f, rule[1])


def hypervolume_2d(values: ArrayLike, reference: Sequence[float]) -> float:
    """The area (units of f1 x f2) dominated by points (n, 2) (smaller is better) and
    bounded by ``reference``; points not below the reference in both add nothing."""
    f = np.asarray(values, dtype=float).reshape(-1, 2)
    r = np.asarray(reference, dtype=float)
    f = f[np.all(f < r, axis=1)]
    if f.size == 0:
        return 0.0
    f = f[np.lexsort((f[:, 1], f[:, 0]))]
    area, best = 0.0, r[1]
    for x, y in f:
        if y < best:
            area += (r[0] - x) * (best - y)
            best = y
    return float(area)


def settings(
    variables: Sequence[Variable], choices: Sequence[Choice], key: Sequence[float]
) -> dict[str, float]:
    """The parameter values of one design of the search: the continuous variables'
    (the key's first values) and the chosen catalogue entries' (its last, rounded)."""
    d = len(variables)
    out = assignments(variables, key[:d])
    out.update(choice_values(choices, key[d:]))
    return out


class _Archive:
    """Every design evaluated: key -> (rank, summary), with the budget's count."""

    def __init__(
        self,
        objectives: Sequence[Quantity],
        constraints: Sequence[Constraint],
        choices: Sequence[Choice] = (),
        variables: Sequence[Variable] = (),
    ):
        self.objectives, self.constraints, self.choices = objectives, constraints, choices
        self.variables = variables
        self.summaries: dict[tuple[float, ...], tuple[int, RegionSummary]] = {}
        self.evaluations = 0
        self.refused = 0

    def add(self, key: tuple[float, ...], summary: RegionSummary) -> None:
        self.evaluations += 1
        self.refused += summary.refused_by_check
        self.summaries.setdefault(key, (self.evaluations, summary))

    def record(
        self, variables: Sequence[Variable], key: tuple[float, ...], rank: int, s: RegionSummary
    ) -> FrontDesign:
        d = len(variables)
        return FrontDesign(
            parameters=assignments(variables, key[:d]),
            summary=s,
            objectives=tuple(q.value(s) for q in self.objectives),
            constraints=tuple(c.quantity.value(s) for c in self.constraints),
            evaluation=rank,
            choices={
                c.name: c.entry_name(int(round(x)))
                for c, x in zip(self.choices, key[d:], strict=True)
            },
            settings=settings(variables, self.choices, key),
        )

    def feasible(self) -> list[tuple[tuple[float, ...], int, RegionSummary]]:
        out = []
        for key, (rank, s) in self.summaries.items():
            g = constraint_values(self.objectives, self.constraints, s)
            if np.all(g <= 0):
                out.append((key, rank, s))
        return out

    def front(self, variables: Sequence[Variable]) -> tuple[list[FrontDesign], FloatArray]:
        rows = self.feasible()
        values = np.array(
            [[q.value(s) for q in self.objectives] for _, _, s in rows], dtype=float
        ).reshape(-1, len(self.objectives))
        keep = non_dominated(signed(self.objectives, values))
        designs = [self.record(variables, rows[i][0], rows[i][1], rows[i][2]) for i in keep]
        designs.sort(key=lambda d: (signed(self.objectives, [d.objectives])[0, 0], d.evaluation))
        return designs, values


def _algorithm(size: int, n_objectives: int) -> tuple[str, object]:
    """NSGA-II for two objectives, NSGA-III for more (module doc)."""
    if n_objectives == 2:
        from pymoo.algorithms.moo.nsga2 import NSGA2

        return "NSGA-II", NSGA2
    from pymoo.util.ref_dirs import get_reference_directions

    p = 1
    while math.comb(p + 1 + n_objectives - 1, n_objectives - 1) <= size:
        p += 1
    directions = get_reference_directions("das-dennis", n_objectives, n_partitions=p)
    from pymoo.algorithms.moo.nsga3 import NSGA3

    def make(**kwargs: object) -> object:
        return NSGA3(ref_dirs=directions, **kwargs)

    return "NSGA-III", make


def _round_choices(x: FloatArray, d: int, counts: FloatArray) -> FloatArray:
    """``x`` (n, d + c) with its last c columns (the choices) rounded to entry indices."""
    if counts.size:
        x[:, d:] = np.clip(np.round(x[:, d:]), 0.0, counts - 1.0)
    return x


def _choice_repair(d: int, counts: FloatArray) -> object:
    """A pymoo repair that keeps the choices' columns on integers (entry indices)."""
    from pymoo.core.repair import Repair

    class RoundChoices(Repair):
        def _do(self, problem: object, x: FloatArray, **kwargs: object) -> FloatArray:
            return _round_choices(np.asarray(x, dtype=float), d, counts)

    return RoundChoices()


def _import_pymoo() -> None:
    try:
        import pymoo  # noqa: F401
    except ImportError:
        raise InputDataError(
            "two or more --objective need pymoo: pip install 'ppm-stiffness[pareto]'"
        ) from None


def optimize_front(
    design: Design,
    variables: Sequence[Variable],
    objectives: Sequence[Quantity],
    region: RequiredRegionModel,
    *,
    budget: int,
    seed: int,
    wrench: ArrayLike | None = None,
    constraints: Sequence[Constraint] = (),
    executor: Executor | None = None,
    progress: Callable[[float], None] | None = None,
    choices: Sequence[Choice] = (),
    cheap_checks: bool = True,
    link_modes: int | None = None,
) -> FrontResult:
    """The Pareto front of ``objectives`` over ``region`` (module doc).

    Parameters
    ----------
    design : Design
        The start design; it must cover the region and give every objective a value.
    variables : sequence of Variable
        Continuous ranges.
    objectives : sequence of Quantity
        Two or more, distinct.
    region : RequiredRegionModel
    budget : int
        Most design evaluations, the start design's included.
    seed : int
        Seeds every random choice: the same seed gives the same front on every executor.
    wrench : array_like (6,), optional
        At the tool point [N·m, N]; needed by the loaded quantities.
    constraints : sequence of Constraint
    executor : concurrent.futures.Executor, optional
        Default :class:`~ppm_stiffness.optimize.executors.SerialExecutor`.
    progress : callable(amount), optional
        Called with the number of designs evaluated as they finish.
    choices : sequence of Choice
        Catalogue choices (:func:`~ppm_stiffness.optimize.catalogue.parse_choice`):
        integer variables, the entry's index, rounded by a repair step.
    cheap_checks : bool
        Skip the maps of a design that the cheap check refuses
        (:mod:`ppm_stiffness.optimize.precheck`); False computes them (the same
        ranking, at the maps' cost). The start design is always evaluated in full.
    link_modes : int, optional
        f1 with each leg's own modes, as :func:`~ppm_stiffness.optimize.optimizer
        .optimize_design` takes it (None: the default; 0: the legs condensed).

    Returns
    -------
    FrontResult

    Raises
    ------
    InputDataError
        Fewer than two or repeated objectives; a budget too small; pymoo missing; the
        start design does not cover the region or has no value of an objective.
    DesignError
        No feasible design was found.
    KeyboardInterrupt
        Ctrl-C before any feasible design.
    """
    _import_pymoo()
    from pymoo.core.problem import Problem

    if len(objectives) < 2 or len({q.name for q in objectives}) < len(objectives):
        raise InputDataError("a Pareto front needs two or more different objectives")
    if variables:
        check_distinct(variables)
    elif not choices:
        raise InputDataError("give at least one --vary NAME=LO:HI or --choose")
    outside: list[tuple[str, float | None]] = [
        (v.name, value) for v, value in outside_ranges(design, variables)
    ]
    chosen_start = [c.start(design) for c in choices]
    outside += [(c.name, None) for c, i in zip(choices, chosen_start, strict=True) if i is None]
    size, generations = front_plan(budget, not outside)
    w = None if wrench is None else np.asarray(wrench, dtype=float)
    quantities = (*objectives, *(c.quantity for c in constraints))
    check_quantities(design, quantities, w is not None)
    margin = any(q.needs_margin for q in quantities)
    frequencies = any(q.needs_frequencies for q in quantities)
    hinges = any(q.needs_hinges for q in quantities)
    reach = any(q.needs_candidate for q in quantities)
    condition = any(q.needs_condition for q in quantities)
    count = 0
    if frequencies:  # f1 as optimize_design takes it
        from ppm_stiffness.dynamics.legmodes import resolve_link_modes

        count = resolve_link_modes(link_modes)
    executor = SerialExecutor() if executor is None else executor
    check = "skip" if cheap_checks else "record"

    def evaluate(keys: list[tuple[float, ...] | None]) -> list[RegionSummary]:
        args = [
            candidate_task(
                design,
                None if k is None else settings(variables, choices, k),
                region,
                w,
                margin=margin,
                frequencies=frequencies,
                hinges=hinges,
                reach=reach,
                condition=condition,
                check="none" if k is None else check,
                link_modes=count,
            )
            for k in keys
        ]
        return run_ordered(executor, summarize_candidate, args, progress)

    try:
        start = evaluate([None])[0]
    except Interrupted:
        raise KeyboardInterrupt from None
    for q in objectives:
        _check_start(design, start, region, w, q)
    scales = [abs(q.value(start)) or 1.0 for q in objectives]
    archive = _Archive(objectives, constraints, choices, variables)
    starts = [v.start(design) for v in variables]
    start_key = None
    if not outside:
        start_key = tuple(float(x) for x in [*starts, *chosen_start] if x is not None)
    archive.evaluations = 1
    if start_key is not None:
        archive.summaries[start_key] = (1, start)

    d = len(variables)
    counts = np.array([len(c.entries) for c in choices], dtype=float)
    lo = np.concatenate([[v.lo for v in variables], np.full(len(choices), -0.5)])
    hi = np.concatenate([[v.hi for v in variables], counts - 0.5])
    rng = np.random.default_rng(np.random.SeedSequence(seed))
    init = _round_choices(lo + rng.random((size, lo.size)) * (hi - lo), d, counts)
    if start_key is not None:
        init[0] = start_key
    name, make = _algorithm(size, len(objectives))
    algorithm = make(  # type: ignore[operator]
        pop_size=size,
        sampling=init,
        eliminate_duplicates=True,
        repair=_choice_repair(d, counts),
    )
    n_g = 2 + len(constraints)
    problem = Problem(n_var=lo.size, n_obj=len(objectives), n_ieq_constr=n_g, xl=lo, xu=hi)
    algorithm.setup(problem, termination=("n_gen", generations + 1), seed=seed, verbose=False)
    feasible_start = bool(np.all(constraint_values(objectives, constraints, start) <= 0))
    history = [(1, 1 if feasible_start else 0)]
    ran, interrupted = _evolve(algorithm, problem, archive, evaluate, budget, scales, history)
    front, values = archive.front(variables)
    if not front:
        if interrupted:
            raise KeyboardInterrupt from None
        raise DesignError(
            f"none of the {archive.evaluations} designs evaluated covers the region, gives "
            "every objective a value and meets the constraints; widen the --vary ranges, "
            "relax --constraint or shrink the region"
        )
    start_record = FrontDesign(
        parameters={v.name: s for v, s in zip(variables, starts, strict=True)},  # type: ignore[misc]
        summary=start,
        objectives=tuple(q.value(start) for q in objectives),
        constraints=tuple(c.quantity.value(start) for c in constraints),
        evaluation=1,
        choices={
            c.name: None if i is None else c.entry_name(i)
            for c, i in zip(choices, chosen_start, strict=True)
        },
    )
    return FrontResult(
        objectives=list(objectives),
        variables=list(variables),
        constraints=list(constraints),
        choices=list(choices),
        start=start_record,
        front=front,
        feasible=values,
        evaluations=archive.evaluations,
        population=size,
        generations=max(ran, 0),
        budget=budget,
        algorithm=name,
        interrupted=interrupted,
        outside=outside,
        history=history,
        refused_by_check=archive.refused,
    )


def _evolve(
    algorithm: Any,
    problem: Any,
    archive: _Archive,
    evaluate: Callable[[list[tuple[float, ...] | None]], list[RegionSummary]],
    budget: int,
    scales: Sequence[float],
    history: list[tuple[int, int]],
) -> tuple[int, bool]:
    """pymoo's ask-and-tell loop: each generation's new designs evaluated as one batch
    (``evaluate``), recorded in ``archive``, told back as F and G; ``history`` gets
    (evaluations, front size) after each. Stops when pymoo's termination is met, when
    the next generation would pass the budget, or when pymoo has no new design.
    Returns (generations run, interrupted by Ctrl-C)."""
    from pymoo.core.evaluator import Evaluator
    from pymoo.problems.static import StaticProblem

    objectives, constraints = archive.objectives, archive.constraints
    ran = -1  # the initial population is not a generation
    try:
        while algorithm.has_next():
            pop = algorithm.ask()
            if pop is None or len(pop) == 0:  # no new design left (few discrete choices)
                break
            keys = [tuple(float(x) for x in row) for row in np.asarray(pop.get("X"), dtype=float)]
            todo = [k for k in dict.fromkeys(keys) if k not in archive.summaries]
            if archive.evaluations + len(todo) > budget:
                break
            try:
                results = evaluate(list(todo))
            except Interrupted as stop:
                for i in sorted(stop.done):
                    archive.add(todo[i], stop.done[i])
                raise
            for k, summary in zip(todo, results, strict=True):
                archive.add(k, summary)
            summaries = [archive.summaries[k][1] for k in keys]
            f = np.array([scaled_objectives(objectives, x, scales) for x in summaries])
            g = np.array([constraint_values(objectives, constraints, x) for x in summaries])
            Evaluator().eval(StaticProblem(problem, F=f, G=g), pop)
            algorithm.tell(infills=pop)
            ran += 1
            history.append((archive.evaluations, len(archive.front(archive.variables)[0])))
    except Interrupted:
        return ran, True
    return ran, False
