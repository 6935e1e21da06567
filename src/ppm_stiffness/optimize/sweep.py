"""Sweeps: the summary figures of many designs, on a grid of parameter values or on a
scrambled Sobol sample.

Grid: every combination of the variables' values (``NAME=LO:HI:N``), the first
variable varying slowest. Sobol: ``n`` points (a power of 2) of
:class:`scipy.stats.qmc.Sobol`, scrambled with ``seed``, mapped onto the ranges. Each
design is one task on the executor (:mod:`ppm_stiffness.optimize.executors`); results
come back in order whatever the executor.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import RequiredRegionModel
from ppm_stiffness.optimize.executors import Interrupted, SerialExecutor, run_ordered
from ppm_stiffness.optimize.summary import RegionSummary, candidate_task, summarize_candidate
from ppm_stiffness.optimize.variables import Variable, assignments, check_distinct

#: Most designs in one sweep.
MAX_DESIGNS = 1_000_000


@dataclass(frozen=True)
class SweepResult:
    """Designs of a sweep and their summaries (SI).

    Attributes
    ----------
    variables : list of Variable
    points : ndarray (n, n_variables)
        The variables' values of each design [their SI units].
    summaries : list of RegionSummary
        One per point done (fewer than ``points`` when interrupted).
    sample : str
        ``"grid"`` or ``"sobol"``.
    interrupted : bool
        Stopped by Ctrl-C: ``summaries`` holds the designs done, in order, up to the
        first one not done.
    """

    variables: list[Variable]
    points: FloatArray
    summaries: list[RegionSummary]
    sample: str
    interrupted: bool = False

    def partial_note(self) -> str | None:
        """One line saying that the sweep is partial (None when it is not): for a
        comment in the files written from it."""
        if not self.interrupted:
            return None
        return (
            f"partial: interrupted after {len(self.summaries)} of {len(self.points)} "
            "designs; the rows are the designs done, in order"
        )

    def figure(self, name: str) -> FloatArray:
        """One figure of every design done (n_done,) [SI]; NaN where it has none."""
        return np.array([s[name] for s in self.summaries], dtype=float)


def sweep_points(
    variables: Sequence[Variable], sample: str = "grid", count: int | None = None, seed: int = 0
) -> FloatArray:
    """The designs' variable values (n, n_variables).

    Raises
    ------
    InputDataError
        A variable without N on a grid; a Sobol count that is not a power of 2; too
        many designs.
    """
    check_distinct(variables)
    if sample == "grid":
        axes = [v.grid() for v in variables]
        total = int(np.prod([a.size for a in axes]))
        if total > MAX_DESIGNS:
            raise InputDataError(f"the grid has {total} designs, more than {MAX_DESIGNS}")
        return np.array(list(itertools.product(*axes)), dtype=float).reshape(-1, len(variables))
    if sample == "sobol":
        from scipy.stats import qmc

        if count is None or count < 1 or count & (count - 1) or count > MAX_DESIGNS:
            raise InputDataError(
                f"--sample sobol:N needs N a power of 2 up to {MAX_DESIGNS}, got {count}"
            )
        unit = qmc.Sobol(d=len(variables), scramble=True, seed=np.random.default_rng(seed))
        u = unit.random_base2(int(count).bit_length() - 1)
        lo = np.array([v.lo for v in variables])
        hi = np.array([v.hi for v in variables])
        return np.asarray(lo + u * (hi - lo))
    raise InputDataError(f"unknown sample {sample!r}; use grid or sobol:N")


def sweep_designs(
    design: Design,
    variables: Sequence[Variable],
    region: RequiredRegionModel,
    *,
    wrench: ArrayLike | None = None,
    sample: str = "grid",
    count: int | None = None,
    seed: int = 0,
    executor: Executor | None = None,
    progress: Callable[[float], None] | None = None,
    margin: bool = False,
    frequencies: bool = True,
    hinges: bool = False,
    reach: bool = False,
    condition: bool = False,
    link_modes: int | None = None,
) -> SweepResult:
    """Summary figures (:func:`~ppm_stiffness.optimize.summary.summarize`) of every
    design of the sweep.

    Parameters
    ----------
    design : Design
        The base design; each point sets the variables on a copy.
    variables : sequence of Variable
    region : RequiredRegionModel
    wrench : array_like (6,), optional
        At the tool point [N·m, N], for the loaded figures.
    sample : {"grid", "sobol"}
    count : int, optional
        Sobol points (a power of 2).
    seed : int
        Scrambles the Sobol sample.
    executor : concurrent.futures.Executor, optional
        Default :class:`~ppm_stiffness.optimize.executors.SerialExecutor`.
    progress : callable(amount), optional
        Called with the number of designs of each task as it finishes
        (:func:`~ppm_stiffness.optimize.executors.run_ordered`).
    margin : bool
        Also the load margin of ``wrench`` on the margin sub-grid
        (:mod:`ppm_stiffness.optimize.margin`; about 0.1 s per pose).
    frequencies : bool
        The f1 figures of a design with a mass model (several times the cost of the
        stiffness figures); False: NaN.
    hinges : bool
        The hinge figures (``hinge_range_min``, ``hinge_stress_max``); False: NaN.
    reach : bool
        The share of each design's candidate region reached (``candidate_share``);
        False: NaN.
    condition : bool
        The length-balanced K's condition number (``condition_max``); False: NaN.
    link_modes : int, optional
        The f1 figures with each leg's own modes, this many per leg
        (:func:`~ppm_stiffness.optimize.summary.summarize`); None: the default, as
        ``analyze``; 0: the legs condensed.

    Returns
    -------
    SweepResult
        ``interrupted`` on Ctrl-C, with the designs done so far.
    """
    points = sweep_points(variables, sample, count, seed)
    w = None if wrench is None else np.asarray(wrench, dtype=float)
    executor = SerialExecutor() if executor is None else executor
    args = [
        candidate_task(
            design,
            assignments(variables, p),
            region,
            w,
            margin=margin,
            frequencies=frequencies,
            hinges=hinges,
            reach=reach,
            condition=condition,
            link_modes=link_modes,
        )
        for p in points
    ]
    try:
        summaries = run_ordered(executor, summarize_candidate, args, progress)
    except Interrupted as stop:
        done: list[RegionSummary] = []
        for i in range(len(args)):
            if i not in stop.done:
                break
            done.append(stop.done[i])
        return SweepResult(list(variables), points, done, sample, interrupted=True)
    return SweepResult(list(variables), points, summaries, sample)


def summarize_designs(
    designs: Sequence[Design],
    region: RequiredRegionModel,
    *,
    wrench: ArrayLike | None = None,
    executor: Executor | None = None,
    progress: Callable[[float], None] | None = None,
    margin: bool = False,
    frequencies: bool = True,
    hinges: bool = False,
    reach: bool = False,
    condition: bool = False,
    link_modes: int | None = None,
) -> list[RegionSummary]:
    """Summary figures of several designs over one region (``compare``), in order;
    ``margin``: also the load margin of ``wrench``; ``frequencies``: f1 for a design
    with a mass model; ``hinges``: the hinge figures of a design with notch hinges
    (NaN for another); ``reach``: the share of each
    design's candidate region reached; ``condition``: the balanced K's condition number;
    f1 with each leg's ``link_modes`` own modes (None: the default, as ``analyze``;
    0: the legs condensed).

    Raises
    ------
    InputDataError
        Designs of different task coordinates (they cannot share a region).
    """
    tasks = {tuple(d.task_coordinates) for d in designs}
    if len(tasks) > 1:
        raise InputDataError(
            "the designs compared must share their task coordinates; these have "
            + " and ".join(f"({', '.join(t)})" for t in sorted(tasks))
        )
    w = None if wrench is None else np.asarray(wrench, dtype=float)
    executor = SerialExecutor() if executor is None else executor
    return run_ordered(
        executor,
        summarize_candidate,
        [
            candidate_task(
                d,
                None,
                region,
                w,
                margin=margin,
                frequencies=frequencies,
                hinges=hinges,
                reach=reach,
                condition=condition,
                link_modes=link_modes,
            )
            for d in designs
        ],
        progress,
    )
