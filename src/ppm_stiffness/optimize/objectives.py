"""Objectives and constraints of ``optimize``, in physical units and sign.

Each quantity is a function of a :class:`~ppm_stiffness.optimize.summary.RegionSummary`
(never of raw eigenvalues of the mixed-unit K):

=========================  ===========================================  ========  =========
name                       value                                        unit      optimum
=========================  ===========================================  ========  =========
``worst-k-translational``  min over the region of min(k_x, k_y)         N/m       maximum
``worst-k-rotational``     min over the region of k_phi                 N·m/rad   maximum
``max-displacement``       max over the region of |(dx, dy)|, --wrench  m         minimum
``max-rotation``           max over the region of |phi_z|, --wrench     rad       minimum
=========================  ===========================================  ========  =========

A constraint is ``QUANTITY<=VALUE`` or ``QUANTITY>=VALUE`` (SI), QUANTITY one of the
names above or a summary figure (``k_phi_p5``, ``covered_fraction``, ...). A candidate
is *feasible* when it covers the region and meets every constraint; its violation
(:func:`violation`) is the uncovered fraction plus each constraint's shortfall relative
to its bound (1 for a quantity without a finite value).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.optimize.summary import FIGURE_UNITS, RegionSummary


@dataclass(frozen=True)
class Quantity:
    """A named function of the summary figures."""

    name: str
    unit: str
    maximise: bool
    needs_wrench: bool
    description: str

    def value(self, summary: RegionSummary) -> float:
        """The quantity of one summary [unit]; NaN when it has none."""
        if self.name == "worst-k-translational":
            return min(summary["k_x_min"], summary["k_y_min"])
        key = _FIGURE_OF.get(self.name, self.name.replace("-", "_"))
        return summary[key]


_FIGURE_OF = {
    "worst-k-rotational": "k_phi_min",
    "max-displacement": "max_displacement",
    "max-rotation": "max_rotation",
}

#: The objectives ``optimize --objective`` accepts.
OBJECTIVES: dict[str, Quantity] = {
    q.name: q
    for q in (
        Quantity(
            "worst-k-translational", "N/m", True, False, "min over the region of min(k_x, k_y)"
        ),
        Quantity("worst-k-rotational", "N·m/rad", True, False, "min over the region of k_phi"),
        Quantity("max-displacement", "m", False, True, "max |(dx, dy)| of P under --wrench"),
        Quantity("max-rotation", "rad", False, True, "max |phi_z| under --wrench"),
    )
}


def quantity(name: str) -> Quantity:
    """An objective or a summary figure by name (InputDataError if unknown)."""
    if name in OBJECTIVES:
        return OBJECTIVES[name]
    key = name.replace("-", "_")
    if key in FIGURE_UNITS:
        loaded = key in ("max_displacement", "max_rotation")
        return Quantity(name, FIGURE_UNITS[key], not loaded, loaded, key)
    known = ", ".join([*OBJECTIVES, *FIGURE_UNITS])
    raise InputDataError(f"unknown quantity {name!r}; use one of {known}")


@dataclass(frozen=True)
class Constraint:
    """``quantity <= bound`` (``upper``) or ``quantity >= bound``."""

    quantity: Quantity
    bound: float
    upper: bool

    def shortfall(self, summary: RegionSummary) -> float:
        """0 when met; else the excess relative to |bound| (1 when not finite)."""
        value = self.quantity.value(summary)
        if not math.isfinite(value):
            return 1.0
        excess = value - self.bound if self.upper else self.bound - value
        return max(0.0, excess) / max(abs(self.bound), 1e-300)

    def __str__(self) -> str:
        return f"{self.quantity.name}{'<=' if self.upper else '>='}{self.bound:g}"


_CONSTRAINT = re.compile(r"^\s*([A-Za-z_][\w-]*)\s*(<=|>=)\s*(\S+)\s*$")


def parse_constraint(text: str) -> Constraint:
    """``QUANTITY<=VALUE`` or ``QUANTITY>=VALUE`` (VALUE in SI), or InputDataError."""
    match = _CONSTRAINT.match(text)
    if match is None:
        raise InputDataError(
            f"--constraint must be QUANTITY<=VALUE or QUANTITY>=VALUE, got {text!r}"
        )
    try:
        bound = float(match.group(3))
    except ValueError:
        raise InputDataError(f"--constraint {text}: {match.group(3)!r} is not a number") from None
    if not math.isfinite(bound):
        raise InputDataError(f"--constraint {text}: the bound must be finite")
    try:
        q = quantity(match.group(1))
    except InputDataError as exc:
        raise InputDataError(f"--constraint {text}: {exc}") from None
    return Constraint(q, bound, match.group(2) == "<=")


def violation(summary: RegionSummary, constraints: Sequence[Constraint]) -> float:
    """Uncovered fraction plus the constraints' shortfalls (0: feasible)."""
    total = 0.0 if summary.covers else 1.0 - summary.covered_fraction + 1e-3
    return total + sum(c.shortfall(summary) for c in constraints)
