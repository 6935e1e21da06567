"""The design schema (v2): a manipulator as a list of legs, each its own joint chain
and parts, plus the workspace centre and an optional tool point. SI throughout.

Every scalar has a dotted parameter name: ``leg2.platform_radius``,
``leg1.guide.lateral``, ``workspace.centre_x``; legs are numbered from 1. A glob such
as ``leg*.guide.lateral`` names the same part in every leg that has it
(:meth:`Design.expand`). The leg types come from :mod:`ppm_stiffness.legs.registry`;
this module knows none of them by name.
"""

from __future__ import annotations

import fnmatch
import math
from collections import Counter
from collections.abc import Iterable
from typing import Annotated, Any, Literal, Union

import numpy as np
from pydantic import (
    AliasChoices,
    BaseModel,
    Field,
    ValidationInfo,
    field_validator,
    model_validator,
)

from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.core.pose import POSE_COORDINATES
from ppm_stiffness.design.axis_globs import AxisOfLeg, copies_of_first
from ppm_stiffness.design.platform import PLATFORM_UNITS, PlatformModel
from ppm_stiffness.design.points import (
    AXIS_COMPONENTS,
    COMPONENT_UNITS,
    POINT_SPREAD,
    axis_component_names,
    component,
    component_names,
    is_axis_field,
    is_point_field,
    split_component,
    with_component,
)
from ppm_stiffness.design.validation import design_issues, validate_design
from ppm_stiffness.legs.base import LegModel, PlanarLegModel, check_plausible
from ppm_stiffness.legs.joint_kinds import joint_kind
from ppm_stiffness.legs.parts import ACTUATOR_STIFFNESSES, Finite, PartModel, StrictNumber
from ppm_stiffness.legs.registry import leg_types

#: The schema version this module reads and writes.
SCHEMA_VERSION = 2


#: Largest |x|, |y|, |z| of a required region [m]: beyond it, a length in mm is likely.
MAX_REGION_LENGTH = 1.0
#: Largest |angle| of a required region [rad] (half a turn): beyond it, degrees are likely.
MAX_REGION_ANGLE = math.pi
#: Most grid values along one axis of a required region.
MAX_REGION_AXIS = 1000
#: Most poses in a required region (the product of its grid).
MAX_REGION_POSES = 1_000_000

GridCount = Annotated[int, StrictNumber, Field(ge=1, le=MAX_REGION_AXIS, strict=True)]
Range = tuple[Finite, Finite]
#: The name a design file may use for rz (the planar orientation, phi).
RZ_ALIASES = AliasChoices("phi", "rz")


