"""Design variables of a sweep or an optimisation: ``NAME=LO:HI[:N]``.

NAME is a parameter name exactly as ``ppm-stiffness calibrate --list-parameters``
prints it (``leg1.platform_radius``), or a glob (``leg*.platform_radius``) whose
matches vary together as one variable. LO and HI are SI values (the parameter's unit,
:meth:`~ppm_stiffness.design.schema.Design.parameter_unit`), LO < HI; N (sweeps on a
grid) is the number of values, ends included, at least 2.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design

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
        try:
            return design.parameter(self.name)
        except DesignError:
            return None


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
    try:
        matches = tuple(design.expand(name))
    except DesignError as exc:
        raise DesignError(
            f"--vary: {exc}; this design's are {parameter_families(design)}"
        ) from None
    unit = design.parameter_unit(name)
    for end, value in (("LO", lo), ("HI", hi)):
        try:
            design.with_parameters({name: value})
        except DesignError as exc:
            raise InputDataError(
                f"--vary {name}: {end} = {value:g} {unit} is refused by the design "
                f"({str(exc).removeprefix('parameters: ')})"
            ) from None
    return Variable(name=name, matches=matches, lo=lo, hi=hi, count=n, unit=unit)


def parameter_families(design: Design) -> str:
    """The design's scalar parameter names with leg numbers as a glob (``leg*.``), once
    each: what ``--vary`` can take on this design (planar leg types have
    ``platform_radius``; spatial ones their link lengths, parts' stiffnesses, ...)."""
    import re

    names = dict.fromkeys(re.sub(r"^leg\d+\.", "leg*.", n) for n in design.scalar_parameter_names())
    return ", ".join(names)


def check_distinct(variables: Sequence[Variable]) -> None:
    """Refuse two variables that set the same parameter (InputDataError)."""
    seen: dict[str, str] = {}
    for v in variables:
        for m in v.matches:
            if m in seen:
                raise InputDataError(
                    f"--vary {v.name} and --vary {seen[m]} both set parameter {m!r}"
                )
            seen[m] = v.name
    if not variables:
        raise InputDataError("give at least one --vary NAME=LO:HI")


def assignments(variables: Sequence[Variable], point: Sequence[float]) -> dict[str, float]:
    """``{variable name: value}`` for one point (one value per variable)."""
    return {v.name: float(x) for v, x in zip(variables, point, strict=True)}
