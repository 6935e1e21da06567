"""Objectives and constraints of ``optimize``, in physical units and sign.

Each quantity is a function of a :class:`~ppm_stiffness.optimize.summary.RegionSummary`
(never of raw eigenvalues of the mixed-unit K):

=========================  =============================================  ========  =======
name                       value                                          unit      optimum
=========================  =============================================  ========  =======
``worst-k-translational``  min over the region of the worst translational  N/m       maximum
                           principal stiffness (planar: min(k_x, k_y))
``worst-k-rotational``     min over the region of the worst rotational     N·m/rad   maximum
                           principal stiffness (planar: k_phi)
``max-displacement``       max over the region of the tool point's         m         minimum
                           displacement under --wrench (planar: |(dx, dy)|)
``max-rotation``           max over the region of the rotation under       rad       minimum
                           --wrench (planar: |phi_z|)
``first-frequency``        min over the region of the first natural        Hz        maximum
                           frequency (a mass model; loaded under --wrench)
``load-margin``            min over the margin sub-grid of the load        1         maximum
                           margin of --wrench
``moving-mass``            the mass of every body moving with the          kg        minimum
                           platform: platform, links (a parallelogram's
                           two bars), carriages (a mass model); a rotor's
                           reflected inertia is not a mass and does not
                           count
``range``                  min over the region of the hinge range: each   rad or m  maximum
                           drive's range alone to yield, the smallest
                           over the drives (notch hinges with yield
                           strengths; rad for rotary drives)
``stress``                 max over the region of the largest hinge       Pa        minimum
                           stress with the drives anywhere within their
                           strokes (notch hinges, strokes)
``actuator-effort``        max over the region of the largest |actuator   N or N·m  minimum
                           force or torque| under --wrench (drives of
                           one kind; ``effort``)
``actuator-force``         the same over the linear drives                N         minimum
``actuator-torque``        the same over the rotary drives                N·m       minimum
``condition-number``       max over the region of the condition number    1         minimum
                           of the length-balanced K at the tool point
=========================  =============================================  ========  =======

For a planar design the stiffness objectives keep the paper's decoupled k_x, k_y, k_phi
(:mod:`ppm_stiffness.optimize.summary`); for any other design they are the spatial
worst-direction principal stiffnesses (``k_translational_min``, ``k_rotational_min``).
``f1`` is another name of ``first-frequency``, ``effort`` of ``actuator-effort``.

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

from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.optimize.summary import FIGURE_UNITS, RegionSummary, drive_units


@dataclass(frozen=True)
class Quantity:
    """A named function of the summary figures."""

    name: str
    unit: str
    maximise: bool
    needs_wrench: bool
    description: str
    needs_mass: bool = False
    needs_margin: bool = False
    needs_hinges: bool = False
    needs_candidate: bool = False
    needs_condition: bool = False

    @property
    def needs_frequencies(self) -> bool:
        """The quantity needs the f1 figures (the moving mass needs a mass model, not f1)."""
        return self.needs_mass and self.name != "moving-mass"

    def value(self, summary: RegionSummary) -> float:
        """The quantity of one summary [unit]; NaN when it has none."""
        if self.name == "moving-mass":
            return summary.moving_mass
        if self.name == "reachable-workspace":
            return summary.candidate_share
        if self.name in _ATTRIBUTE_OF:
            return (
                _effort(summary)
                if self.name == "actuator-effort"
                else _ATTRIBUTE_OF[self.name](summary)
            )
        if self.name == "worst-k-translational":
            if not summary.planar:
                return summary["k_translational_min"]
            return min(summary["k_x_min"], summary["k_y_min"])
        if self.name == "worst-k-rotational" and not summary.planar:
            return summary["k_rotational_min"]
        key = _FIGURE_OF.get(self.name, self.name.replace("-", "_"))
        return summary[key]


def _effort(summary: RegionSummary) -> float:
    """The larger of the force and torque efforts that have a value (a design of one
    kind of drive has one; :func:`check_quantities` refuses a mixed one)."""
    values = [
        v for v in (summary.actuator_force_max, summary.actuator_torque_max) if not math.isnan(v)
    ]
    return max(values) if values else math.nan


#: The quantities that are attributes of the summary, not figures.
_ATTRIBUTE_OF = {
    "actuator-effort": _effort,
    "actuator-force": lambda s: s.actuator_force_max,
    "actuator-torque": lambda s: s.actuator_torque_max,
    "condition-number": lambda s: s.condition_max,
}

_FIGURE_OF = {
    "worst-k-rotational": "k_phi_min",
    "max-displacement": "max_displacement",
    "max-rotation": "max_rotation",
    "first-frequency": "f1_min",
    "load-margin": "load_margin",
    "range": "hinge_range_min",
    "stress": "hinge_stress_max",
}

#: The objectives ``optimize --objective`` accepts.
OBJECTIVES: dict[str, Quantity] = {
    q.name: q
    for q in (
        Quantity(
            "worst-k-translational",
            "N/m",
            True,
            False,
            "min over the region of the worst translational principal stiffness "
            "(planar: min(k_x, k_y))",
        ),
        Quantity(
            "worst-k-rotational",
            "N·m/rad",
            True,
            False,
            "min over the region of the worst rotational principal stiffness (planar: k_phi)",
        ),
        Quantity(
            "max-displacement",
            "m",
            False,
            True,
            "max displacement of the tool point under --wrench (planar: |(dx, dy)|)",
        ),
        Quantity(
            "max-rotation", "rad", False, True, "max rotation under --wrench (planar: |phi_z|)"
        ),
        Quantity(
            "first-frequency",
            "Hz",
            True,
            False,
            "min over the region of the first natural frequency (with the legs' own "
            "modes as modes and analyze; --link-modes)",
            needs_mass=True,
        ),
        Quantity(
            "load-margin",
            "1",
            True,
            True,
            "min over the margin sub-grid of the load margin of --wrench",
            needs_margin=True,
        ),
        Quantity(
            "moving-mass",
            "kg",
            False,
            False,
            "the mass of every body moving with the platform: platform, links, carriages "
            "(rotor inertia not counted)",
            needs_mass=True,
        ),
        Quantity(
            "range",
            "rad or m",
            True,
            False,
            "min over the region of the hinge range (each drive's range alone to yield, "
            "the smallest over the drives)",
            needs_hinges=True,
        ),
        Quantity(
            "stress",
            "Pa",
            False,
            False,
            "max over the region of the largest hinge stress, the drives anywhere within "
            "their strokes",
            needs_hinges=True,
        ),
        Quantity(
            "reachable-workspace",
            "1",
            True,
            False,
            "the share of the candidate region's ([workspace.candidate]) grid poses "
            "reached without refusal (unreachable, limits, singular)",
            needs_candidate=True,
        ),
        Quantity(
            "actuator-effort",
            "N or N·m",
            False,
            True,
            "max over the region of the largest actuator force or torque magnitude under "
            "--wrench (a design whose drives are of one kind)",
        ),
        Quantity(
            "actuator-force",
            "N",
            False,
            True,
            "max over the region of the largest linear actuator force magnitude under --wrench",
        ),
        Quantity(
            "actuator-torque",
            "N·m",
            False,
            True,
            "max over the region of the largest rotary actuator torque magnitude under --wrench",
        ),
        Quantity(
            "condition-number",
            "1",
            False,
            False,
            "max over the region of the condition number of the length-balanced K "
            "(K_rr / L^2, K_rt / L, K_tt; L = 0.1 m) at the tool point, actuators locked",
            needs_condition=True,
        ),
    )
}
#: Other names of the objectives.
ALIASES = {"f1": "first-frequency", "effort": "actuator-effort"}


def quantity(name: str) -> Quantity:
    """An objective or a summary figure by name (InputDataError if unknown)."""
    if name in OBJECTIVES or name in ALIASES:
        return OBJECTIVES[ALIASES.get(name, name)]
    key = name.replace("-", "_")
    if key in FIGURE_UNITS:
        loaded = key in ("max_displacement", "max_rotation", "load_margin")
        return Quantity(
            name,
            FIGURE_UNITS[key],
            key not in ("max_displacement", "max_rotation", "hinge_stress_max"),
            loaded,
            key,
            needs_mass=key.startswith("f1_"),
            needs_margin=key == "load_margin",
            needs_hinges=key.startswith("hinge_"),
        )
    known = ", ".join([*OBJECTIVES, *ALIASES, *FIGURE_UNITS])
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


def for_design(q: Quantity, design: Design) -> Quantity:
    """``q`` with its unit stated for ``design`` when its drives are of one kind:
    ``actuator-effort``'s "N or N·m" becomes N (linear drives) or N·m (rotary ones),
    ``range``'s "rad or m" rad or m; any other quantity unchanged."""
    if q.name == "actuator-effort":
        kinds = {u for u in drive_units(design) if u is not None}
    elif q.name == "range":
        kinds = {leg.actuator_units()[1] for leg in design.legs if leg.is_actuated()}
    else:
        return q
    if len(kinds) != 1:
        return q
    from dataclasses import replace

    return replace(q, unit=kinds.pop())


