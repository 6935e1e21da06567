"""A design dict (schema 2) validated as a model, with every error of the input reported
at once, each under the key the user wrote.

Schema 2's ``[parts]`` table is applied here (:func:`apply_parts`): every leg gets the
parts it declares but does not set, key by key. An error in a value that came from
``[parts]`` is reported once, as ``parts.guide.roll``, not once per leg.

:func:`validate_design` raises one :class:`~ppm_stiffness.core.errors.DesignError`
listing every error, one a line, ordered by position in the file (the order of the
keys as written), each line ``"<source>: key '<dotted key>': <what is wrong>"``; the
same error in every leg is one line, keyed with the glob ``leg*``. With
several errors the first line ends with ``(1 of N errors; the others follow, one a
line)``, so that the first line alone still reads as one complete error (the CLI's
one-line convention). A misspelt key is named with its closest valid key, and the
"Field required" it causes for that key is not reported on top of it.

This module knows the root model only as an argument (``Design``), so that the schema
can validate its own copies (:meth:`Design.with_parameters`) without an import cycle.
"""

from __future__ import annotations

import copy
import difflib
import re
import typing
from dataclasses import dataclass
from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError

from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.legs.parts import value_kind
from ppm_stiffness.legs.registry import leg_types

M = TypeVar("M", bound=BaseModel)

#: A path into a design dict: table keys and list indices (``("legs", 0, "guide")``).
Path = tuple[str | int, ...]

#: What pydantic's type errors expect, in TOML's words.
_EXPECTED = {
    "model_type": "a table",
    "model_attributes_type": "a table",
    "dict_type": "a table",
    "tuple_type": "a list",
    "list_type": "a list",
    "string_type": "a string",
    "int_type": "an integer",
}


@dataclass(frozen=True)
class Issue:
    """One error of a design input.

    Attributes
    ----------
    position : tuple of int
        Where it is in the file: the index of each key (in the order written) or list
        item along its path; a missing key sorts after its table's keys.
    key : str
        Dotted key as written, legs from 1 (``leg2.guide.lateral``, ``parts.guide.roll``).
    message : str
        What is wrong and what is valid.
    """

    position: tuple[int, ...]
    key: str
    message: str


def validate_design(root: type[M], data: dict[str, Any], source: str) -> M:
    """``data`` (schema 2, ``[parts]`` allowed) validated as ``root``.

    Raises
    ------
    DesignError
        Listing every error of ``data`` (module doc: one a line, in file order).
    """
    model, issues = design_issues(root, data)
    if model is None:
        raise DesignError(format_issues(source, issues))
    return model


def design_issues(root: type[M], data: dict[str, Any]) -> tuple[M | None, list[Issue]]:
    """Validate ``data`` as ``root``: the model, or None and every error, in file order."""
    parts = apply_parts(data)
    issues = list(parts.issues)
    try:
        context = getattr(root, "validation_context", None)
        model = root.model_validate(
            parts.merged, context=None if context is None else context(parts.merged)
        )
    except ValidationError as exc:
        issues += _issues_of(exc, root, data, parts)
    else:
        if not issues:
            return model, []
    legs = data.get("legs")
    return None, _tidy(issues, len(legs) if isinstance(legs, list) else 0)


def format_issues(source: str, issues: list[Issue]) -> str:
    """The message of a :class:`DesignError` listing ``issues`` (module doc)."""
    lines = [f"{source}: key '{issue.key}': {issue.message}" for issue in issues]
    if len(lines) > 1:
        lines[0] += f" (1 of {len(lines)} errors; the others follow, one a line)"
    return "\n".join(lines)


