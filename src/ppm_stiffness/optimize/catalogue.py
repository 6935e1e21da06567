"""Catalogue choices: a discrete design variable that picks one entry of a catalogue
for a part (``--choose PART=FILE.toml:TABLE``).

A catalogue is a TOML file of tables of entries; each entry has a ``name``, optionally
a ``source`` and a ``price`` (kept, not used), and the part's keys with their SI values
(``young_modulus``, ``area``, ``mass``, ... for a link; ``locked_stiffness``,
``carriage_mass``, ... for an actuator)::

    [[rods]]
    name = "steel round bar 8 mm x 160 mm"
    source = "computed: solid round bar ..."
    young_modulus = 210e9
    area = 5.0265e-5
    ...

PART is a part's parameter prefix as ``calibrate --list-parameters`` prints it, a name
or a glob (``leg*.distal``): choosing entry i sets ``PART.KEY`` to the entry's value for
every KEY of the entry (:meth:`Choice.values`), on every match of the glob at once.
Every entry is checked against the design when the choice is parsed (:func:`parse_choice`):
an unknown key or a value the design schema refuses is an error then, not during the
search.

In the optimiser a choice is an integer variable, the entry's index (0-based, in file
order): :mod:`ppm_stiffness.optimize.pareto` rounds it (pymoo's population stays on
integers).
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design

#: Keys of an entry that are not parameters of the part.
INFORMATION_KEYS = ("name", "source", "price")
#: Relative difference within which a design's value equals an entry's.
SAME_VALUE = 1e-9


@dataclass(frozen=True)
class Choice:
    """A discrete variable: one entry of a catalogue table for a part.

    Attributes
    ----------
    name : str
        The part as given (a parameter prefix or a glob, ``leg*.distal``).
    source : str
        ``FILE:TABLE`` as given.
    entries : tuple of (str, dict)
        Each entry's name and its parameter values (``KEY`` -> SI value).
    """

    name: str
    source: str
    entries: tuple[tuple[str, dict[str, float]], ...]

    def values(self, index: int) -> dict[str, float]:
        """``{PART.KEY: value}`` of entry ``index``."""
        return {f"{self.name}.{k}": v for k, v in self.entries[index][1].items()}

    def entry_name(self, index: int) -> str:
        return self.entries[index][0]

    def start(self, design: Design) -> int | None:
        """The index of the entry whose every value the design has (the first such),
        None when none matches or a glob's matches differ."""
        for i, (_, values) in enumerate(self.entries):
            try:
                current = {k: design.parameter(f"{self.name}.{k}") for k in values}
            except DesignError:
                return None
            if all(
                abs(current[k] - v) <= SAME_VALUE * max(abs(v), 1e-300) for k, v in values.items()
            ):
                return i
        return None


def load_table(path: str | Path, table: str) -> list[dict[str, object]]:
    """The entries of ``table`` in catalogue ``path`` (InputDataError naming the file
    and what is wrong)."""
    p = Path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputDataError(f"catalogue {path}: cannot read it ({exc.strerror})") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputDataError(f"catalogue {path}: not TOML ({exc})") from None
    entries = data.get(table)
    if not isinstance(entries, list) or not entries:
        tables = ", ".join(k for k, v in data.items() if isinstance(v, list)) or "none"
        raise InputDataError(
            f"catalogue {path}: no table [[{table}]] of entries; its tables: {tables}"
        )
    return entries


def _entry(path: str, table: str, i: int, raw: object) -> tuple[str, dict[str, float]]:
    where = f"catalogue {path}: [[{table}]] entry {i + 1}"
    if not isinstance(raw, dict) or not isinstance(raw.get("name"), str):
        raise InputDataError(f'{where}: needs a name = "..."')
    values: dict[str, float] = {}
    for key, value in raw.items():
        if key in INFORMATION_KEYS:
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputDataError(f"{where} ({raw['name']}): {key} must be a number (SI)")
        if not math.isfinite(float(value)):
            raise InputDataError(f"{where} ({raw['name']}): {key} must be finite")
        values[key] = float(value)
    if not values:
        raise InputDataError(f"{where} ({raw['name']}): no part values")
    return str(raw["name"]), values


def parse_choice(text: str, design: Design) -> Choice:
    """A choice from ``PART=FILE:TABLE``, every entry checked against ``design``.

    Raises
    ------
    InputDataError
        Malformed text, an unreadable catalogue, a missing table, an entry without a
        name or with a non-numeric value, a key that is not a parameter of the part, a
        value the design refuses, or fewer than two entries.
    """
    from ppm_stiffness.optimize.variables import apply_values

    part, sep, rest = text.partition("=")
    part = part.strip()
    path, colon, table = rest.rpartition(":")
    if not sep or not part or not colon or not path or not table:
        raise InputDataError(f"--choose must be PART=FILE.toml:TABLE, got {text!r}")
    raw = load_table(path, table)
    entries = tuple(_entry(path, table, i, r) for i, r in enumerate(raw))
    if len(entries) < 2:
        raise InputDataError(f"--choose {part}: [[{table}]] has one entry: nothing to choose")
    choice = Choice(name=part, source=f"{path}:{table}", entries=entries)
    for i, (name, _) in enumerate(entries):
        for key in choice.values(i):
            try:
                design.addressed(key)
            except DesignError:
                raise InputDataError(
                    f"--choose {part}: entry {name!r} sets {key}, not a parameter of design "
                    f"{design.name!r} (see calibrate --list-parameters)"
                ) from None
        try:
            apply_values(design, choice.values(i))
        except DesignError as exc:
            raise InputDataError(
                f"--choose {part}: entry {name!r} is refused by the design "
                f"({str(exc).removeprefix('parameters: ')})"
            ) from None
    return choice


def choice_values(choices: Sequence[Choice], indices: Sequence[float]) -> dict[str, float]:
    """The parameter values of one entry per choice (indices rounded)."""
    out: dict[str, float] = {}
    for c, x in zip(choices, indices, strict=True):
        out.update(c.values(int(round(x))))
    return out