def parse_constraint(text: str, design: Design | None = None) -> Constraint:
    """``QUANTITY<=VALUE`` or ``QUANTITY>=VALUE`` (VALUE in SI), or InputDataError; the
    quantity's unit stated for ``design`` when given (:func:`for_design`)."""
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
    return Constraint(q if design is None else for_design(q, design), bound, match.group(2) == "<=")


def check_quantities(design: Design, quantities: Sequence[Quantity], wrench: bool) -> None:
    """Refuse quantities that ``design`` or the options cannot give: a loaded one
    without a wrench (InputDataError), f1 without a mass model (DesignError naming the
    missing [platform] table), a hinge quantity without notch hinges (DesignError),
    a candidate-region quantity without ``[workspace.candidate]`` (DesignError),
    or a stiffness figure of the other family (k_x, k_y,
    k_phi are a planar design's; k_translational, k_rotational any other's)."""
    for q in quantities:
        if q.needs_wrench and not wrench:
            raise InputDataError(f"{q.name} needs --wrench (the load whose effect it measures)")
        if q.needs_mass and not design.has_mass_model:
            raise DesignError(
                f"{q.name}: design {design.name!r} has no mass model; add a [platform] "
                "table (mass [kg] and inertia [kg·m^2], or a shape; docs/dynamics.md)"
            )
        if q.needs_hinges or q.description.startswith("hinge_"):
            _require_hinges(design, q)
        if q.needs_candidate and design.workspace.candidate is None:
            raise DesignError(
                f"{q.name}: design {design.name!r} has no candidate region; add a "
                "[workspace.candidate] table (the keys of [workspace.required], usually wider "
                "ranges)"
            )
        if q.name.startswith("actuator-"):
            _require_drives(design, q)
        key = q.description
        family = "paper" if key[:4] in ("k_x_", "k_y_", "k_ph") else None
        family = "principal" if key.startswith(("k_translational", "k_rotational")) else family
        if family is not None and (family == "paper") != design.planar:
            names = "k_x, k_y, k_phi" if design.planar else "k_translational, k_rotational"
            raise InputDataError(
                f"{q.name} is not a figure of design {design.name!r}; its stiffness figures "
                f"are {names} (_min, _mean, _p5)"
            )


