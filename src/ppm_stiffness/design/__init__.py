"""Design description: validated data, loaded from and written to TOML.

A design file is SI throughout (m, rad, Pa, N/m, N·m/rad). It names its
architecture; the geometry module of that architecture turns the design and a pose
into virtual springs for :mod:`ppm_stiffness.core.solver`. Every scalar parameter has a
dotted name (``leg2.bearing_offset``, ``guide.yaw``, ``workspace.centre_x``) used by
calibration and the CLI; legs are numbered from 1.
"""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal

import tomli_w
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.core.errors import DesignError

Positive = Annotated[float, Field(gt=0.0, allow_inf_nan=False)]
Finite = Annotated[float, Field(allow_inf_nan=False)]


class _Model(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class SectionModel(_Model):
    """A link's material and section (paper Table 2)."""

    young_modulus: Positive
    shear_modulus: Positive
    area: Positive
    torsion_constant: Positive
    inertia_y: Positive
    inertia_z: Positive

    def section(self) -> BeamSection:
        return BeamSection(**self.model_dump())


class GuideModel(_Model):
    """Linear guide (paper Table 3, eq. 3a): five springs at the guide block B.

    roll about u, pitch about y_B = z x u, yaw about z [N·m/rad];
    lateral along y_B, vertical along z [N/m].
    """

    roll: Positive
    pitch: Positive
    yaw: Positive
    lateral: Positive
    vertical: Positive


class BearingModel(_Model):
    """Linear bearing of the rod (Table 3, eq. 3b): four springs at the bearing C.

    tilt about y_D = z x w and about z [N·m/rad]; radial along y_D and z [N/m].
    """

    tilt_lateral: Positive
    tilt_vertical: Positive
    radial_lateral: Positive
    radial_vertical: Positive


class ActuatorModel(_Model):
    """Actuator law (eq. 20-21): G = k_a * delta**q; stiffness ``locked_stiffness``
    below ``threshold_displacement``, q k_a delta**(q-1) above. ``q = 1`` is a linear
    spring of stiffness k_a; a huge threshold makes the actuator constant."""

    locked_stiffness: Positive
    k_a: Positive
    q: Annotated[float, Field(gt=0.0, le=1.0)]
    threshold_displacement: Annotated[float, Field(ge=0.0, allow_inf_nan=False)]


class WorkspaceModel(_Model):
    """The workspace centre [m] in F_b (default pose of the CLI)."""

    centre_x: Finite = 0.0
    centre_y: Finite = 0.0
    phi: Finite = 0.0


class PPRLegModel(_Model):
    """One P-P-R leg (paper Table 1 plus the calibrated carriage layout).

    The rail runs through ``base_point`` A along ``u = (cos alpha, sin alpha)``; the
    rod runs along ``w = rot(beta) u`` from the bearing C to the platform point D;
    D sits at ``-platform_radius * (cos psi, sin psi)`` from P in F_p. In the leg
    frame (u, w) with origin A: C = A + rho u + bearing_offset w, with rho the
    actuator coordinate (the u coordinate of D); the guide block B = A +
    (rho + guide_offset_u) u + guide_offset_w w; the proximal link runs from B to C.
    """

    base_point: tuple[Finite, Finite]
    alpha: Finite
    beta: Finite
    psi: Finite
    platform_radius: Positive
    bearing_offset: Finite
    guide_offset_u: Finite
    guide_offset_w: Finite
    stroke: tuple[Finite, Finite] = (-1.0, 1.0)
    rod_length_range: tuple[Positive, Positive] = (1e-3, 1.0)

    @model_validator(mode="after")
    def _ranges(self) -> PPRLegModel:
        if not self.stroke[0] < self.stroke[1]:
            raise ValueError("stroke must be [min, max] with min < max")
        if not self.rod_length_range[0] < self.rod_length_range[1]:
            raise ValueError("rod_length_range must be [min, max] with min < max")
        return self


class Design(_Model):
    """A planar parallel manipulator built from the paper's parts."""

    name: str = "unnamed design"
    architecture: Literal["PPR"] = "PPR"
    workspace: WorkspaceModel = WorkspaceModel()
    actuator: ActuatorModel
    guide: GuideModel
    bearing: BearingModel
    proximal: SectionModel
    distal: SectionModel
    legs: Annotated[list[PPRLegModel], Field(min_length=3)]

    def parameter(self, name: str) -> float:
        """Value of the scalar parameter ``name`` (dotted, legs from 1)."""
        obj, key = _resolve(self, name)
        value = getattr(obj, key)
        if not isinstance(value, (int, float)):
            raise DesignError(f"parameter {name!r} is not a scalar")
        return float(value)

    def with_parameters(self, values: dict[str, float]) -> Design:
        """A copy with the named scalar parameters replaced (validated again)."""
        data = self.model_dump()
        for name, value in values.items():
            _resolve(self, name)  # raises on an unknown name
            parts = _split(name)
            target: Any = data
            for part in parts[:-1]:
                target = target[part]
            target[parts[-1]] = float(value)
        return design_from_dict(data, source="parameters")

    def scalar_parameter_names(self) -> list[str]:
        """Every scalar parameter name of this design."""
        names: list[str] = []
        for section in ("workspace", "actuator", "guide", "bearing", "proximal", "distal"):
            names += [f"{section}.{k}" for k, v in getattr(self, section) if isinstance(v, float)]
        for i, leg in enumerate(self.legs, start=1):
            names += [f"leg{i}.{k}" for k, v in leg if isinstance(v, float)]
        return names


def _split(name: str) -> list[Any]:
    parts: list[Any] = []
    for part in name.split("."):
        if part.startswith("leg") and part[3:].isdigit():
            parts += ["legs", int(part[3:]) - 1]
        else:
            parts.append(part)
    return parts


def _resolve(design: Design, name: str) -> tuple[Any, str]:
    parts = _split(name)
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


def _format_location(loc: tuple[Any, ...]) -> str:
    out: list[str] = []
    for i, part in enumerate(loc):
        if isinstance(part, int) and i > 0 and loc[i - 1] == "legs":
            out[-1] = f"leg{part + 1}"
        else:
            out.append(str(part))
    return ".".join(out)


def design_from_dict(data: dict[str, Any], source: str = "design") -> Design:
    """Validate a nested dict as a :class:`Design`; errors name the offending key."""
    try:
        return Design.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        key = _format_location(tuple(first["loc"])) or "(top level)"
        raise DesignError(f"{source}: key '{key}': {first['msg']}") from None


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


def dump_design(design: Design) -> str:
    """The design as TOML text (round-trips through :func:`load_design`)."""
    data = design.model_dump(mode="json")
    header = (
        "# ppm-stiffness design file. SI units: m, rad, Pa, m^2, m^4, N/m, N·m/rad.\n"
    )
    return header + tomli_w.dumps(data)


def save_design(design: Design, path: str | Path) -> None:
    """Write the design as a TOML file."""
    Path(path).write_text(dump_design(design), encoding="utf-8")


def default_design() -> Design:
    """The built-in design: the paper's 3-PPR, carriage layout calibrated on (22)."""
    text = resources.files("ppm_stiffness").joinpath("data/paper_3ppr.toml").read_text("utf-8")
    return design_from_dict(tomllib.loads(text), source="built-in design")
