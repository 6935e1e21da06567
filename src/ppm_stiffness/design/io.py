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

A file without a ``schema`` key is read as the v1 format only if it has v1's layout
(an ``architecture`` key or shared ``actuator``, ``guide``, ``bearing``, ``proximal``,
``distal`` tables at the top) and none of schema 2's (a ``[parts]`` table, a leg
``type``): its shared tables become ``[parts]`` and each leg gets ``type = "PPR"``, and
a :class:`~ppm_stiffness.core.errors.DesignFormatWarning` says so in one line. Any
other file without ``schema`` is refused ("no 'schema' key: add `schema = 2`"), as is
an empty one ("file is empty"). A UTF-8 byte-order mark is skipped.

Validation (:mod:`.validation`) reports every error of a file at once, one a line,
in file order.
"""

from __future__ import annotations

import tomllib
import warnings
from dataclasses import replace
from importlib import resources
from pathlib import Path
from typing import Any

import tomli_w

from ppm_stiffness.core.errors import DesignError, DesignFormatWarning
from ppm_stiffness.design.schema import SCHEMA_VERSION, Design
from ppm_stiffness.design.validation import design_issues, format_issues, validate_design

#: Tables of a v1 file shared by every leg.
_V1_PARTS = ("actuator", "guide", "bearing", "proximal", "distal")


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


def _schema_2_layout(data: dict[str, Any]) -> list[str]:
    """What marks ``data`` as schema 2 (a ``[parts]`` table, a leg ``type``)."""
    signs = ["a [parts] table"] if "parts" in data else []
    legs = data.get("legs")
    if isinstance(legs, list) and any(isinstance(leg, dict) and "type" in leg for leg in legs):
        signs.append("legs with a 'type'")
    return signs


def _is_v1(data: dict[str, Any]) -> bool:
    """``data`` has the v1 layout (module doc)."""
    return "architecture" in data or any(isinstance(data.get(k), dict) for k in _V1_PARTS)


def design_from_dict(data: dict[str, Any], source: str = "design") -> Design:
    """Validate a nested dict (v2, or v1 with a warning) as a :class:`Design`.

    Raises
    ------
    DesignError
        Every error of ``data``, one a line, in file order, each naming its key
        (``leg2.guide.lateral``); or, alone, an empty input, a missing or unknown
        ``schema``.
    """
    if not data:
        raise DesignError(
            f"{source}: file is empty; a design needs `schema = 2` and at least 3 [[legs]]"
        )
    if "schema_version" in data and "schema" not in data:  # Design.model_dump()
        data = {("schema" if k == "schema_version" else k): v for k, v in data.items()}
    if "schema" not in data:
        signs = _schema_2_layout(data)
        if signs or not _is_v1(data):
            why = f" (it has {' and '.join(signs)}, as schema 2 files do)" if signs else ""
            raise DesignError(f"{source}: no 'schema' key: add `schema = 2`{why}")
        warnings.warn(
            f"{source}: design format v1 (no 'schema' key) is deprecated and was read "
            "as schema 2; add 'schema = 2' and put the shared part tables under "
            "[parts] (save_design writes it so)",
            DesignFormatWarning,
            stacklevel=2,
        )
        design, issues = design_issues(Design, migrate_v1(data, source))
        if design is None:  # named as the v1 file has them: its shared tables at the top
            issues = [replace(i, key=i.key.removeprefix("parts.")) for i in issues]
            raise DesignError(format_issues(source, issues))
        return design
    if type(data["schema"]) is not int or data["schema"] != SCHEMA_VERSION:
        raise DesignError(
            f"{source}: key 'schema': this version reads schema {SCHEMA_VERSION}, "
            f"got {data['schema']!r}"
        )
    return validate_design(Design, data, source)


def load_design(path: str | Path) -> Design:
    """Read and validate a TOML design file."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8-sig")  # a byte-order mark is not content
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
    if {type(leg).TASK_COORDINATES for leg in design.legs} == {design.task_coordinates}:
        del data["task_coordinates"]  # what the legs state: no need to write it
    workspace = data.get("workspace", {})
    for key in ("centre_z", "rx", "ry"):  # a planar file stays as it was
        if workspace.get(key) == 0.0:
            del workspace[key]
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
