"""Design variables of a sweep or an optimisation: ``NAME=LO:HI[:N]``.

NAME is a parameter name exactly as ``ppm-stiffness calibrate --list-parameters``
prints it (``leg1.platform_radius``), or a glob (``leg*.platform_radius``) whose
matches vary together as one variable. LO and HI are SI values (the parameter's unit,
:meth:`~ppm_stiffness.design.schema.Design.parameter_unit`), LO < HI; N (sweeps on a
grid) is the number of values, ends included, at least 2.

Two geometric variables are not scalar parameters of the design file
(:data:`GEOMETRY_VARIABLES`): ``platform_radius`` and ``base_radius`` [m], the common
horizontal distance from the z axis of every leg's ``platform_point`` (platform frame)
or ``base_point`` (F_b), for designs whose legs all have such points at one radius (a
hexapod's joint circles, a tripod's rail and platform circles). Setting one scales the
x and y of every leg's point by the same factor (angles about z and heights kept):
:func:`apply_values`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import shared_parameter, tied_note

#: Most values along one variable of a grid sweep.
MAX_VALUES = 10_000


@dataclass(frozen=True)
class Variable:
    """One design variable.

    Attributes
    ----------
    name : str
        As given: a parameter name or a glob.
    matches : tuple of str
        The parameter names it sets (one value for all).
    lo, hi : float
        Range [SI unit of the parameter], lo < hi.
    count : int or None
        Grid values (sweeps), None for a continuous range (optimisation, Sobol).
    unit : str
        SI unit of the parameter.
    """

    name: str
    matches: tuple[str, ...]
    lo: float
    hi: float
    count: int | None
    unit: str

    def grid(self) -> FloatArray:
        """The ``count`` grid values from lo to hi (ends included)."""
        if self.count is None:
            raise InputDataError(f"--vary {self.name}: no number of values (LO:HI:N)")
        return np.linspace(self.lo, self.hi, self.count)

    def start(self, design: Design) -> float | None:
        """The design's value of this variable (None when a glob's matches differ)."""
        if self.name in GEOMETRY_VARIABLES:
            return geometry_radius(design, self.name)
        try:
            return design.parameter(self.name)
        except DesignError:
            return None


#: Geometric variables: name -> the legs' point they scale radially.
GEOMETRY_VARIABLES = {"platform_radius": "platform_point", "base_radius": "base_point"}
#: Relative spread of the legs' radii within which they count as one radius.
RADIUS_TOLERANCE = 1e-9


def geometry_radius(design: Design, name: str) -> float | None:
    """The common radius [m] of geometric variable ``name`` on ``design``, or None when
    it does not apply (a leg without that point, radii that differ, a zero radius)."""
    key = GEOMETRY_VARIABLES[name]
    radii = []
    for leg in design.legs:
        point = getattr(getattr(leg, "spec", leg), key, None)
        if point is None:
            return None
        p = np.asarray(point, dtype=float).reshape(-1)
        if p.size not in (2, 3):
            return None
        radii.append(float(np.hypot(p[0], p[1])))
    if not radii or min(radii) <= 0 or max(radii) - min(radii) > RADIUS_TOLERANCE * max(radii):
        return None
    return float(np.mean(radii))


def geometry_names(design: Design) -> list[str]:
    """The geometric variables that apply to ``design``."""
    return [n for n in GEOMETRY_VARIABLES if geometry_radius(design, n) is not None]


def apply_values(design: Design, values: dict[str, float]) -> Design:
    """``design`` with ``values`` set (name or glob -> SI value): scalar parameters by
    :meth:`~ppm_stiffness.design.schema.Design.with_parameters`, the geometric
    variables by scaling the legs' points (module doc).

    Raises
    ------
    DesignError
        A value the design schema refuses, or a geometric variable that does not apply.
    """
    from ppm_stiffness.design.io import design_from_dict, design_to_dict

    geometry = {k: v for k, v in values.items() if k in GEOMETRY_VARIABLES}
    scalars = {k: v for k, v in values.items() if k not in GEOMETRY_VARIABLES}
    out = design.with_parameters(scalars) if scalars else design
    if not geometry:
        return out
    data = design_to_dict(out)
    for name, radius in geometry.items():
        current = geometry_radius(out, name)
        if current is None:
            raise DesignError(f"{name} does not apply to design {design.name!r}")
        if not (math.isfinite(radius) and radius > 0):
            raise DesignError(f"{name} = {radius:g}: a radius must be > 0 [m]")
        key = GEOMETRY_VARIABLES[name]
        for leg in data["legs"]:
            point = list(leg[key])
            point[0], point[1] = point[0] * radius / current, point[1] * radius / current
            leg[key] = point
    try:
        return design_from_dict(data)
    except DesignError as exc:
        raise DesignError(str(exc).replace("design: ", "parameters: ", 1)) from None


def parse_variable(text: str, design: Design, count: bool | None = None) -> Variable:
    """A variable from ``NAME=LO:HI`` or ``NAME=LO:HI:N``, checked against ``design``.

    Parameters
    ----------
    count : bool or None
        True: N is required; False: N is refused; None: either.

    Raises
    ------
    InputDataError
        Malformed text; LO or HI not finite; an empty (LO == HI) or inverted range; N
        below 2; a value the design schema refuses at either end of the range.
    DesignError
        An unknown parameter name, or a glob that matches nothing.
    """
    spec = "NAME=LO:HI" + (":N" if count else "[:N]" if count is None else "")
    name, sep, rest = text.partition("=")
    name = name.strip()
    if not sep or not name:
        raise InputDataError(f"--vary must be {spec}, got {text!r}")
    fields = rest.split(":")
    if len(fields) not in (2, 3) or (count is True and len(fields) != 3):
        raise InputDataError(f"--vary {name}: expected {spec}, got {text!r}")
    if count is False and len(fields) == 3:
        raise InputDataError(f"--vary {name}: give LO:HI here (no N), got {text!r}")
    try:
        lo, hi = float(fields[0]), float(fields[1])
    except ValueError:
        raise InputDataError(f"--vary {name}: LO and HI must be numbers, got {rest!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise InputDataError(f"--vary {name}: LO and HI must be finite, got {rest!r}")
    if lo == hi:
        raise InputDataError(f"--vary {name}: empty range (LO == HI == {lo:g})")
    if lo > hi:
        raise InputDataError(f"--vary {name}: inverted range (LO {lo:g} > HI {hi:g})")
    n: int | None = None
    if len(fields) == 3:
        try:
            n = int(fields[2])
        except ValueError:
            raise InputDataError(
                f"--vary {name}: N must be an integer, got {fields[2]!r}"
            ) from None
        if not 2 <= n <= MAX_VALUES:
            raise InputDataError(f"--vary {name}: N must be between 2 and {MAX_VALUES}, got {n}")
    if name in GEOMETRY_VARIABLES:
        if geometry_radius(design, name) is None:
            raise DesignError(
                f"--vary: {name} does not apply to design {design.name!r} (its legs' "
                f"{GEOMETRY_VARIABLES[name]}s are not on one circle about z); this "
                f"design's are {parameter_families(design)}"
            )
        matches: tuple[str, ...] = (name, *_point_radii(design, name))
        unit = "m"
    else:
        try:
            matches = tuple(design.addressed(name))  # with a linear actuator's twin
        except DesignError as exc:
            raise DesignError(
                f"--vary: {exc}; this design's are {parameter_families(design)}"
            ) from None
        unit = design.parameter_unit(name)
    for end, value in (("LO", lo), ("HI", hi)):
        try:
            apply_values(design, {name: value})
        except DesignError as exc:
            raise InputDataError(
                f"--vary {name}: {end} = {value:g} {unit} is refused by the design "
                f"({str(exc).removeprefix('parameters: ')})"
            ) from None
    return Variable(name=name, matches=matches, lo=lo, hi=hi, count=n, unit=unit)


def _point_radii(design: Design, name: str) -> list[str]:
    """The legs' point parameters geometric variable ``name`` sets (their ``.radius``
    with the ``.x`` and ``.y`` it moves), so that ``--vary platform_radius`` and
    ``--vary leg1.platform_point.radius`` are refused together."""
    try:
        return design.addressed(f"leg*.{GEOMETRY_VARIABLES[name]}.radius")
    except DesignError:  # a leg type whose points are not parameters
        return []


def parameter_families(design: Design) -> str:
    """The design's scalar parameter names with leg numbers as a glob (``leg*.``), once
    each: what ``--vary`` can take on this design (planar leg types have
    ``platform_radius``; spatial ones their link lengths, parts' stiffnesses, ...)."""
    import re

    names = dict.fromkeys(re.sub(r"^leg\d+\.", "leg*.", n) for n in design.scalar_parameter_names())
    return ", ".join(names)


def check_distinct(variables: Sequence[Variable]) -> None:
    """Refuse two variables that set the same parameter (InputDataError)."""
    shared = shared_parameter((v.name, v.matches) for v in variables)
    if shared is not None:
        first, name, m = shared
        raise InputDataError(
            f"--vary {name} and --vary {first} both set parameter {m!r}" + tied_note(m)
        )
    if not variables:
        raise InputDataError("give at least one --vary NAME=LO:HI")


def assignments(variables: Sequence[Variable], point: Sequence[float]) -> dict[str, float]:
    """``{variable name: value}`` for one point (one value per variable)."""
    return {v.name: float(x) for v, x in zip(variables, point, strict=True)}
