"""Tolerances of design parameters: the tolerance file, and samples drawn from it.

File format (TOML). Each table named by a parameter name or glob of
``calibrate --list-parameters`` (quoted when it holds ``*``) gives one of

- ``pm = 0.1`` or ``pm = "10%"``: uniform within +- the half-width (absolute, in the
  parameter's SI unit, or relative to its catalogue value);
- ``sigma = 5000.0`` or ``sigma = "5%"``: normal with this 1-sigma;

a relative value of 100 % or more is refused (it reaches zero: :data:`MAX_RELATIVE`),

and optionally ``tied = true``::

    ["leg*.guide.yaw"]
    sigma = "5%"          # each leg's guide drawn independently

    ["leg*.actuator.locked_stiffness"]
    pm = "10%"
    tied = true           # one draw for every leg (the same batch of actuators)

    [leg3.distal]         # nested tables are joined with dots
    young_modulus = { pm = 10e9 }

A glob means independent draws for each match, unless ``tied = true``: then one draw
moves every match (by the same relative amount for a ``%`` value, by the same offset
otherwise). Each independent draw is one *tolerance variable* ``z``: uniform on
[-1, 1] or standard normal, and a matched parameter takes ``p = p0 + width * z``.

Positivity. A draw that would make a parameter with a positive catalogue value (every
stiffness) <= 0 is redrawn from the same distribution restricted to the admissible
side (by inverse transform: the sample stays a quasi-random point); the number of
redrawn values is counted.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import shared_parameter, tied_note

#: Smallest relative tolerance refused (100 %): a half-width or a sigma of the whole
#: catalogue value reaches zero (a stiffness or a mass of 0 or less).
MAX_RELATIVE = 1.0

#: Keys of one tolerance entry.
ENTRY_KEYS = ("pm", "sigma", "tied")
#: Variance of the tolerance variable z of each distribution.
Z_VARIANCE = {"uniform": 1.0 / 3.0, "normal": 1.0}


@dataclass(frozen=True)
class ToleranceEntry:
    """One entry of the file, as written.

    Attributes
    ----------
    name : str
        Parameter name or glob.
    distribution : {"uniform", "normal"}
    value : float
        Half-width (uniform) or 1-sigma (normal): absolute [SI] or a fraction.
    relative : bool
        True for a ``%`` value (``value`` is then the fraction, 0.1 for 10 %).
    tied : bool
    """

    name: str
    distribution: str
    value: float
    relative: bool
    tied: bool = False


@dataclass(frozen=True)
class ToleranceVariable:
    """One independent draw and the parameters it moves.

    Attributes
    ----------
    label : str
        The parameter name (or the glob, when tied).
    distribution : {"uniform", "normal"}
    names : tuple of str
        The matched parameter names.
    nominal, width : ndarray (len(names),)
        Catalogue values and ``dp/dz`` [SI]: ``p = nominal + width * z``.
    """

    label: str
    distribution: str
    names: tuple[str, ...]
    nominal: FloatArray
    width: FloatArray

    @property
    def z_min(self) -> float:
        """Smallest admissible z (every positive parameter stays > 0); -inf if none."""
        bound = -math.inf
        for p0, w in zip(self.nominal, self.width, strict=True):
            if p0 > 0 and w > 0:
                bound = max(bound, -p0 / w)
        return bound


def _parse_value(key: str, raw: Any) -> tuple[float, bool]:
    if isinstance(raw, bool):
        raise InputDataError(f"tolerance file: {key} = {raw!r} is not a number or a percentage")
    if isinstance(raw, (int, float)):
        value, relative = float(raw), False
    elif isinstance(raw, str) and raw.strip().endswith("%"):
        try:
            value, relative = float(raw.strip()[:-1]) / 100.0, True
        except ValueError:
            raise InputDataError(
                f'tolerance file: {key} = {raw!r} is not a percentage (write "10%")'
            ) from None
    else:
        raise InputDataError(
            f'tolerance file: {key} = {raw!r} is not a number or a percentage such as "10%"'
        )
    if not math.isfinite(value) or value < 0:
        raise InputDataError(f"tolerance file: {key} = {raw!r} must be finite and >= 0")
    if relative and value >= MAX_RELATIVE:
        raise InputDataError(
            f"tolerance file: {key} = {raw!r}: a relative tolerance of 100 % or more "
            "reaches zero (a stiffness or a mass of 0 or less); relative tolerances are "
            f'below 100 % (did you mean "{value:g}%"?)'
        )
    return value, relative


def _entry(name: str, table: dict[str, Any]) -> ToleranceEntry:
    unknown = [k for k in table if k not in ENTRY_KEYS]
    if unknown:
        raise InputDataError(
            f"tolerance file: {name}.{unknown[0]}: unknown key (an entry has pm or sigma, "
            "and optionally tied)"
        )
    kinds = [k for k in ("pm", "sigma") if k in table]
    if len(kinds) != 1:
        raise InputDataError(f"tolerance file: {name}: give exactly one of pm and sigma")
    kind = kinds[0]
    value, relative = _parse_value(f"{name}.{kind}", table[kind])
    tied = table.get("tied", False)
    if not isinstance(tied, bool):
        raise InputDataError(f"tolerance file: {name}.tied = {tied!r} must be true or false")
    return ToleranceEntry(name, "uniform" if kind == "pm" else "normal", value, relative, tied)


def _flatten(prefix: str, data: dict[str, Any], out: list[ToleranceEntry]) -> None:
    for key, value in data.items():
        name = f"{prefix}.{key}" if prefix else key
        if not isinstance(value, dict):
            raise InputDataError(
                f"tolerance file: {name} = {value!r}: expected a table with pm or sigma"
            )
        if any(k in value for k in ENTRY_KEYS):
            out.append(_entry(name, value))
        else:
            _flatten(name, value, out)


def parse_tolerances(text: str, source: str = "tolerance file") -> list[ToleranceEntry]:
    """Entries of a tolerance file's text (module doc).

    Raises
    ------
    InputDataError
        Not TOML; an entry with neither or both of pm and sigma, an unknown key, a
        negative, non-finite or unparseable value (the key is named); no entry.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputDataError(f"{source}: not valid TOML ({exc})") from None
    entries: list[ToleranceEntry] = []
    _flatten("", data, entries)
    if not entries:
        raise InputDataError(f"{source}: no tolerance given")
    return entries


