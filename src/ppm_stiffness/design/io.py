"""Design files: TOML in, TOML out, with the v1 format migrated on reading.

Schema v2 (``schema = 2``)::

    schema = 2
    name = "..."
    tool_point = [0.0, 0.0, 0.0]          # optional, m, platform frame
    [workspace]                           # optional: centre_x, centre_y [m], phi [rad]
    [parts.guide]                         # optional: parts every leg gets unless it
    ...                                   #   gives its own (key by key)
    [[legs]]
    type = "PPR"                          # a leg type (ppm_stiffness.legs.types)
    ...                                   # its geometry and parts

A v1 file (no ``schema`` key; one ``architecture = "PPR"`` and shared ``actuator``,
``guide``, ``bearing``, ``proximal``, ``distal`` tables) still loads: its shared tables
become ``[parts]`` and each leg gets ``type = "PPR"``. A
:class:`~ppm_stiffness.core.errors.DesignFormatWarning` says so in one line.
"""

from __future__ import annotations

import copy
import difflib
import re
import tomllib
import warnings
from importlib import resources
from pathlib import Path
from typing import Any

import tomli_w
from pydantic import ValidationError

from ppm_stiffness.core.errors import DesignError, DesignFormatWarning
from ppm_stiffness.design.schema import SCHEMA_VERSION, Design
from ppm_stiffness.legs.registry import leg_types

#: Tables of a v1 file shared by every leg.
_V1_PARTS = ("actuator", "guide", "bearing", "proximal", "distal")


def _format_location(loc: tuple[Any, ...]) -> str:
    out: list[str] = []
    for i, part in enumerate(loc):
        if isinstance(part, int) and i > 0 and loc[i - 1] == "legs":
            out[-1] = f"leg{part + 1}"
        elif (
            i > 1 and isinstance(loc[i - 1], int) and loc[i - 2] == "legs" and (part in leg_types())
        ):
            continue  # the discriminator's tag pydantic puts in the location
        else:
            out.append(str(part))
    return ".".join(out)


def migrate_v1(data: dict[str, Any], source: str) -> dict[str, Any]:
    """A v1 design dict as a v2 one (module doc)."""
    arch = data.get("architecture", "PPR")
    if arch != "PPR":
        raise DesignError(f"{source}: key 'architecture': a v1 design file is 'PPR', got {arch!r}")
    out = {k: v for k, v in data.items() if k not in _V1_PARTS and k != "architecture"}
    out["schema"] = SCHEMA_VERSION
    out["parts"] = {k: data[k] for k in _V1_PARTS if k in data}
    legs = data.get("legs", [])
    if isinstance(legs, list):
        out["legs"] = [{"type": "PPR", **leg} if isinstance(leg, dict) else leg for leg in legs]
    return out


def _merge(base: Any, override: Any) -> Any:
    if isinstance(base, dict) and isinstance(override, dict):
        out = dict(base)
        for k, v in override.items():
            out[k] = _merge(base.get(k), v) if k in base else v
        return out
    return override


def apply_parts(data: dict[str, Any], source: str) -> dict[str, Any]:
    """Give every leg the ``[parts]`` it declares but does not set itself."""
    out = {k: v for k, v in data.items() if k != "parts"}
    parts = data.get("parts", {})
    if not isinstance(parts, dict):
        raise DesignError(f"{source}: key 'parts': expected a table")
    legs = data.get("legs")
    if not isinstance(legs, list):
        return out
    types = leg_types()
    used: set[str] = set()
    new_legs = []
    for i, leg in enumerate(legs, start=1):
        if not isinstance(leg, dict):
            new_legs.append(leg)
            continue
        kind = leg.get("type")
        if kind not in types:
            raise DesignError(
                f"{source}: key 'leg{i}.type': "
                + ("missing" if kind is None else f"unknown leg type {kind!r}")
                + f"; expected one of {', '.join(sorted(types))}"
            )
        fields = types[kind].model_fields
        merged = copy.deepcopy(leg)
        for name, value in parts.items():
            if name in fields:
                used.add(name)
                merged[name] = _merge(value, leg[name]) if name in leg else copy.deepcopy(value)
        new_legs.append(merged)
    unused = sorted(set(parts) - used)
    if unused:
        raise DesignError(
            f"{source}: key 'parts.{unused[0]}': no leg of this design has a part "
            f"named {unused[0]!r}"
        )
    out["legs"] = new_legs
    return out


