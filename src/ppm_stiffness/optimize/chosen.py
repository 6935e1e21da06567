"""The chosen front design against the start design, as ``compare`` sets them side by
side (:func:`~ppm_stiffness.optimize.sweep.summarize_designs`, the ``compare``
command's function).

:func:`compare_chosen` evaluates both designs afresh over the region (the chosen one
as the design file ``optimize --out`` writes: :meth:`FrontResult.design`) and lists,
for each, every objective, every constrained quantity and the figures ``compare``
prints for such designs (covered fraction, stiffness statistics, the loaded ones with
a wrench, f1 with a mass model, the load margin when an objective or a constraint
asks for it). These two evaluations are not part of the search and not counted in its
budget.
"""

from __future__ import annotations

import math
from concurrent.futures import Executor
from dataclasses import dataclass

from numpy.typing import ArrayLike

from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import RequiredRegionModel
from ppm_stiffness.optimize.pareto import FrontResult
from ppm_stiffness.optimize.summary import (
    FIGURE_UNITS,
    RegionSummary,
    figure_label,
    figure_names,
)
from ppm_stiffness.optimize.sweep import summarize_designs


@dataclass(frozen=True)
class ComparisonRow:
    """One quantity of the start and the chosen design (SI).

    Attributes
    ----------
    name : str
        An objective's name, a constraint (``f1>=240``) or a summary figure.
    label : str
        For tables.
    unit : str
    start, chosen : float
        The two designs' values (NaN: none).
    """

    name: str
    label: str
    unit: str
    start: float
    chosen: float

    @property
    def ratio(self) -> float:
        """chosen / start (NaN when either is not finite or the start is 0)."""
        if not (math.isfinite(self.start) and math.isfinite(self.chosen)) or self.start == 0:
            return math.nan
        return self.chosen / self.start


@dataclass(frozen=True)
class Comparison:
    """The chosen design against the start (:func:`compare_chosen`)."""

    index: int
    rows: list[ComparisonRow]
    summaries: tuple[RegionSummary, RegionSummary]


def compare_chosen(
    design: Design,
    result: FrontResult,
    index: int,
    region: RequiredRegionModel,
    *,
    wrench: ArrayLike | None = None,
    executor: Executor | None = None,
    link_modes: int | None = None,
) -> Comparison:
    """Front design ``index`` of ``result`` against the start ``design`` (module doc).

    Parameters
    ----------
    design : Design
        The start design of the run.
    result : FrontResult
    index : int
        A row of ``result.front`` (:func:`~ppm_stiffness.optimize.pareto.choose`).
    region : RequiredRegionModel
        The run's region.
    wrench : array_like (6,), optional
        The run's wrench [N·m, N].
    executor : concurrent.futures.Executor, optional
    link_modes : int, optional
        The run's modes per leg of f1 (None: the default, as the run takes it).

    Returns
    -------
    Comparison
        Rows: the objectives, the constraints' quantities, then the other figures.
    """
    from ppm_stiffness.dynamics.legmodes import resolve_link_modes

    quantities = [*result.objectives, *(c.quantity for c in result.constraints)]
    margin = any(q.needs_margin for q in quantities)
    chosen = result.design(index, design, region)
    pair = summarize_designs(
        [design, chosen],
        region,
        wrench=wrench,
        executor=executor,
        margin=margin,
        frequencies=design.has_mass_model,
        hinges=any(q.needs_hinges for q in quantities),
        reach=any(q.needs_candidate for q in quantities),
        condition=any(q.needs_condition for q in quantities),
        link_modes=resolve_link_modes(link_modes) if design.has_mass_model else 0,
    )
    start, best = pair
    rows = [
        ComparisonRow(q.name, q.name, q.unit, q.value(start), q.value(best))
        for q in result.objectives
    ]
    rows += [
        ComparisonRow(
            str(c), str(c), c.quantity.unit, c.quantity.value(start), c.quantity.value(best)
        )
        for c in result.constraints
    ]
    names = figure_names(
        design.planar,
        wrench=wrench is not None,
        mass=design.has_mass_model,
        margin=margin,
    )
    rows += [
        ComparisonRow(n, figure_label(n, design.planar), FIGURE_UNITS[n], start[n], best[n])
        for n in names
    ]
    return Comparison(index, rows, (start, best))