def _require_drives(design: Design, q: Quantity) -> None:
    """Refuse an actuator effort that ``design``'s drives cannot give: the force of a
    design without linear drives, the torque of one without rotary drives, the effort
    (one unit) of one with both (DesignError naming the per-kind quantities)."""
    kinds = {u for u in drive_units(design) if u is not None}
    if q.name == "actuator-effort" and len(kinds) > 1:
        raise DesignError(
            f"{q.name}: design {design.name!r} has linear (N) and rotary (N·m) drives; "
            "use actuator-force [N] and actuator-torque [N·m]"
        )
    wanted = {"actuator-force": "N", "actuator-torque": "N·m"}.get(q.name)
    if wanted is not None and wanted not in kinds:
        kind = "linear" if wanted == "N" else "rotary"
        raise DesignError(f"{q.name}: design {design.name!r} has no {kind} drive")


def _require_hinges(design: Design, q: Quantity) -> None:
    """Refuse a hinge quantity of a design without hinges, yield strengths or (the
    stress) strokes (DesignError naming the quantity)."""
    from ppm_stiffness.statics.hinge_stress import require_hinge_figures, stroke_corners

    try:
        require_hinge_figures(design)
        if q.name in ("stress", "hinge-stress-max", "hinge_stress_max"):
            stroke_corners(design)
    except DesignError as exc:
        raise DesignError(f"{q.name}: {exc}") from None


def violation(summary: RegionSummary, constraints: Sequence[Constraint]) -> float:
    """Uncovered fraction plus the constraints' shortfalls (0: feasible); for a design
    the cheap check refused, :func:`~ppm_stiffness.optimize.precheck.check_violation`
    plus 1 per constraint (no value), whether or not its maps were computed."""
    if summary.refused_by_check:
        from ppm_stiffness.optimize.precheck import check_violation

        gap = check_violation(summary.check_poses, summary.check_refused)
        return gap + float(len(constraints))
    total = 0.0 if summary.covers else 1.0 - summary.covered_fraction + 1e-3
    return total + sum(c.shortfall(summary) for c in constraints)