class RequiredRegionModel(PartModel):
    """The required workspace ``[workspace.required]``: a grid of poses the design must
    reach without singularity (``ppm-stiffness compare``, ``sweep``, ``optimize``).

    Attributes
    ----------
    x, y, z : (lo, hi) [m], optional
        Ranges of the position of P in F_b.
    rx, ry, phi : (lo, hi) [rad], optional
        Ranges of the orientation angles (:mod:`ppm_stiffness.core.pose`); ``phi`` is rz
        (a file may write either name).
    grid : (n, ...)
        Grid values along each range given, in the order x, y, z, rx, ry, rz, ends
        included; a range with ``lo == hi`` has one value, and one value needs
        ``lo == hi``.

    The ranges given are the design's task coordinates (:attr:`Design.task_coordinates`:
    x, y, phi for a planar design). It is a table, not a scalar parameter: ``sweep`` and
    ``optimize`` do not vary it. Values beyond :data:`MAX_REGION_LENGTH` (1 m) or
    :data:`MAX_REGION_ANGLE` (pi rad) are refused with the likely unit mistake (mm,
    degrees) named.
    """

    x: Range | None = None
    y: Range | None = None
    z: Range | None = None
    rx: Range | None = None
    ry: Range | None = None
    phi: Range | None = Field(default=None, validation_alias=RZ_ALIASES)
    grid: Annotated[tuple[GridCount, ...], Field(min_length=1, max_length=6)]

    model_config = {**PartModel.model_config, "populate_by_name": True}

    @field_validator("x", "y", "z", "rx", "ry", "phi")
    @classmethod
    def _range_in_si(cls, pair: tuple[float, float] | None, info: ValidationInfo) -> Any:
        """A range of a task coordinate (when the design's are known: validation
        context ``task_coordinates``), ordered and in SI (the likely unit mistake named)."""
        if pair is None:
            return pair
        key, (lo, hi) = str(info.field_name), pair
        text = f"{key} = [{lo:g}, {hi:g}]"
        task = (info.context or {}).get("task_coordinates")
        name = POSE_COORDINATES[REGION_KEYS.index(key)]
        if task and name not in task:
            raise ValueError(
                f"{text}: {name} is not a task coordinate of this design; the region's "
                f"ranges are over {', '.join(task)}"
            )
        big = max(abs(lo), abs(hi))
        angle = key in ("rx", "ry", "phi")
        if angle and big > MAX_REGION_ANGLE:
            raise ValueError(
                f"{text}: angles in design files are in radians (a region's |{key}| <= pi); "
                f"did you mean [{math.radians(lo):.6g}, {math.radians(hi):.6g}]?"
            )
        if not angle and big > MAX_REGION_LENGTH:
            raise ValueError(
                f"{text}: lengths in design files are in metres (a region's |{key}| "
                f"<= {MAX_REGION_LENGTH:g} m); did you mean [{lo / 1000:.6g}, "
                f"{hi / 1000:.6g}]?"
            )
        if lo > hi:
            raise ValueError(f"{text}: inverted range (lo > hi)")
        return pair

    def ranges(self) -> dict[str, tuple[float, float]]:
        """The ranges given, by pose coordinate name (``rz`` for phi), in pose order."""
        out = {}
        for name, key in zip(POSE_COORDINATES, REGION_KEYS, strict=True):
            value = getattr(self, key)
            if value is not None:
                out[name] = (float(value[0]), float(value[1]))
        return out

    def range(self, name: str) -> tuple[float, float]:
        """The range of pose coordinate ``name`` (``"rz"`` or ``"phi"`` for rz).

        Raises
        ------
        DesignError
            If the region has no range of that coordinate.
        """
        ranges = self.ranges()
        key = "rz" if name == "phi" else name
        if key not in ranges:
            raise DesignError(
                f"the required region has no range of {name} (its ranges: {', '.join(ranges)})"
            )
        return ranges[key]

    @model_validator(mode="after")
    def _consistent(self) -> RequiredRegionModel:
        """Ranges matching the grid, and not too many poses."""
        ranges = self.ranges()
        if len(ranges) != len(self.grid):
            raise ValueError(
                f"grid = {list(self.grid)}: one grid value per range given "
                f"({', '.join(ranges) or 'none'}: {len(ranges)})"
            )
        for (name, (lo, hi)), n in zip(ranges.items(), self.grid, strict=True):
            key = REGION_KEYS[POSE_COORDINATES.index(name)]
            if (n == 1) != (lo == hi):
                raise ValueError(
                    f"{key} = [{lo:g}, {hi:g}]: a range with lo == hi has grid value 1, "
                    f"and grid value 1 needs lo == hi (grid gives {n})"
                )
        if math.prod(self.grid) > MAX_REGION_POSES:
            raise ValueError(
                f"grid = {list(self.grid)}: {math.prod(self.grid)} poses, more than "
                f"{MAX_REGION_POSES}"
            )
        return self


#: The region's (and the workspace's) key of each pose coordinate.
REGION_KEYS = ("x", "y", "z", "rx", "ry", "phi")


class WorkspaceModel(PartModel):
    """The workspace centre, or home pose, in F_b [m, rad] (the default pose of the CLI,
    and the start of the pose completion), an optional required region
    (:class:`RequiredRegionModel`, ``[workspace.required]``) and an optional candidate
    region (``[workspace.candidate]``, the same keys): a grid over which
    ``optimize --objective reachable-workspace`` counts the share of poses reached
    (usually larger than the required region; not checked).

    ``centre_x, centre_y, centre_z`` [m] and ``rx, ry, phi`` [rad] (``phi`` is rz; a
    file may write either name). The coordinates that are not task coordinates of the
    design are the start of the completion; the home pose is the completed one.
    """

    centre_x: Finite = 0.0
    centre_y: Finite = 0.0
    centre_z: Finite = 0.0
    rx: Finite = 0.0
    ry: Finite = 0.0
    phi: Finite = Field(default=0.0, validation_alias=RZ_ALIASES)
    required: RequiredRegionModel | None = None
    candidate: RequiredRegionModel | None = None

    model_config = {**PartModel.model_config, "populate_by_name": True}

    @field_validator("centre_x", "centre_y", "centre_z", "rx", "ry", "phi")
    @classmethod
    def _pose_in_si(cls, value: float, info: ValidationInfo) -> float:
        """A home-pose coordinate in SI: a length beyond :data:`MAX_LENGTH` (10 m) or an
        angle beyond pi (a pose's angles lie in [-pi, pi]) is refused with the likely
        unit mistake (mm, degrees) named, as the required region's ranges are."""
        key = str(info.field_name)
        if key in ("rx", "ry", "phi") and abs(value) > MAX_REGION_ANGLE:
            raise ValueError(
                f"{key} = {value:g}: angles in design files are in radians (a pose's "
                f"|{key}| <= pi); did you mean {math.radians(value):.6g}?"
            )
        check_plausible(key, value, "m" if key.startswith("centre_") else "rad")
        return value

    def start(self) -> tuple[float, float, float, float, float, float]:
        """The home pose as written (x, y, z, rx, ry, rz) [m, rad]."""
        return (self.centre_x, self.centre_y, self.centre_z, self.rx, self.ry, self.phi)


