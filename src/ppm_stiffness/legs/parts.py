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

Masses (optional, for natural frequencies: :mod:`ppm_stiffness.dynamics`). A link's
section may carry its ``mass`` [kg], the distance of its centre of mass from one of its
ends, ``mass_centre`` [m] from ``mass_centre_from`` (``"start"``, the end nearer the base
along the chain, the default, or ``"end"``; without ``mass_centre``: the middle of the
link's current length), and
its inertia about the centre of mass, ``inertia_transverse`` (about any axis normal to
the link) and ``inertia_axial`` (about the link) [kg·m^2] (default: a uniform slender
rod of the current length, ``m L^2 / 12``, spin neglected). An actuator may carry the
moving parts of its drive: ``carriage_mass`` [kg], a body at the actuated joint moving
with its output, and ``rotor_inertia`` [kg·m^2] with ``gear_ratio`` (motor rotation per
unit of the actuated coordinate: rad/rad for a rotary actuator, rad/m for a linear one,
e.g. 2 pi / lead of a ball screw), reflected to the actuated coordinate as
``rotor_inertia * gear_ratio^2``. Masses are in kg, inertias in kg·m^2: a mass beyond
:data:`MAX_MASS` or a radius of gyration ``sqrt(I / m)`` beyond
:data:`~ppm_stiffness.legs.base.MAX_LENGTH` is refused naming the likely unit mistake
(g, kg·mm^2), and so is a nonzero mass below :data:`MIN_MASS`. The leg
(:class:`~ppm_stiffness.legs.base.LegModel`) checks what needs its lengths: a link's
density against its section (:func:`check_density`, :data:`MAX_LINK_DENSITY`), its
centre of mass within the leg, a rotor's reflection (:data:`MAX_REFLECTED`) and, in
a design with a platform mass, a carriage's mass against it
(:func:`check_mass_ratio`, :data:`MAX_CARRIAGE_RATIO`).
"""

from __future__ import annotations

import math
import numbers
import sys
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    ValidationInfo,
    field_validator,
    model_validator,
)
from pydantic_core import PydanticCustomError

from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.legs.chain import JointMass, LinkMass


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
#: Largest mass of one body of a design [kg] (10 t): above, grams are likely.
MAX_MASS = 1e4
#: Smallest mass of a body that has one [kg] (a milligram): below, no part of a machine
#: (a 0 is a massless part, allowed where a mass may be 0).
MIN_MASS = 1e-6
#: Largest density of a solid [kg/m^3]: above any material's (osmium, 22 590 kg/m^3).
MAX_DENSITY = 25_000.0
#: Largest mass of a link per volume of its section over its longest length [kg/m^3]:
#: ten times the densest material's. A link's body may carry a motor, a nut or a
#: housing on a thin tube (the shipped examples reach 3.3e4 kg/m^3), but a mass typed
#: in grams is 1000 times a material's density (7.85e6 for steel).
MAX_LINK_DENSITY = 10 * MAX_DENSITY
#: Largest mass (linear actuator) [kg] or inertia (rotary) [kg·m^2] a rotor may reflect
#: onto its actuated coordinate (``rotor_inertia * gear_ratio^2``): the heaviest body
#: of a design (:data:`MAX_MASS`), at 1 m for a rotary one.
MAX_REFLECTED = MAX_MASS
#: Largest radius of gyration ``sqrt(I / m)`` of a body [m]: the largest length of a
#: design (:data:`ppm_stiffness.legs.base.MAX_LENGTH`, repeated here to avoid an import
#: cycle). Above, an inertia in kg·mm^2 is likely.
MAX_GYRATION = 10.0
#: Largest carriage mass of an actuator per platform mass: a carriage moves with its
#: leg's end, a share of the platform it carries (the shipped examples: 0.4 to 0.9);
#: a carriage mass typed in grams is 400 to 900 times its platform's there.
MAX_CARRIAGE_RATIO = 100.0
#: Largest rotor inertia [kg·m^2] of an actuator (a motor of some 100 kW): above, an
#: inertia in kg·mm^2 is likely.
MAX_ROTOR_INERTIA = 1.0


def check_mass(key: str, value: float) -> float:
    """Refuse a mass beyond :data:`MAX_MASS`, naming the likely unit mistake (g), or a
    nonzero one below :data:`MIN_MASS` (naming t where that is plausible)."""
    if value > MAX_MASS:
        raise ValueError(
            f"{key} = {value:g}: masses in design files are in kg (<= {MAX_MASS:g} kg); "
            f"did you mean {value * 1e-3:.6g} (g)?"
        )
    if 0 < value < MIN_MASS:
        tonnes = value * 1e3
        hint = f"; did you mean {tonnes:.6g} (t)?" if tonnes >= MIN_MASS else ""
        raise ValueError(
            f"{key} = {value:g}: implausible mass, below {MIN_MASS:g} kg (a milligram; "
            f"no part of a machine is lighter; 0 is a massless part){hint}"
        )
    return value


def check_density(key: str, mass: float, volume: float, body: str, limit: float, why: str) -> None:
    """Refuse a body whose density ``mass / volume`` exceeds ``limit`` [kg/m^3] as a mass
    in grams (the platform's solid and each link's body share this check).

    Parameters
    ----------
    key : str
        The mass's key, which starts the message.
    mass : float [kg]
    volume : float [m^3]
        The body's volume (or the one its density is measured against).
    body : str
        What the volume is, for the message (``"a cylinder of 0.002 m^3"``).
    limit : float [kg/m^3]
    why : str
        What the limit is (``"denser than any material"``).
    """
    density = mass / volume
    if density > limit:
        raise ValueError(
            f"{key} = {mass:g}: implausible density: {body} would be {density:.3g} kg/m^3, "
            f"above {limit:g} ({why}); masses are in kg: did you mean {mass * 1e-3:.6g} (g)?"
        )


def check_mass_ratio(key: str, mass: float, reference: float, body: str, limit: float) -> None:
    """Refuse a mass more than ``limit`` times the mass of a body it goes with (a
    carriage against the platform it moves) as a mass in grams, as :func:`check_density`
    does against a volume.

    Parameters
    ----------
    key : str
        The mass's key, which starts the message.
    mass, reference : float [kg]
        The mass checked and the one it is measured against; a reference below
        :data:`MIN_MASS` is refused on its own (:func:`check_mass`), and nothing is
        measured against it.
    body : str
        What the reference is, for the message (``"the platform's mass"``).
    limit : float
        The largest plausible ratio ``mass / reference``.
    """
    if reference >= MIN_MASS and mass > limit * reference:
        raise ValueError(
            f"{key} = {mass:g}: implausible mass: {mass / reference:.3g} times {body} "
            f"({reference:g} kg), above {limit:g}; masses are in kg: did you mean "
            f"{mass * 1e-3:.6g} (g)?"
        )


def check_gyration(key: str, inertia: float, mass: float) -> None:
    """Refuse an inertia whose radius of gyration ``sqrt(I / m)`` exceeds
    :data:`MAX_GYRATION`, naming the likely unit mistake (kg·mm^2)."""
    if mass > 0 and inertia > mass * MAX_GYRATION**2:
        raise ValueError(
            f"{key} = {inertia:g}: inertias in design files are in kg·m^2 (radius of "
            f"gyration sqrt(I / m) = {math.sqrt(inertia / mass):.3g} m > "
            f"{MAX_GYRATION:g} m); did you mean {inertia * 1e-6:.6g} (kg·mm^2)?"
        )


class PartModel(BaseModel):
    """Base of every design record: unknown keys are errors, values are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True)