@dataclass(frozen=True)
class PartsApplied:
    """The result of :func:`apply_parts`.

    Attributes
    ----------
    merged : dict
        The design dict without ``parts``, its legs completed (key by key).
    issues : list of Issue
        A leg without a known ``type``, ``parts`` not a table, a part no leg has.
    bad_legs : set of int
        Indices of the legs without a known type (their other errors would only
        repeat it).
    meant : set of str
        Part names that a misspelt ``[parts]`` table was likely meant to give (its
        legs' "Field required" for them would only repeat the misspelling).
    """

    merged: dict[str, Any]
    issues: list[Issue]
    bad_legs: set[int]
    meant: set[str]
    origin: list[int] | None = None

    def written_leg(self, index: int) -> int:
        """The index in the file of merged leg ``index`` (a pattern's copies are its
        written leg's)."""
        return index if self.origin is None or index >= len(self.origin) else self.origin[index]


def apply_parts(data: dict[str, Any]) -> PartsApplied:
    """Give every leg the ``[parts]`` it declares but does not set itself."""
    merged = {k: v for k, v in data.items() if k != "parts"}
    parts = data.get("parts", {})
    issues: list[Issue] = []
    bad_legs: set[int] = set()
    parts_is_table = isinstance(parts, dict)
    if not parts_is_table:
        issues.append(_issue(data, ("parts",), f"expected a table, got {value_kind(parts)}"))
        parts = {}
    legs = data.get("legs")
    meant: set[str] = set()
    if not isinstance(legs, list):
        return PartsApplied(merged, issues, bad_legs, meant)
    types = leg_types()
    used: set[str] = set()
    part_names: set[str] = set()  # the parts the typed legs have
    typed = 0
    new_legs = []
    origin: list[int] = []
    for i, leg in enumerate(legs):
        kind = leg.get("type") if isinstance(leg, dict) else None
        if not isinstance(leg, dict) or not isinstance(kind, str) or kind not in types:
            if isinstance(leg, dict):  # (a leg that is not a table: pydantic says so)
                what = "missing" if kind is None else f"unknown leg type {kind!r}"
                message = f"{what}; expected one of {', '.join(sorted(types))}"
                issues.append(_issue(data, ("legs", i, "type"), message))
                bad_legs.add(i)
            new_legs.append(leg)
            origin.append(i)
            continue
        typed += 1
        fields = types[kind].model_fields
        part_names.update(n for n, f in fields.items() if _is_part(f.annotation))
        out = copy.deepcopy(leg) if parts else leg
        for name, value in parts.items():
            if name in fields:
                used.add(name)
                out[name] = _merge(value, leg[name]) if name in leg else copy.deepcopy(value)
        try:
            copies = types[kind].pattern_copies(out)
        except ValueError as exc:
            issues.append(_issue(data, ("legs", i, "pattern"), str(exc)))
            copies = [{k: v for k, v in out.items() if k != "pattern"}]
        new_legs += copies
        origin += [i] * len(copies)
        continue
    if typed and typed == len(legs):  # else "no leg has it" may not be true
        for name in parts:
            if name not in used:
                hint = _suggestion(name, sorted(part_names), listing=False)
                message = f"no leg of this design has a part named {name!r}{hint}"
                issues.append(_issue(data, ("parts", name), message))
                meant.update(re.findall(r"did you mean '(\w+)'", hint))
    if not parts_is_table:  # the legs' missing parts were likely in it
        meant.update(part_names)
    merged["legs"] = new_legs
    return PartsApplied(merged, issues, {origin.index(i) for i in bad_legs}, meant, origin)


def _is_part(annotation: Any) -> bool:
    """A field holds a part (a table of its own), not a number or a list."""
    args = typing.get_args(annotation) or (annotation,)
    return any(isinstance(a, type) and issubclass(a, BaseModel) for a in args)


def _merge(base: Any, override: Any) -> Any:
    if isinstance(base, dict) and isinstance(override, dict):
        out = dict(base)
        for k, v in override.items():
            out[k] = _merge(base.get(k), v) if k in base else v
        return out
    return override


# -- pydantic's errors in the file's terms ---------------------------------------------


@dataclass(frozen=True)
class _Raw:
    """A pydantic error on its way to an :class:`Issue`."""

    path: Path
    kind: str
    message: str