class ReferenceWrenchModel(PartModel):
    """The report's loaded case (``[reference_wrench]``): a wrench on the platform at
    the tool point, axes of F_b; ``force`` [N], ``moment`` [N·m]. Without it the report
    loads a planar design with the paper's f = (5, 5, 20) N, m_z = 0.1 N·m and a spatial
    one with that load scaled to the design (``docs/report.md``)."""

    force: tuple[Finite, Finite, Finite] = (0.0, 0.0, 0.0)
    moment: tuple[Finite, Finite, Finite] = (0.0, 0.0, 0.0)

    @model_validator(mode="after")
    def _not_zero(self) -> ReferenceWrenchModel:
        if not any(self.force) and not any(self.moment):
            raise ValueError(
                "force and moment are both zero: give a load (force [N], moment [N·m]) "
                "or leave the table out"
            )
        return self

    def wrench(self) -> tuple[float, ...]:
        """(m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N], the library's order."""
        return (*self.moment, *self.force)


_LEG_UNION: Any = Annotated[
    Union[tuple(leg_types().values())],  # noqa: UP007 - built from the registry
    Field(discriminator="type"),
]


class Design(PartModel):
    """A parallel manipulator: legs (any registered type, any number >= 3) joining the
    base to a platform.

    Attributes
    ----------
    schema_version : int
        2 (the file's ``schema`` key).
    task_coordinates : tuple of str
        The pose coordinates the user gives (:mod:`ppm_stiffness.core.pose`), in pose
        order (x, y, z, rx, ry, rz): ``("x", "y", "rz")`` for a planar design, all six
        for a hexapod, ``("z", "rx", "ry")`` for a 3-PRS or 3-RPS tripod. The others
        follow from the legs' constraints (:mod:`ppm_stiffness.legs.completion`).
        Optional in a file when every leg type states the same ones
        (``LegModel.TASK_COORDINATES``).
    tool_point : (x, y, z) [m]
        A point fixed to the platform, in the platform frame F_p. Results that are
        "at the tool point" (``analyze``, ``map``, ``deflect``) are expressed there;
        the model itself works at P. Each component within the plausible length of
        :data:`ppm_stiffness.legs.base.MAX_LENGTH`, as every length of a design.
    platform : PlatformModel or None
        The platform's mass properties (``[platform]``,
        :mod:`ppm_stiffness.design.platform`): the design's mass model, with the legs'
        optional masses (links' sections, actuators' moving parts). None: no mass
        model (natural frequencies are not available; everything else is).
    reference_wrench : ReferenceWrenchModel or None
        The report's loaded case (``[reference_wrench]``: force [N], moment [N·m] at the
        tool point, axes of F_b); None: the report's default (``docs/report.md``).
    """

    schema_version: Literal[2] = Field(default=2, alias="schema")
    name: str = "unnamed design"
    workspace: WorkspaceModel = WorkspaceModel()
    tool_point: tuple[Finite, Finite, Finite] = (0.0, 0.0, 0.0)
    reference_wrench: ReferenceWrenchModel | None = None
    task_coordinates: tuple[str, ...] = ()
    platform: PlatformModel | None = None
    legs: Annotated[list[_LEG_UNION], Field(min_length=3)]

    model_config = {**PartModel.model_config, "populate_by_name": True}

    @classmethod
    def validation_context(cls, data: dict[str, Any]) -> dict[str, Any]:
        """What the parts of a design need to know of the whole while it is validated:
        its task coordinates when the raw ``data`` states them (``task_coordinates``, or
        the one set its leg types state), the home pose as written (``home_pose``, (6,)
        [m, rad]: where a chain leg's joints are given), and the platform's mass [kg]
        (``platform_mass``, a positive finite number given), against which the legs
        check their carriages."""
        context: dict[str, Any] = {"home_pose": _home_pose(data.get("workspace"))}
        platform = data.get("platform")
        mass: Any = platform.get("mass") if isinstance(platform, dict) else None
        if _is_scalar(mass) and 0 < mass < math.inf:
            context["platform_mass"] = float(mass)
        given = data.get("task_coordinates")
        if isinstance(given, (list, tuple)) and all(isinstance(n, str) for n in given):
            return {**context, "task_coordinates": tuple(given)}
        legs = data.get("legs")
        types = leg_types()
        if isinstance(legs, list) and legs:
            kinds = [leg.get("type") if isinstance(leg, dict) else None for leg in legs]
            stated = {types[k].TASK_COORDINATES for k in kinds if k in types}
            if len(stated) == 1 and all(k in types for k in kinds):
                return {**context, "task_coordinates": stated.pop()}
        return context

    @field_validator("task_coordinates")
    @classmethod
    def _known_coordinates(cls, names: tuple[str, ...]) -> tuple[str, ...]:
        """Pose coordinate names, each once, in pose order."""
        unknown = [n for n in names if n not in POSE_COORDINATES]
        if unknown:
            raise ValueError(
                f"unknown coordinate {unknown[0]!r}; task coordinates are among "
                f"{', '.join(POSE_COORDINATES)}"
            )
        ordered = tuple(n for n in POSE_COORDINATES if n in names)
        if tuple(names) != ordered or len(set(names)) != len(names):
            raise ValueError(
                f"{list(names)}: give each task coordinate once, in the order "
                f"{', '.join(POSE_COORDINATES)} ({list(ordered)})"
            )
        return tuple(names)

    @model_validator(mode="after")
    def _task_coordinates(self) -> Design:
        """The task coordinates: given, or the one set every leg type states; the
        required region's ranges are over them."""
        if not self.task_coordinates:
            stated = {type(leg).TASK_COORDINATES for leg in self.legs}
            if len(stated) != 1:
                raise ValueError(
                    "task_coordinates: the leg types state different task coordinates "
                    f"({'; '.join(sorted(', '.join(t) for t in stated))}); give them"
                )
            object.__setattr__(self, "task_coordinates", stated.pop())
        for key in ("required", "candidate"):
            region = getattr(self.workspace, key)
            if region is not None and tuple(region.ranges()) != self.task_coordinates:
                raise ValueError(
                    f"workspace.{key}: its ranges ({', '.join(region.ranges()) or 'none'}) "
                    f"must be the task coordinates ({', '.join(self.task_coordinates)}); rz "
                    "may be written phi"
                )
        return self

    @model_validator(mode="after")
    def _enough_actuators(self) -> Design:
        """At least one actuated leg per task coordinate (passive constraining legs
        drive nothing): with fewer, the platform moves with every actuator locked."""
        actuated = sum(leg.is_actuated() for leg in self.legs)
        if actuated < len(self.task_coordinates):
            raise ValueError(
                f"legs: {actuated} actuated leg(s) for {len(self.task_coordinates)} task "
                f"coordinates ({', '.join(self.task_coordinates)}): the platform would "
                "move with every actuator locked; each task coordinate needs an actuated "
                "leg (a passive constraining leg, without an actuated joint, drives none)"
            )
        return self

    @model_validator(mode="after")
    def _masses_need_platform(self) -> Design:
        """Leg masses are part of a mass model, whose base is the platform's mass."""
        if self.platform is None:
            for i, leg in enumerate(self.legs):
                chain_masses = _leg_mass_keys(leg)
                if chain_masses:
                    raise ValueError(
                        f"leg{i + 1}.{chain_masses[0]}: the legs carry masses but the "
                        "design has no [platform] table (mass [kg] and inertia, or a "
                        "shape): the mass model starts with the platform's"
                    )
        return self

    @property
    def has_mass_model(self) -> bool:
        """True when the design has a mass model (a ``[platform]`` table)."""
        return self.platform is not None

    @property
    def planar(self) -> bool:
        """True for a planar design: task coordinates (x, y, rz) and planar legs, whose
        results also have the paper's planar meaning (k_x, k_y, k_phi)."""
        return self.task_coordinates == ("x", "y", "rz") and all(
            isinstance(leg, PlanarLegModel) for leg in self.legs
        )

    @field_validator("tool_point")
    @classmethod
    def _plausible_tool_point(cls, point: tuple[float, float, float]) -> tuple[float, ...]:
        """A tool point in metres (``tool_point = [0, 0, 50]`` would be a 50 m tool)."""
        for v in point:
            check_plausible("tool_point", v, "m")
        return point

    @property
    def architecture(self) -> str:
        """E.g. ``"3-PPR"``, ``"4-PPR"``, or ``"2-PRR+1-RPR"`` for mixed legs."""
        counts = Counter(leg.architecture_name() for leg in self.legs)
        return "+".join(f"{n}-{t}" for t, n in counts.items())

    @property
    def actuator(self) -> Any:
        """The actuator law shared by every leg (for code that assumes one law).

        Raises
        ------
        DesignError
            If the legs have different laws.
        """
        laws = [leg.actuator for leg in self.legs if leg.actuator is not None]
        law = laws[0]  # a design has an actuated leg (passive legs: no law)
        if any(other != law for other in laws[1:]):
            raise DesignError("the legs have different actuator laws; use each leg's own")
        return law

    def parameter(self, name: str) -> float:
        """Value of the scalar parameter ``name`` (dotted, legs from 1).

        A glob (``leg*.guide.yaw``) is one value for all its matches: they must be equal
        (a point's components within :data:`~ppm_stiffness.design.points.POINT_SPREAD`
        of each other, relative: the first is returned).
        """
        values, spread = [], 0.0
        matches = self.expand(name)
        copies = _axis_glob(self, name, matches)
        if copies is not None:  # the first axis's angle, the others its pattern's copies
            first = _point_component(self, matches[0])
            assert first is not None
            value = component(copies[0].axis, first[1])
            copies_of_first(copies, copies[0].axis, matches)  # refuses a non-copy
            return value
        for match in matches:
            point = _point_component(self, match)
            if point is not None:  # a component of a leg's point (design.points)
                obj, key = _resolve(self, point[0])
                values.append(component(getattr(obj, key), point[1]))
                spread = POINT_SPREAD  # copies turned by a pattern differ by rounding
                continue
            obj, key = _resolve(self, match)
            value = getattr(obj, key)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise DesignError(f"parameter {match!r} is not a scalar")
            values.append(float(value))
        if max(values) - min(values) > spread * max(abs(v) for v in values):
            raise DesignError(
                f"parameter {name!r}: its matches differ ({min(values):g} to "
                f"{max(values):g}); a glob ties parameters that are equal"
            )
        return values[0]

    def expand(self, pattern: str) -> list[str]:
        """Parameter names matching ``pattern`` (a name, or a glob like ``leg*.guide.yaw``).

        A name that starts with neither ``legN.`` nor ``workspace.`` (``guide.yaw``)
        means that part in every leg, as ``leg*.guide.yaw`` (the v1 names).

        Raises
        ------
        DesignError
            If nothing matches.
        """
        names = self.scalar_parameter_names()
        hits = _matches(names, pattern)
        if not hits and not pattern.startswith(("leg", "workspace.")):
            hits = _matches(names, f"leg*.{pattern}")  # a part of every leg
        if not hits:
            raise DesignError(
                f"unknown design parameter {pattern!r} "
                "(`ppm-stiffness calibrate --list-parameters` lists them)"
            )
        return hits

    def parameter_unit(self, name: str) -> str:
        """SI unit of a parameter (``"m"``, ``"rad"``, ``"N/m"``, ...; "" if unknown)."""
        from ppm_stiffness.legs.parts import part_units

        first = self.expand(name)[0]
        parts = first.split(".")
        if _point_component(self, first) is not None:
            return COMPONENT_UNITS[parts[-1]]
        if parts[0] == "workspace":
            return "rad" if parts[-1] in ("phi", "rx", "ry") else "m"
        if parts[0] == "platform":
            return PLATFORM_UNITS.get(parts[-1], "")
        leg = self.legs[int(parts[0][3:]) - 1]
        part, key = _resolve(self, first)
        if part is leg:
            return leg.parameter_unit(key)
        if parts[1] == "actuator":
            force, disp, stiff = leg.actuator_units()
            return {
                "locked_stiffness": stiff,
                "k_a": f"{force}/{disp}^q",
                "q": "1",
                "threshold_displacement": disp,
                **leg.drive_units(),
            }[parts[2]]
        # a field of the element itself (a parallelogram's width) is the leg's to say
        return part_units(type(part)).get(key, "") or leg.parameter_unit(".".join(parts[1:]))

    def with_parameters(self, values: dict[str, float]) -> Design:
        """A copy with the named (or globbed) scalar parameters replaced, validated again.

        Raises
        ------
        DesignError
            ``"parameters: key '<name>': <why>"``, every error one a line.
        """
        return validate_design(Design, self._replaced(values), source="parameters")

    def _replaced(self, values: dict[str, float]) -> dict[str, Any]:
        """This design as a dict with the named (or globbed) parameters replaced, and
        each actuator's two stiffnesses kept one under a linear law
        (:func:`_tie_linear_actuators`)."""
        data = self.model_dump(by_alias=True)
        stiffnesses: dict[int, dict[str, float]] = {}
        for pattern, value in values.items():
            matches = self.expand(pattern)
            copies = _axis_glob(self, pattern, matches)
            if copies is not None:  # the first axis set, the others moved as its copies
                _set_axis_copies(self, data, matches, copies, float(value))
                continue
            for name in matches:
                parts = _split(name)
                target: Any = data
                point = _point_component(self, name)
                path = _field_path(self, point[0] if point else name)
                for part in path[:-1]:
                    target = target[part]
                if point is not None:  # a component of a leg's point (design.points)
                    old = target[path[-1]]
                    target[path[-1]] = with_component(old, point[1], float(value), name)
                    continue
                target[path[-1]] = float(value)
                if _actuator_key(parts, (*ACTUATOR_STIFFNESSES, "q")):
                    stiffnesses.setdefault(parts[1], {})[parts[-1]] = float(value)
        _tie_linear_actuators(data, stiffnesses)
        return data

    def addressed(self, pattern: str) -> list[str]:
        """The parameters that setting ``pattern`` (a name or glob) changes: its matches
        (:meth:`expand`) and, for an actuator under a linear law (q = 1), its other
        stiffness (``locked_stiffness`` and ``k_a`` are one there); for a point's
        ``.radius`` or ``.angle`` its ``.x`` and ``.y``, which they move (so x or y and
        radius or angle of one point, whose result would hang on their order, are
        refused together; so are radius and angle, conservatively). What commands
        compare to refuse two options that set one parameter.

        Raises
        ------
        DesignError
            If nothing matches.
        """
        out: list[str] = []
        for name in self.expand(pattern):
            parts = _split(name)
            out.append(name)
            point = _point_component(self, name)
            if point is not None and point[1] in ("radius", "angle"):
                out += [f"{point[0]}.x", f"{point[0]}.y"]  # both move x and y
            linear = _actuator_key(parts, ACTUATOR_STIFFNESSES) and (
                self.legs[parts[1]].law().q == 1
            )
            if linear:
                other = next(k for k in ACTUATOR_STIFFNESSES if k != parts[-1])
                out.append(f"{name.rsplit('.', 1)[0]}.{other}")
        return list(dict.fromkeys(out))

    def check_value(self, name: str, value: float) -> None:
        """Refuse a value that parameter ``name`` (or glob) cannot take.

        Raises
        ------
        DesignError
            ``"<name> = <value>: <why>"``: the design file's own validation message
            (bounds, the likely unit mistake), without the file context; a glob's
            legs that fail alike give one message.
        """
        _, issues = design_issues(Design, self._replaced({name: value}))
        if issues:
            why = "; ".join(dict.fromkeys(_unprefixed(issue.message, name) for issue in issues))
            raise DesignError(f"{name} = {value:g}: {why}")

    def check_range(self, name: str, low: float, high: float) -> None:
        """Refuse a range ``[low, high]`` for parameter ``name`` (or glob) that is empty or
        reaches values the design cannot take.

        Both ends are validated as design values (:meth:`check_value`), so a range in
        the wrong unit gets the same message as a wrong value in a design file
        (``alpha = 90: angles ... are in radians; did you mean 1.5708?``), and a
        stiffness range reaching 0 is refused.

        Raises
        ------
        DesignError
            Naming the parameter, the range and what is wrong.
        """
        if not (math.isfinite(low) and math.isfinite(high)) or not low < high:
            raise DesignError(
                f"range of {name!r}: [{low:g}, {high:g}] must be finite with low < high"
            )
        for end in (low, high):
            try:
                self.check_value(name, end)
            except DesignError as exc:
                raise DesignError(f"range [{low:g}, {high:g}] of {exc}") from None

    def scalar_parameter_names(self) -> list[str]:
        """Every scalar parameter name of this design, in file order."""
        names = [f"workspace.{k}" for k, v in self.workspace if _is_scalar(v)]
        if self.platform is not None:
            names += [f"platform.{k}" for k, v in self.platform if _is_scalar(v)]
        for i, leg in enumerate(self.legs, start=1):
            names += _scalar_names(leg, f"leg{i}", leg.parameter_items())
            names += _point_names(leg, f"leg{i}")
        return names