#: The fields of :class:`SectionModel` that are the beam's section (the others are its
#: optional mass).
SECTION_FIELDS = (
    "young_modulus",
    "shear_modulus",
    "area",
    "torsion_constant",
    "inertia_y",
    "inertia_z",
)


class SectionModel(PartModel):
    """A link's material and section (paper Table 2) [Pa, m^2, m^4], and optionally its
    mass [kg], centre of mass [m] and inertia [kg·m^2] (module doc)."""

    young_modulus: Positive
    shear_modulus: Positive
    area: Positive
    torsion_constant: Positive
    inertia_y: Positive
    inertia_z: Positive
    mass: NonNegative | None = None
    mass_centre: NonNegative | None = None
    mass_centre_from: Literal["start", "end"] | None = None
    inertia_transverse: NonNegative | None = None
    inertia_axial: NonNegative | None = None

    @field_validator("mass")
    @classmethod
    def _mass_in_kg(cls, v: float | None) -> float | None:
        return v if v is None else check_mass("mass", v)

    @field_validator("mass_centre")
    @classmethod
    def _centre_in_m(cls, v: float | None) -> float | None:
        if v is not None and v > MAX_GYRATION:
            raise ValueError(
                f"mass_centre = {v:g}: lengths in design files are in metres "
                f"(<= {MAX_GYRATION:g} m); did you mean {v / 1000:.6g}?"
            )
        return v

    @model_validator(mode="after")
    def _mass_fields(self) -> SectionModel:
        """A centre of mass or an inertia needs the mass; inertias in kg·m^2."""
        given = [
            k
            for k in ("mass_centre", "inertia_transverse", "inertia_axial")
            if getattr(self, k) is not None
        ]
        if self.mass is None:
            if self.mass_centre_from is not None:
                given.append("mass_centre_from")
            if given:
                names = ", ".join(given)
                raise ValueError(f"{names} given without the link's mass: give mass [kg]")
            return self
        for key in ("inertia_transverse", "inertia_axial"):
            value = getattr(self, key)
            if value is not None:
                check_gyration(key, value, self.mass)
        return self

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
        return BeamSection(**{k: getattr(self, k) for k in SECTION_FIELDS})

    def link_mass(self) -> LinkMass | None:
        """The link's mass properties for its chain element, or None (no mass given)."""
        if self.mass is None:
            return None
        return LinkMass(
            mass=self.mass,
            centre=self.mass_centre,
            from_end=self.mass_centre_from == "end",
            transverse=self.inertia_transverse,
            axial=0.0 if self.inertia_axial is None else self.inertia_axial,
        )


