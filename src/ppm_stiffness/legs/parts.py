"""Catalogue parts a leg is built from: actuator law, joint springs, link sections.

Each is a validated, frozen record in SI units. A joint's hardware springs act in its
*constrained* directions, expressed in the joint frame ``(e1, e2, e3)`` of
:mod:`ppm_stiffness.legs.chain`: ``e1`` the joint axis, ``e2 = unit(z x e1)`` (for an
in-plane axis: the in-plane lateral direction), ``e3 = e1 x e2`` (then: z).

- :class:`GuideModel`, a prismatic joint (linear guide, paper Table 3, eq. 3a):
  roll about e1, pitch about e2, yaw about e3 [N·m/rad]; lateral along e2, vertical
  along e3 [N/m].
- :class:`BearingModel`, a cylindrical joint (linear bearing of a rod, eq. 3b): tilt
  about e2 and about e3 [N·m/rad]; radial along e2 and e3 [N/m].
- :class:`RevoluteModel`, a revolute joint (a rotary bearing, axisymmetric): tilt
  about any axis normal to its own [N·m/rad], radial along any direction normal to
  it and axial along it [N/m].
- :class:`UniversalModel`, a universal joint (axes e1, e2; e3 = e1 x e2): radial
  along e1 and e2, axial along e3 [N/m], torsion about e3 [N·m/rad]; optionally the
  largest angle [rad] between the leg and the joint's mounting axis.
- :class:`SphericalModel`, a spherical joint (its frame oriented by the adjacent link,
  e1 along it): axial along e1, radial along e2 and e3 [N/m]; optionally the largest
  angle [rad] between the link and the joint's mounting axis.
"""

from __future__ import annotations

import math
import numbers
import sys
from typing import Annotated, Any

import numpy as np
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, ValidationInfo, field_validator
from pydantic_core import PydanticCustomError

from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.core.conventions import FloatArray


def value_kind(value: Any) -> str:
    """How a message names the type of a value (``"a boolean"``, ``"a table"``)."""
    if isinstance(value, (bool, np.bool_)):
        return "a boolean"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, (list, tuple)):
        return "a list"
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, float):
        return "a float"
    if isinstance(value, int):
        return "an integer"
    return f"a {type(value).__name__}"


def strict_number(value: Any) -> Any:
    """Let a finite real number (int or float, numpy ones included) through unchanged
    and refuse anything else, which pydantic's lax mode would coerce (``true`` to 1.0,
    ``"4e3"`` to 4000.0): "expected a number, got a boolean"; "expected a finite
    number, got not-a-number"."""
    if isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
        if isinstance(value, int) and abs(value) > sys.float_info.max:  # TOML allows it
            value = math.inf if value > 0 else -math.inf
        if math.isfinite(value):
            return value
        number = float(value)
        what = "not-a-number" if math.isnan(number) else f"{'minus ' * (number < 0)}infinity"
        raise PydanticCustomError(
            "finite_number", "expected a finite number, got {what}", {"what": what}
        )
    kind = {"kind": value_kind(value)}
    raise PydanticCustomError("number_type", "expected a number, got {kind}", kind)


#: The number types of every numeric field of a design: finite ints and floats, never
#: booleans or strings (:func:`strict_number`). Defined here once.
StrictNumber = BeforeValidator(strict_number)
Finite = Annotated[float, StrictNumber, Field(allow_inf_nan=False)]
Positive = Annotated[float, StrictNumber, Field(gt=0.0, allow_inf_nan=False)]
NonNegative = Annotated[float, StrictNumber, Field(ge=0.0, allow_inf_nan=False)]

#: Smallest plausible Young's or shear modulus [Pa]: soft polymers have ~1e8 Pa; below
#: this a value is a unit mistake (GPa). No upper limit: the rigid-link limit is
#: modelled by huge moduli.
MIN_MODULUS = 1e6
#: Largest section area [m^2] and second moment [m^4] of a link: a 1 m x 1 m solid bar
#: (0.083 m^4). Above, mm^2 / mm^4 are likely.
MAX_AREA = 1.0
MAX_SECOND_MOMENT = 0.1


class PartModel(BaseModel):
    """Base of every design record: unknown keys are errors, values are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class SectionModel(PartModel):
    """A link's material and section (paper Table 2) [Pa, m^2, m^4]."""

    young_modulus: Positive
    shear_modulus: Positive
    area: Positive
    torsion_constant: Positive
    inertia_y: Positive
    inertia_z: Positive

    @field_validator("young_modulus", "shear_modulus")
    @classmethod
    def _modulus_in_pa(cls, v: float, info: ValidationInfo) -> float:
        """Refuse a modulus no structural material has, naming the likely unit
        mistake (GPa)."""
        if v < MIN_MODULUS:
            hint = f"; did you mean {v * 1e9:.6g} (GPa)?" if 1e-3 <= v <= 1e4 else ""
            raise ValueError(
                f"{info.field_name} = {v:g}: moduli in design files are in Pa "
                f"(>= {MIN_MODULUS:g}){hint}"
            )
        return v

    @field_validator("area", "torsion_constant", "inertia_y", "inertia_z")
    @classmethod
    def _size_in_si(cls, v: float, info: ValidationInfo) -> float:
        """Refuse a section larger than a 1 m x 1 m bar, naming the likely unit mistake
        (mm^2, mm^4)."""
        power, limit = (2, MAX_AREA) if info.field_name == "area" else (4, MAX_SECOND_MOMENT)
        if v > limit:
            raise ValueError(
                f"{info.field_name} = {v:g}: sections in design files are in m^{power} "
                f"(<= {limit:g}); did you mean {v * 1e-3**power:.6g} (mm^{power})?"
            )
        return v

    def section(self) -> BeamSection:
        return BeamSection(**self.model_dump())