def _home_pose(workspace: Any) -> tuple[float, ...]:
    """The home pose (x, y, z, rx, ry, rz) a raw ``[workspace]`` table writes (its
    defaults for keys not given or not numbers: the model's validation reports those)."""
    table = workspace if isinstance(workspace, dict) else {}
    keys = ("centre_x", "centre_y", "centre_z", "rx", "ry", "phi")
    return tuple(float(v) if _is_scalar(v := table.get(k, 0.0)) else 0.0 for k in keys)


def _leg_mass_keys(leg: LegModel) -> list[str]:
    """Dotted keys (within a leg) of the masses a leg's parts carry."""
    keys = []
    for key, value in leg.parameter_items():
        if isinstance(value, BaseModel):
            keys += [
                f"{key}.{sub}"
                for sub in ("mass", "carriage_mass", "rotor_inertia")
                if getattr(value, sub, None) is not None
            ]
    return keys


def _point_names(leg: LegModel, prefix: str) -> list[str]:
    """The component parameters (x, y, z, radius, angle; :mod:`ppm_stiffness.design.
    points`) of each point of ``leg``, dotted under ``prefix``."""
    names: list[str] = []
    for key, value in leg.parameter_items():
        unit = leg.parameter_unit(key)
        if is_point_field(key, value, unit):
            names += component_names(f"{prefix}.{key}", value)
        elif is_axis_field(key, value, unit):
            names += axis_component_names(f"{prefix}.{key}")
    return names