#: The two stiffnesses of an actuator law: one parameter under a linear law (q = 1).
ACTUATOR_STIFFNESSES = ("locked_stiffness", "k_a")


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class ActuatorModel(PartModel):
    """Actuator law (eq. 20-21): ``G = k_a * delta**q``.

    For ``q < 1`` the stiffness is ``locked_stiffness`` while the displacement is at
    most ``threshold_displacement`` (the force at most ``k_a delta_th^q``: the unloaded
    K, small loads) and the tangent ``q k_a delta**(q-1)`` above it; a threshold at
    the actuator's stroke makes it constant (a leg refuses one beyond its stroke as a
    unit slip). ``q = 1`` is a linear spring: its tangent is ``k_a``
    at every load, so ``locked_stiffness`` and ``k_a`` are one stiffness. A file may
    give either (the other follows) or both equal; two different values are refused,
    and setting either by name (:meth:`~ppm_stiffness.design.schema.Design.
    with_parameters`) sets both. Units follow the actuated joint: N, m and N/m for a
    linear actuator (prismatic joint); N·m, rad and N·m/rad for a rotary one
    (revolute joint).
    """

    locked_stiffness: Positive
    k_a: Positive
    q: Annotated[Positive, Field(le=1.0)]
    threshold_displacement: NonNegative
    carriage_mass: NonNegative | None = None
    rotor_inertia: NonNegative | None = None
    gear_ratio: Positive | None = None

    @model_validator(mode="before")
    @classmethod
    def _one_linear_stiffness(cls, data: Any) -> Any:
        """Under a linear law (q = 1) ``locked_stiffness`` and ``k_a`` are one stiffness:
        either given alone gives both; two different values are refused."""
        if not isinstance(data, dict) or not _is_number(q := data.get("q")) or q != 1:
            return data
        locked, k_a = (data.get(k) for k in ACTUATOR_STIFFNESSES)
        if locked is None and _is_number(k_a):
            return {**data, "locked_stiffness": k_a}
        if k_a is None and _is_number(locked):
            return {**data, "k_a": locked}
        if _is_number(locked) and _is_number(k_a) and locked != k_a:
            raise ValueError(
                f"k_a = {k_a:g} and locked_stiffness = {locked:g} differ, but with q = 1 "
                "(a linear actuator) they are one stiffness, used locked and under load: "
                "give one of them, or both equal"
            )
        return data

    @field_validator("carriage_mass")
    @classmethod
    def _mass_in_kg(cls, v: float | None) -> float | None:
        return v if v is None else check_mass("carriage_mass", v)

    @field_validator("rotor_inertia")
    @classmethod
    def _rotor_in_si(cls, v: float | None) -> float | None:
        if v is not None and v > MAX_ROTOR_INERTIA:
            raise ValueError(
                f"rotor_inertia = {v:g}: inertias in design files are in kg·m^2 (a rotor "
                f"<= {MAX_ROTOR_INERTIA:g} kg·m^2); did you mean {v * 1e-6:.6g} (kg·mm^2)?"
            )
        return v

    @model_validator(mode="after")
    def _gear_needs_rotor(self) -> ActuatorModel:
        if self.gear_ratio is not None and self.rotor_inertia is None:
            raise ValueError("gear_ratio given without rotor_inertia [kg·m^2]")
        return self

    def moving_parts(self) -> JointMass | None:
        """The drive's moving parts for the actuated joint of a chain, or None.

        The rotor's inertia is reflected to the actuated coordinate:
        ``rotor_inertia * gear_ratio^2`` (a missing ``gear_ratio`` is 1, direct drive;
        a linear actuator's leg type requires it).
        """
        if self.carriage_mass is None and self.rotor_inertia is None:
            return None
        ratio = 1.0 if self.gear_ratio is None else self.gear_ratio
        rotor = 0.0 if self.rotor_inertia is None else self.rotor_inertia * ratio**2
        return JointMass(
            mass=0.0 if self.carriage_mass is None else self.carriage_mass, rotor=rotor
        )


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
            "mass": "kg",
            "mass_centre": "m",
            "inertia_transverse": "kg·m^2",
            "inertia_axial": "kg·m^2",
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
    # other parts (a flexure hinge's) state their units as a class attribute UNITS
    return dict(units.get(model, getattr(model, "UNITS", {})))


JointPart = GuideModel | BearingModel | RevoluteModel | UniversalModel | SphericalModel


def joint_springs(part: JointPart | None) -> FloatArray | None:
    """A joint part's spring stiffnesses, or None for a rigid joint (no part given)."""
    return None if part is None else part.stiffnesses()