def read_tolerances(path: str | Path) -> list[ToleranceEntry]:
    """Entries of a tolerance file (:func:`parse_tolerances`)."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8-sig")  # a byte-order mark is not content
    except (OSError, UnicodeDecodeError) as exc:
        raise InputDataError(f"cannot read tolerance file {p}: {exc}") from None
    return parse_tolerances(text, str(p))


def tolerance_variables(design: Design, entries: list[ToleranceEntry]) -> list[ToleranceVariable]:
    """The independent draws of ``entries`` on ``design`` (globs expanded).

    Raises
    ------
    DesignError
        An unknown parameter name.
    InputDataError
        Two entries that address the same parameter.
    """
    # an actuator's two stiffnesses under q = 1 are one parameter (Design.addressed)
    shared = shared_parameter((e.name, design.addressed(e.name)) for e in entries)
    if shared is not None:
        first, name, n = shared
        raise InputDataError(
            f"tolerance file: {first!r} and {name!r} both address {n!r}" + tied_note(n)
        )
    out: list[ToleranceVariable] = []
    for e in entries:
        names = design.expand(e.name)
        nominal = np.array([design.parameter(n) for n in names])
        width = e.value * np.abs(nominal) if e.relative else np.full(len(names), e.value)
        groups = [list(range(len(names)))] if e.tied else [[k] for k in range(len(names))]
        for g in groups:
            label = e.name if e.tied else names[g[0]]
            out.append(
                ToleranceVariable(
                    label, e.distribution, tuple(names[k] for k in g), nominal[g], width[g]
                )
            )
    return out


def design_at(design: Design, variables: list[ToleranceVariable], z: FloatArray) -> Design:
    """The design with every variable at ``z`` (n_variables,)."""
    values: dict[str, float] = {}
    for v, zj in zip(variables, z, strict=True):
        for n, p0, w in zip(v.names, v.nominal, v.width, strict=True):
            values[n] = float(p0 + w * zj)
    return design.with_parameters(values)


def _cdf(distribution: str, z: FloatArray | float) -> Any:
    from scipy.stats import norm

    if distribution == "normal":
        return norm.cdf(z)
    return np.clip((np.asarray(z) + 1.0) / 2.0, 0.0, 1.0)


def _ppf(distribution: str, u: FloatArray) -> FloatArray:
    from scipy.stats import norm

    if distribution == "normal":
        return np.asarray(norm.ppf(u))
    return np.asarray(2.0 * u - 1.0)


def sample_variables(
    variables: list[ToleranceVariable], n: int, seed: int = 0
) -> tuple[FloatArray, int]:
    """``n`` scrambled Sobol points of the tolerance variables (quasi-Monte Carlo).

    Returns
    -------
    z : ndarray (n, n_variables)
    redrawn : int
        Values that would have made a positive parameter <= 0, redrawn (module doc).
    """
    from scipy.stats import qmc

    if n < 2:
        raise InputDataError(f"need at least 2 samples, got {n}")
    d = len(variables)
    sobol = qmc.Sobol(d, scramble=True, seed=seed)
    m = int(math.ceil(math.log2(n)))
    u = sobol.random_base2(m)[:n]  # a power of 2, the first n kept
    u = np.clip(u, 1e-12, 1 - 1e-12)
    z = np.empty_like(u)
    redrawn = 0
    for j, v in enumerate(variables):
        z_min = v.z_min
        f_min = float(_cdf(v.distribution, z_min)) if math.isfinite(z_min) else 0.0
        bad = u[:, j] <= f_min
        redrawn += int(bad.sum())
        # a value below the bound is redrawn from the admissible part, u' = u / F(z_min)
        uj = np.where(bad, f_min + (u[:, j] / max(f_min, 1e-300)) * (1.0 - f_min), u[:, j])
        z[:, j] = _ppf(v.distribution, np.clip(uj, 1e-12, 1 - 1e-12))
    return z, redrawn


__all__ = [
    "Z_VARIANCE",
    "ToleranceEntry",
    "ToleranceVariable",
    "design_at",
    "parse_tolerances",
    "read_tolerances",
    "sample_variables",
    "tolerance_variables",
]