def _set_axis_copies(
    design: Design, data: dict[str, Any], names: list[str], copies: list[AxisOfLeg], value: float
) -> None:
    """Set the first of ``names`` (an axis angle in each leg) to ``value`` in ``data``
    (the design's dump) and every other axis as its copy (:func:`_axis_glob`)."""
    first = _point_component(design, names[0])
    assert first is not None
    turned = np.asarray(with_component(copies[0].axis, first[1], value, names[0]))
    for name, axis in zip(names, copies_of_first(copies, turned, names), strict=True):
        point = _point_component(design, name)
        assert point is not None
        target: Any = data
        path = _field_path(design, point[0])
        for part in path[:-1]:
            target = target[part]
        target[path[-1]] = axis


def _axis_glob(design: Design, pattern: str, names: list[str]) -> list[AxisOfLeg] | None:
    """The matches of a glob over one axis angle of several legs
    (:mod:`ppm_stiffness.design.axis_globs`), None for any other name or glob."""
    axes = [_point_component(design, n) for n in names]
    angles = [a for a in axes if a is not None and a[1] in AXIS_COMPONENTS]
    if len(names) < 2 or not angles:
        return None
    within = {a[0].partition(".")[2] for a in angles} | {a[1] for a in angles}
    if len(angles) != len(names) or len(within) != 2:
        raise DesignError(
            f"{pattern}: a glob of axis angles matches one angle of one axis in each leg "
            f"(leg*.JOINT.axis.tilt); this one matches {', '.join(names)}"
        )
    out = []
    for axis_name, _ in angles:
        obj, key = _resolve(design, axis_name)
        leg = design.legs[int(axis_name.split(".", 1)[0][3:]) - 1]
        letter = getattr(obj, "joint", None)  # the joint (a parallelogram has none)
        axial = (
            key in ("axis", "axis2")
            and isinstance(letter, str)
            and joint_kind(letter).first_rotates
        )
        points = [
            value
            for k, value in leg.parameter_items()
            if is_point_field(k, value, leg.parameter_unit(k)) and len(value) == 3
        ]
        out.append(
            AxisOfLeg(
                np.asarray(getattr(obj, key), dtype=float),
                np.asarray(points, dtype=float).reshape(-1, 3),
                axial,
            )
        )
    return out