def design_from_dict(data: dict[str, Any], source: str = "design") -> Design:
    """Validate a nested dict (v2, or v1 with a warning) as a :class:`Design`.

    Errors name the offending key (``leg2.guide.lateral``).
    """
    if "schema_version" in data and "schema" not in data:  # Design.model_dump()
        data = {("schema" if k == "schema_version" else k): v for k, v in data.items()}
    if "schema" not in data:
        warnings.warn(
            f"{source}: design format v1 (no 'schema' key) is deprecated and was read "
            "as schema 2; add 'schema = 2' and put the shared part tables under "
            "[parts] (save_design writes it so)",
            DesignFormatWarning,
            stacklevel=2,
        )
        data = migrate_v1(data, source)
    elif data["schema"] != SCHEMA_VERSION:
        raise DesignError(
            f"{source}: key 'schema': this version reads schema {SCHEMA_VERSION}, "
            f"got {data['schema']!r}"
        )
    data = apply_parts(data, source)
    try:
        return Design.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        loc = tuple(first["loc"])
        key = _format_location(loc) or "(top level)"
        msg = str(first["msg"]).removeprefix("Value error, ")
        if first["type"] == "extra_forbidden":
            msg = "unknown key" + _nearest_key(data, loc)
        named = re.match(r"(\w+) = ", msg)  # a validator naming the offending field
        if named and first["type"] == "value_error":
            key = f"{key}.{named.group(1)}"
        raise DesignError(f"{source}: key '{key}': {msg}") from None


def _nearest_key(data: dict[str, Any], loc: tuple[Any, ...]) -> str:
    """``"; did you mean 'roll'?"`` for a misspelt key at ``loc`` (or a list of keys)."""
    model: Any = Design
    for i, part in enumerate(loc[:-1]):
        if isinstance(part, int):
            continue
        if i > 0 and loc[i - 1] != "legs" and part in leg_types() and isinstance(loc[i - 1], int):
            model = leg_types()[part]
            continue
        field = model.model_fields.get(part)
        if field is None:
            return ""
        if part == "legs":
            kind = data["legs"][loc[i + 1]].get("type") if isinstance(loc[i + 1], int) else None
            model = leg_types().get(str(kind), model)
            continue
        ann = field.annotation
        candidates = [a for a in getattr(ann, "__args__", (ann,)) if isinstance(a, type)]
        model = next((a for a in candidates if hasattr(a, "model_fields")), None)
        if model is None:
            return ""
    valid = list(model.model_fields)
    close = difflib.get_close_matches(str(loc[-1]), valid, n=1)
    if close:
        return f"; did you mean '{close[0]}'?"
    return f"; valid keys: {', '.join(valid)}"


def load_design(path: str | Path) -> Design:
    """Read and validate a TOML design file."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise DesignError(f"design file not found: {p}") from None
    except UnicodeDecodeError:
        raise DesignError(f"{p}: not a UTF-8 text file") from None
    except OSError as exc:
        raise DesignError(f"cannot read design file {p}: {exc.strerror}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise DesignError(f"{p}: not valid TOML: {exc}") from None
    return design_from_dict(data, source=str(p))


def design_to_dict(design: Design) -> dict[str, Any]:
    """The design as a v2 dict; parts equal in every leg go to ``[parts]``."""
    data = design.model_dump(mode="json", by_alias=True, exclude_none=True)
    legs: list[dict[str, Any]] = data.pop("legs")
    shared: dict[str, Any] = {}
    for name, value in legs[0].items():
        if isinstance(value, dict) and all(leg.get(name) == value for leg in legs):
            shared[name] = value
    for leg in legs:
        for name in shared:
            del leg[name]
    out: dict[str, Any] = {"schema": data.pop("schema"), "name": data.pop("name")}
    out.update(data)
    if shared:
        out["parts"] = shared
    out["legs"] = legs
    return out


def dump_design(design: Design) -> str:
    """The design as TOML text (round-trips through :func:`load_design`)."""
    header = "# ppm-stiffness design file. SI units: m, rad, Pa, m^2, m^4, N/m, N·m/rad.\n"
    return header + tomli_w.dumps(design_to_dict(design))


def save_design(design: Design, path: str | Path) -> None:
    """Write the design as a TOML file."""
    Path(path).write_text(dump_design(design), encoding="utf-8")


def default_design() -> Design:
    """The built-in design: the paper's 3-PPR, carriage layout calibrated on (22)."""
    text = resources.files("ppm_stiffness").joinpath("data/paper_3ppr.toml").read_text("utf-8")
    return design_from_dict(tomllib.loads(text), source="built-in design")