def _issues_of(
    exc: ValidationError, root: type[BaseModel], data: dict[str, Any], parts: PartsApplied
) -> list[Issue]:
    merged = parts.merged
    raws: list[_Raw] = []
    for error in exc.errors():
        path = _path(tuple(error["loc"]))
        if len(path) >= 2 and path[0] == "legs" and path[1] in parts.bad_legs:
            continue  # its unknown type is reported already
        kind = str(error["type"])
        message = str(error["msg"]).removeprefix("Value error, ")
        model = _model_at(root, merged, path)
        if kind == "value_error" and model is not None:
            named = re.match(r"(\w+)(?: = |: | must )", message)  # a validator naming a field
            if named and named.group(1) in _field_names(model) and path[-1:] != (named[1],):
                path = (*path, named.group(1))
            message = message.removeprefix(f"{path[-1]}: ") if path else message
        elif kind == "extra_forbidden":
            parent = _model_at(root, merged, path[:-1])
            valid = _field_names(parent) + (["parts"] if path[:-1] == () else [])
            message = "unknown key" + _suggestion(str(path[-1]), valid, listing=True)
        elif kind in _EXPECTED:
            message = f"expected {_EXPECTED[kind]}, got {value_kind(error['input'])}"
        elif kind == "too_short" and path == ("legs",):
            message = f"a design needs at least 3 legs ([[legs]] tables), got {len(merged['legs'])}"
        if len(path) >= 2 and path[0] == "legs" and isinstance(path[1], int):
            path = ("legs", parts.written_leg(path[1]), *path[2:])  # a pattern's copy
        raws.append(_Raw(_from_parts(data, path), kind, message))
    raws = _without_consequences(raws, data, parts.meant)
    return [_issue(data, raw.path, raw.message) for raw in raws]


def _path(loc: tuple[Any, ...]) -> Path:
    """A pydantic location as a path into the dict (the legs' type tags dropped)."""
    out: list[str | int] = []
    for i, part in enumerate(loc):
        if i >= 2 and loc[i - 2] == "legs" and isinstance(loc[i - 1], int):
            if part in leg_types():
                continue  # the discriminator's tag pydantic puts in the location
        out.append(part if isinstance(part, int) else str(part))
    return tuple(out)


def _from_parts(data: dict[str, Any], path: Path) -> Path:
    """``parts.<part>.<key>`` for a leg's value that came from ``[parts]`` (or is missing
    there), else ``path``."""
    parts = data.get("parts")
    if len(path) < 3 or path[0] != "legs" or not isinstance(parts, dict):
        return path
    i, part = path[1], path[2]
    legs = data.get("legs")
    if not (isinstance(i, int) and isinstance(legs, list) and i < len(legs)):
        return path
    leg = legs[i]
    if not isinstance(leg, dict) or not isinstance(part, str) or part not in parts:
        return path
    own = leg.get(part)
    if own is None or (len(path) > 3 and isinstance(own, dict) and path[3] not in own):
        return ("parts", *path[2:])
    return path


def _without_consequences(
    raws: list[_Raw], data: dict[str, Any], meant_parts: set[str]
) -> list[_Raw]:
    """Drop duplicates, and the "Field required" of a key that is present misspelt: in
    its own table, as a misspelt ``[parts.<part>]`` (``meant_parts``), or in a
    misspelt ``[parts]``."""
    meant: set[Path] = set()
    parts = set(meant_parts)
    for raw in raws:
        hint = re.search(r"did you mean '(\w+)'\?$", raw.message)
        if raw.kind == "extra_forbidden" and hint:
            meant.add((*raw.path[:-1], hint.group(1)))
            value = data.get(str(raw.path[0]))
            if raw.path[:-1] == () and hint.group(1) == "parts" and isinstance(value, dict):
                parts.update(value)

    def consequence(path: Path) -> bool:
        return path in meant or (len(path) == 3 and path[0] == "legs" and path[2] in parts)

    seen: set[tuple[Path, str]] = set()
    out = []
    for raw in raws:
        if (raw.kind == "missing" and consequence(raw.path)) or (raw.path, raw.message) in seen:
            continue
        seen.add((raw.path, raw.message))
        out.append(raw)
    return out