def _point_component(design: Design, name: str) -> tuple[str, str] | None:
    """``(point name, component)`` when ``name`` is a component parameter of a leg's
    point (``leg1.crank_joint.point.radius``), None for any other name (a part's own
    ``radius`` among them)."""
    split = split_component(name)
    if split is None:
        return None
    leg_key, _, within = split[0].partition(".")
    index = int(leg_key[3:]) - 1 if leg_key[:3] == "leg" and leg_key[3:].isdigit() else -1
    if not 0 <= index < len(design.legs):
        return None
    leg = design.legs[index]
    value = dict(leg.parameter_items()).get(within)
    unit = leg.parameter_unit(within)
    if split[1] in AXIS_COMPONENTS:
        return split if is_axis_field(within, value, unit) else None
    return split if is_point_field(within, value, unit) else None


def _matches(names: list[str], pattern: str) -> list[str]:
    if any(ch in pattern for ch in "*?["):
        return [n for n in names if fnmatch.fnmatchcase(n, pattern)]
    return [pattern] if pattern in names else []


def _is_scalar(value: Any) -> bool:
    return isinstance(value, float) or (isinstance(value, int) and not isinstance(value, bool))


def _scalar_names(
    model: BaseModel, prefix: str, items: Iterable[tuple[str, Any]] | None = None
) -> list[str]:
    """The scalar parameters of ``model`` dotted under ``prefix``, from ``items`` (a
    leg's :meth:`~ppm_stiffness.legs.base.LegModel.parameter_items`) or its fields,
    its working modes (``DISCRETE_FIELDS``) left out."""
    names: list[str] = []
    discrete: frozenset[str] = getattr(type(model), "DISCRETE_FIELDS", frozenset())
    for key, value in model if items is None else items:
        if key in discrete:  # a working mode, not a continuous parameter
            continue
        if _is_scalar(value):
            names.append(f"{prefix}.{key}")
        elif isinstance(value, BaseModel):
            names += _scalar_names(value, f"{prefix}.{key}")
    return names