class ActuatorModel(PartModel):
    """Actuator law (eq. 20-21): ``G = k_a * delta**q``.

    The stiffness is ``locked_stiffness`` below ``threshold_displacement`` and the
    tangent ``q k_a delta**(q-1)`` above it. ``q = 1`` is a linear spring of stiffness
    ``k_a``; a huge threshold makes the actuator constant. Units follow the actuated
    joint: N, m and N/m for a linear actuator (prismatic joint); N·m, rad and
    N·m/rad for a rotary one (revolute joint).
    """

    locked_stiffness: Positive
    k_a: Positive
    q: Annotated[Positive, Field(le=1.0)]
    threshold_displacement: NonNegative


class GuideModel(PartModel):
    """Linear guide on a prismatic joint (Table 3, eq. 3a), five springs at the block."""

    roll: Positive
    pitch: Positive
    yaw: Positive
    lateral: Positive
    vertical: Positive

    def stiffnesses(self) -> FloatArray:
        """Stiffness of each constrained direction, in the order of :mod:`.chain`."""
        return np.array([self.roll, self.pitch, self.yaw, self.lateral, self.vertical])


class BearingModel(PartModel):
    """Linear bearing on a cylindrical joint (Table 3, eq. 3b), four springs."""

    tilt_lateral: Positive
    tilt_vertical: Positive
    radial_lateral: Positive
    radial_vertical: Positive

    def stiffnesses(self) -> FloatArray:
        """Stiffness of each constrained direction, in the order of :mod:`.chain`."""
        return np.array(
            [self.tilt_lateral, self.tilt_vertical, self.radial_lateral, self.radial_vertical]
        )


class RevoluteModel(PartModel):
    """Rotary bearing of a revolute joint (axisymmetric), five springs."""

    tilt: Positive
    axial: Positive
    radial: Positive

    def stiffnesses(self) -> FloatArray:
        """Stiffness of each constrained direction, in the order of :mod:`.chain`:
        tilt about e2, e3; axial along e1; radial along e2, e3."""
        return np.array([self.tilt, self.tilt, self.axial, self.radial, self.radial])


#: Largest angle a U or S joint's range may have [rad]: a half turn (beyond it the
#: value is likely in degrees).
MAX_JOINT_ANGLE = float(np.pi)


class _AngleLimited(PartModel):
    """A joint part with an optional largest tilt angle ``max_angle`` [rad]."""

    max_angle: Annotated[Positive, Field(le=MAX_JOINT_ANGLE)] | None = None


class UniversalModel(_AngleLimited):
    """Universal joint: radial (e1, e2) and axial (e3) [N/m], torsion about e3 [N·m/rad]."""

    radial: Positive
    axial: Positive
    torsion: Positive

    def stiffnesses(self) -> FloatArray:
        """Stiffness of each constrained direction, in the order of :mod:`.chain`:
        translation e1, e2, e3; rotation e3."""
        return np.array([self.radial, self.radial, self.axial, self.torsion])


class SphericalModel(_AngleLimited):
    """Spherical joint: axial (e1, along its link) and radial (e2, e3) [N/m]."""

    axial: Positive
    radial: Positive

    def stiffnesses(self) -> FloatArray:
        """Stiffness of each constrained direction, in the order of :mod:`.chain`:
        translation e1, e2, e3."""
        return np.array([self.axial, self.radial, self.radial])


def part_units(model: type[BaseModel]) -> dict[str, str]:
    """SI unit of each field of a part, for reports and tables."""
    units: dict[type[BaseModel], dict[str, str]] = {
        SectionModel: {
            "young_modulus": "Pa",
            "shear_modulus": "Pa",
            "area": "m^2",
            "torsion_constant": "m^4",
            "inertia_y": "m^4",
            "inertia_z": "m^4",
        },
        GuideModel: {
            "roll": "N·m/rad",
            "pitch": "N·m/rad",
            "yaw": "N·m/rad",
            "lateral": "N/m",
            "vertical": "N/m",
        },
        BearingModel: {
            "tilt_lateral": "N·m/rad",
            "tilt_vertical": "N·m/rad",
            "radial_lateral": "N/m",
            "radial_vertical": "N/m",
        },
        RevoluteModel: {"tilt": "N·m/rad", "axial": "N/m", "radial": "N/m"},
        UniversalModel: {
            "radial": "N/m",
            "axial": "N/m",
            "torsion": "N·m/rad",
            "max_angle": "rad",
        },
        SphericalModel: {"axial": "N/m", "radial": "N/m", "max_angle": "rad"},
    }
    return dict(units.get(model, {}))


JointPart = GuideModel | BearingModel | RevoluteModel | UniversalModel | SphericalModel


def joint_springs(part: JointPart | None) -> FloatArray | None:
    """A joint part's spring stiffnesses, or None for a rigid joint (no part given)."""
    return None if part is None else part.stiffnesses()