def _model_at(root: type[BaseModel], merged: Any, path: Path) -> type[BaseModel] | None:
    """The model class that validates the table at ``path`` (None: not a table)."""
    model: type[BaseModel] | None = root
    node: Any = merged
    for i, step in enumerate(path):
        if isinstance(step, int):
            node = node[step] if isinstance(node, list) and 0 <= step < len(node) else None
            if i > 0 and path[i - 1] == "legs" and isinstance(node, dict):
                model = leg_types().get(str(node.get("type")))
            else:
                model = None
            continue
        if model is None:
            return None
        field = _fields(model).get(step)
        node = node.get(step) if isinstance(node, dict) else None
        if field is None:
            return None
        if step == "legs":
            continue  # the next step (an index) picks the leg's type
        args = typing.get_args(field.annotation) or (field.annotation,)
        model = next((a for a in args if isinstance(a, type) and issubclass(a, BaseModel)), None)
    return model


def _fields(model: type[BaseModel]) -> dict[str, Any]:
    """Fields by the key a file uses (the alias where there is one)."""
    return {(f.alias or name): f for name, f in model.model_fields.items()}


def _field_names(model: type[BaseModel] | None) -> list[str]:
    return [] if model is None else list(_fields(model))


def _suggestion(key: str, valid: list[str], *, listing: bool) -> str:
    """``"; did you mean 'roll'?"``, else (``listing``) the valid keys, else ""."""
    close = difflib.get_close_matches(key, valid, n=1)
    if close:
        return f"; did you mean '{close[0]}'?"
    return f"; valid keys: {', '.join(valid)}" if listing and valid else ""


def _issue(data: dict[str, Any], path: Path, message: str) -> Issue:
    return Issue(_position(data, path), _key(path) or "(top level)", message)


def _key(path: Path) -> str:
    out: list[str] = []
    for i, step in enumerate(path):
        if isinstance(step, int) and i > 0 and path[i - 1] == "legs":
            out[-1] = f"leg{step + 1}"
        else:
            out.append(str(step))
    return ".".join(out)


def _position(data: Any, path: Path) -> tuple[int, ...]:
    """Index of each step of ``path`` in the file's order; a missing key after the rest."""
    out: list[int] = []
    node: Any = data
    for step in path:
        if isinstance(node, dict):
            keys = list(node)
            out.append(keys.index(step) if step in keys else len(keys))
            node = node.get(step) if isinstance(step, str) else None
        elif isinstance(node, list) and isinstance(step, int):
            out.append(step)
            node = node[step] if 0 <= step < len(node) else None
        else:
            break
    return tuple(out)


def _tidy(issues: list[Issue], n_legs: int) -> list[Issue]:
    """Issues without repeats, in file order; the same error in every leg is one issue,
    named with the glob ``leg*`` (``leg*.platform_radius``): the same message, or the
    same value refused with the same hint but leg-dependent figures
    (:func:`_same_slip`), given once with the first leg's figures."""
    unique = list(dict.fromkeys(issues))
    groups: dict[tuple[str, str], list[Issue]] = {}
    for issue in unique:
        glob = re.sub(r"^leg\d+(?=\.|$)", "leg*", issue.key)
        groups.setdefault((glob, _same_slip(issue.message)), []).append(issue)
    out = []
    for (glob, _), group in groups.items():
        if n_legs > 1 and glob != group[0].key and len(group) == n_legs:
            message = group[0].message
            if any(issue.message != message for issue in group):
                message += f" (figures of {group[0].key}; every leg alike)"
            out.append(Issue(group[0].position, glob, message))
        else:
            out += group
    return sorted(out, key=lambda issue: issue.position)


def _same_slip(message: str) -> str:
    """What makes two legs' errors the same error: the key and value the message starts
    with (``"proximal.mass = 85.05"``) and its hint (``"did you mean 0.08505 (g)?"``),
    when it has one; else the whole message."""
    head = message.split(": ", 1)[0]
    hint = re.search(r"did you mean [^?]*\?", message)
    return f"{head} | {hint.group(0)}" if hint and " = " in head else message