def shared_parameter(
    groups: Iterable[tuple[str, Iterable[str]]],
) -> tuple[str, str, str] | None:
    """The first parameter set by two of ``groups`` (label, the parameters it sets, e.g.
    :meth:`Design.addressed`), as ``(earlier label, later label, parameter)``; None if
    none is. Each caller words its own refusal (with :func:`tied_note`)."""
    owner: dict[str, str] = {}
    for label, names in groups:
        for name in names:
            if name in owner:
                return owner[name], label, name
            owner[name] = label
    return None


def tied_note(name: str) -> str:
    """A message's note for parameter ``name`` when it is an actuator stiffness, which
    :meth:`Design.addressed` ties to its twin under a linear law; "" otherwise."""
    if name.rsplit(".", 1)[-1] in ACTUATOR_STIFFNESSES:
        return " (with q = 1 an actuator's locked_stiffness and k_a are one stiffness)"
    return ""


def _actuator_key(parts: list[Any], keys: tuple[str, ...]) -> bool:
    """True for the split name (:func:`_split`) of one of ``keys`` of a leg's actuator."""
    return len(parts) == 4 and parts[0] == "legs" and parts[2] == "actuator" and parts[3] in keys


def _tie_linear_actuators(data: dict[str, Any], given: dict[int, dict[str, float]]) -> None:
    """Keep a linear law's two stiffnesses one (:class:`~ppm_stiffness.legs.parts.
    ActuatorModel`) where this change set some of a leg's ``q``, ``locked_stiffness``,
    ``k_a`` (``given``: leg index -> {key: value}) and its law is linear after it
    (q = 1): one stiffness set sets the other. Both set to different values, or a law
    made linear with neither set while its two differ, are left for the validation to
    refuse naming both: which one the user meant is not ours to guess (the unloaded K
    uses ``locked_stiffness``, the loaded one ``k_a``: 1.1108e5 against 44.75 N/m on
    the paper's law)."""
    for leg, values in given.items():
        actuator = data["legs"][leg]["actuator"]
        named = [values[k] for k in ACTUATOR_STIFFNESSES if k in values]
        if actuator["q"] != 1 or len(named) != 1:
            continue
        for key in ACTUATOR_STIFFNESSES:
            actuator[key] = named[0]


def _unprefixed(message: str, name: str) -> str:
    """``message`` without a leading ``"<key> = <value>: "`` that names ``name`` (or
    its last parts) again: a leg-level check's message already starts so, and
    :meth:`Design.check_value` puts the full name first."""
    head, sep, rest = message.partition(" = ")
    if sep and name.endswith(head) and ": " in rest:
        return rest.split(": ", 1)[1]
    return message


def _split(name: str) -> list[Any]:
    parts: list[Any] = []
    for part in name.split("."):
        if part.startswith("leg") and part[3:].isdigit():
            parts += ["legs", int(part[3:]) - 1]
        else:
            parts.append(part)
    return parts


def _field_path(design: Design, name: str) -> list[Any]:
    """The path of parameter ``name`` through the design's fields (and list indices):
    a leg's keys as its :meth:`~ppm_stiffness.legs.base.LegModel.field_path` says."""
    parts = _split(name)
    if len(parts) > 2 and parts[0] == "legs" and 0 <= parts[1] < len(design.legs):
        return [*parts[:2], *design.legs[parts[1]].field_path(parts[2:])]
    return parts


def _resolve(design: Design, name: str) -> tuple[Any, str]:
    parts = _field_path(design, name)
    obj: Any = design
    try:
        for part in parts[:-1]:
            obj = obj[part] if isinstance(part, int) else getattr(obj, part)
        if not isinstance(parts[-1], str) or parts[-1] not in type(obj).model_fields:
            raise KeyError(name)
    except (AttributeError, IndexError, KeyError, TypeError) as exc:
        raise DesignError(
            f"unknown design parameter {name!r} "
            "(`ppm-stiffness calibrate --list-parameters` lists them)"
        ) from exc
    return obj, parts[-1]


def leg_label(index: int) -> str:
    """``"leg 1"`` for index 0: how messages name a leg."""
    return f"leg {index + 1}"


__all__ = [
    "SCHEMA_VERSION",
    "Design",
    "LegModel",
    "RequiredRegionModel",
    "WorkspaceModel",
    "leg_label",
    "tied_note",
]


#: The optional mass fields of the parts (:mod:`ppm_stiffness.legs.parts`): left out of
#: :func:`leg_parameter_rows` where a design does not give them.
MASS_FIELDS = frozenset(
    {
        "mass",
        "mass_centre",
        "mass_centre_from",
        "inertia_transverse",
        "inertia_axial",
        "carriage_mass",
        "rotor_inertia",
        "gear_ratio",
    }
)


def _model_rows(
    key: str, value: BaseModel, part_units: Any, depth: int = 0
) -> list[tuple[str, Any, str]]:
    """A part's fields as (dotted name, value, SI unit), a nested part (a notch hinge's
    profile and material) flattened into its own fields; an optional mass field, or a
    nested part's optional field, left out where not given."""
    out: list[tuple[str, Any, str]] = []
    for sub, v in value:
        if v is None and (sub in MASS_FIELDS or depth > 0):
            continue
        name = f"{key}.{sub}"
        if isinstance(v, BaseModel):
            out += _model_rows(name, v, part_units, depth + 1)
        else:
            out.append((name, v, part_units(type(value)).get(sub, "")))
    return out


def leg_parameter_rows(design: Design) -> list[tuple[str, list[Any], str]]:
    """The legs' parameters side by side, for tables and reports.

    Returns
    -------
    list of (name, values, unit)
        ``name`` dotted within a leg (``guide.lateral``, ``base_point``); ``values`` one
        per leg (None where that leg has no such parameter; tuples stay tuples); the
        SI unit.
    """
    from ppm_stiffness.legs.parts import part_units

    table: dict[str, list[Any]] = {}
    units: dict[str, str] = {}
    for i, leg in enumerate(design.legs):
        for key, value in leg.parameter_items():
            if value is None:
                continue
            if isinstance(value, BaseModel):
                for name, v, unit in _model_rows(key, value, part_units):
                    table.setdefault(name, [None] * len(design.legs))[i] = v
                    units.setdefault(name, unit)
                if key == "actuator":
                    force, disp, stiff = leg.actuator_units()
                    units.update(
                        {
                            "actuator.locked_stiffness": stiff,
                            "actuator.k_a": f"{force}/{disp}^q",
                            "actuator.q": "1",
                            "actuator.threshold_displacement": disp,
                            **{f"actuator.{k}": u for k, u in leg.drive_units().items()},
                        }
                    )
            else:
                table.setdefault(key, [None] * len(design.legs))[i] = value
                units.setdefault(key, leg.parameter_unit(key))
    return [(name, values, units.get(name, "")) for name, values in table.items()]
