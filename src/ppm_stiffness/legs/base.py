"""What every leg type provides: inverse kinematics, limits, constraints and its chain.

A leg type is one module of :mod:`ppm_stiffness.legs.types` defining a subclass of
:class:`LegModel` with a ``type`` literal (``"PPR"``, ``"UPS"``, ...), its geometry and
parts as validated fields, and these methods:

- :meth:`LegModel.solve`: inverse kinematics at 6-D poses (..., 6) (x, y, z, rx, ry,
  rz; :mod:`ppm_stiffness.core.pose`), returning a :class:`LegPose` (named points,
  joint coordinates, a mask of solvable poses);
- :meth:`LegModel.chain`: the joint chain at those poses (:mod:`.chain`);
- :meth:`LegModel.limits`: the admissible range of each joint coordinate;
- :meth:`LegModel.constraint`: the leg's closure residuals and their wrenches, zero
  where the pose is one the leg can reach (a leg of fewer than six freedoms constrains
  the platform: a P-R-S leg keeps its platform point in the plane of its revolute).

Nothing outside a leg type's module knows its name: the design schema, the model,
the statics, the FE model and the pictures go through these methods only.

Platform points. Leg i is attached to the platform at a point b_i of the platform
frame (:meth:`LegModel.attachment`), at ``p + R b_i`` in F_b. A planar leg
(:class:`PlanarLegModel`) gives it as ``b_i = -platform_radius (cos psi, sin psi, 0)``
(the paper's ``D_i = P - r (cos(psi + phi), sin(psi + phi), 0)``). Points of a
:class:`LegPose` are relative to P with the axes of F_b [m]; joint coordinates are SI
(m, rad).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Annotated, Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike
from pydantic import ValidationInfo, field_validator, model_validator

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import (
    DesignError,
    ImplausibleDesignWarning,
    UnreachablePoseError,
)
from ppm_stiffness.legs.chain import Element, Joint, Link, actuator_screw
from ppm_stiffness.legs.joint_kinds import joint_kind
from ppm_stiffness.legs.parts import (
    MAX_CARRIAGE_RATIO,
    MAX_LINK_DENSITY,
    MAX_REFLECTED,
    ActuatorModel,
    Finite,
    PartModel,
    Positive,
    SectionModel,
    StrictNumber,
    check_density,
    check_mass_ratio,
)

#: Largest length a design file may give [m]: beyond it, a length in mm is likely.
MAX_LENGTH = 10.0
#: Largest angle a design file may give [rad]: beyond it, degrees are likely.
MAX_ANGLE = 2 * math.pi
#: Relative round-off allowed at a joint limit (of the limit's magnitude): a pose placed
#: exactly at a stroke end computes its length a few ulp past it, and stays reachable.
LIMIT_RTOL = 1e-12


def within_limits(q: ArrayLike, lo: float, hi: float) -> FloatArray:
    """Mask of joint coordinates ``q`` in ``[lo, hi]`` up to round-off.

    The one limit test of single poses (:meth:`LegModel.check`) and maps
    (:meth:`LegModel.reachable`): each end is widened by :data:`LIMIT_RTOL` times
    ``max(|lo|, |hi|)`` (finite ends only), so a pose exactly at a stroke end is
    reachable whichever way its last bit rounds.

    Parameters
    ----------
    q : array_like (...)
        Joint coordinate values [m or rad].
    lo, hi : float
        The admissible range [m or rad].

    Returns
    -------
    ndarray of bool (...)
    """
    ends = [abs(v) for v in (lo, hi) if math.isfinite(v)]
    tol = LIMIT_RTOL * max(ends, default=0.0)
    q = np.asarray(q, dtype=float)
    return np.asarray((q >= lo - tol) & (q <= hi + tol))


#: A working mode (+1 or -1) of a leg whose inverse kinematics has two solutions; an
#: integer, never a boolean (``branch = true`` is refused, as every coerced number).
Branch = Annotated[Literal[-1, 1], StrictNumber]


def check_plausible(key: str, value: float, unit: str) -> None:
    """Refuse a length beyond :data:`MAX_LENGTH` or an angle beyond :data:`MAX_ANGLE`,
    naming the likely unit mistake (mm, degrees).

    Parameters
    ----------
    key : str
        The field's name, which starts the message (``"alpha = 90: ..."``).
    value : float
        The value [m or rad].
    unit : {"m", "rad"}
        Its SI unit; any other unit is not checked.

    Raises
    ------
    ValueError
        ``"<key> = <value>: lengths in design files are in metres (|length| <= 10 m);
        did you mean <value / 1000>?"`` (or the radian version).
    """
    if unit == "rad" and abs(value) > MAX_ANGLE:
        raise ValueError(
            f"{key} = {value:g}: angles in design files are in radians "
            f"(|angle| <= 2 pi); did you mean {math.radians(value):.6g}?"
        )
    if unit == "m" and abs(value) > MAX_LENGTH:
        raise ValueError(
            f"{key} = {value:g}: lengths in design files are in metres "
            f"(|length| <= {MAX_LENGTH:g} m); did you mean {value / 1000:.6g}?"
        )


@dataclass(frozen=True)
class Coordinate:
    """A joint coordinate with limits: its label and SI unit ("m" or "rad")."""

    label: str
    unit: str


@dataclass(frozen=True)
class BaseFeature:
    """What a leg is fixed to on the base, for pictures (fixed in F_b).

    Attributes
    ----------
    kind : {"rail", "pivot"}
        A rail for a base prismatic joint, a pivot for a base revolute.
    point : ndarray (3,) [m]
        Absolute position in F_b: the rail's origin (actuator coordinate 0) or the
        pivot.
    axis : ndarray (3,)
        Unit rail direction in F_b (a rail); zero for a pivot.
    stroke : tuple of float or None
        A rail: the range of positions along ``axis`` from ``point`` [m] that the
        actuator travels. An actuated pivot: the range of the actuated angle from the
        x axis of F_b [rad]. None when the leg's limits say nothing of the base joint.
    """

    kind: Literal["rail", "pivot"]
    point: FloatArray
    axis: FloatArray
    stroke: tuple[float, float] | None = None


@dataclass(frozen=True)
class LegPose:
    """A leg at poses: the result of :meth:`LegModel.solve`.

    Attributes
    ----------
    poses : ndarray (..., 6)
        (x, y, z [m], rx, ry, rz [rad]) of P in F_b (:mod:`ppm_stiffness.core.pose`).
    points : dict of str to ndarray (..., 3)
        Named points of the leg relative to P, axes of F_b [m], from the base to the
        platform point ``"D"`` (the order in which a picture joins them).
    coordinates : dict of str to ndarray (...)
        Joint coordinates [m or rad], the keys of :meth:`LegModel.limits`.
    solvable : ndarray of bool (...)
        The inverse kinematics has a real solution (elsewhere the points are finite
        but meaningless).
    """

    poses: FloatArray
    points: dict[str, FloatArray]
    coordinates: dict[str, FloatArray]
    solvable: FloatArray = field(default_factory=lambda: np.array(True))


def planar(v: ArrayLike) -> FloatArray:
    """Append a zero z component to (..., 2) arrays."""
    a = np.asarray(v, dtype=float)
    return np.concatenate([a, np.zeros(a.shape[:-1] + (1,))], axis=-1)


def unit_planar(angle: ArrayLike) -> FloatArray:
    """``(cos a, sin a, 0)`` for angles (...) [rad]; shape (..., 3)."""
    a = np.asarray(angle, dtype=float)
    return np.stack([np.cos(a), np.sin(a), np.zeros_like(a)], axis=-1)


def cross_z(a: FloatArray, b: FloatArray) -> FloatArray:
    """z component of ``a x b`` for (..., 3) arrays."""
    return np.asarray(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])


@dataclass(frozen=True)
class BarPairGeometry:
    """Two bars with ball joints at both ends between a chain's last body and the
    platform (:meth:`LegModel.bar_pair`), at k configurations.

    Attributes
    ----------
    chain : sequence of Joint and Link
        The leg's chain from the base to the body carrying the bars' near ends.
    near, far : ndarray (..., 2, 3) [m]
        The bars' ends on that body and on the platform, relative to P, axes of F_b.
    compliance : float [m/N]
        One bar's axial compliance ``1/k_bar`` (its length, its corner springs); 0:
        rigid.
    """

    chain: Sequence[Element]
    near: FloatArray
    far: FloatArray
    compliance: float


class LegModel(PartModel):
    """Base of every leg type (module doc). Field shared by all legs:

    actuator : ActuatorModel or None
        The law of the leg's actuated joint (linear or rotary, by the joint); required
        for a leg with an actuated joint, refused for a passive constraining leg (a
        chain leg without one, :meth:`is_actuated`).
    """

    type: str
    actuator: ActuatorModel | None = None

    #: Joint coordinates that have limits: name -> Coordinate.
    COORDINATES: ClassVar[dict[str, Coordinate]] = {}
    #: SI unit of each geometry field ("m", "rad", "1"); parts carry their own.
    UNITS: ClassVar[dict[str, str]] = {}
    #: The key of :data:`COORDINATES` that the actuator drives (its stroke).
    ACTUATED_COORDINATE: ClassVar[str] = "rho"
    #: Fields that choose among discrete options (working modes), not continuous
    #: parameters: left out of the parameter names that calibration and sweeps vary.
    DISCRETE_FIELDS: ClassVar[frozenset[str]] = frozenset()
    #: Kind of the actuated joint ("P": linear actuator, "R": rotary); its record
    #: (:func:`~ppm_stiffness.legs.joint_kinds.joint_kind`) gives its units.
    ACTUATED_KIND: ClassVar[str] = "P"
    #: One line for listings: what the letters mean, which joint is actuated.
    DESCRIPTION: ClassVar[str] = ""
    #: The task coordinates of a design whose legs are all of this type (the pose
    #: coordinates the user gives; the others follow from the legs' constraints).
    TASK_COORDINATES: ClassVar[tuple[str, ...]] = ("x", "y", "z", "rx", "ry", "rz")

    @field_validator("*")
    @classmethod
    def _plausible_units(cls, value: Any, info: ValidationInfo) -> Any:
        """Refuse values that are impossible in SI and name the likely unit mistake (a
        field check, so that it is reported with the leg's other errors)."""
        unit = cls.UNITS.get(str(info.field_name))
        if unit is not None:
            for v in value if isinstance(value, tuple) else (value,):
                if isinstance(v, (int, float)):
                    check_plausible(str(info.field_name), v, unit)
        return value

    @model_validator(mode="after")
    def _actuator_given(self) -> LegModel:
        """An actuated leg has its actuator's law; a passive constraining leg has none."""
        if self.actuator is None and self.is_actuated():
            raise ValueError(
                "actuator: the law of the leg's actuated joint is required (a table: "
                "locked_stiffness, q, threshold_displacement, ...)"
            )
        if self.actuator is not None and not self.is_actuated():
            raise ValueError(
                "actuator: this leg has no actuated joint (a passive constraining leg), "
                "so it has no actuator table; remove it, or mark its driven R or P joint "
                "actuated = true"
            )
        return self

    def is_actuated(self) -> bool:
        """Whether the leg has an actuated joint (every coded leg type; a chain leg
        without one is a passive constraining leg, as a Tricept's central leg)."""
        return True

    def law(self, what: str = "this") -> ActuatorModel:
        """The leg's actuator law.

        Parameters
        ----------
        what : str
            What needs it, for the message (``"the loaded mode"``).

        Raises
        ------
        DesignError
            For a passive constraining leg (no actuated joint): ``"<what> needs an
            actuator on every leg; a passive leg has none"``.
        """
        if self.actuator is None:
            raise DesignError(
                f"{what} needs an actuator on every leg; a passive constraining leg "
                f"({self.architecture_name()}, no actuated joint) has none"
            )
        return self.actuator

    def locked_stiffness(self) -> float:
        """The actuator's locked stiffness [N/m or N·m/rad]; ``inf`` for a passive leg
        (no actuator column: the value enters nothing, and 1/inf = 0 keeps every
        compliance finite)."""
        return math.inf if self.actuator is None else self.actuator.locked_stiffness

    def parallel_stiffness(self) -> float:
        """The elastic stiffness acting in parallel with the drive on the actuated
        freedom (a flexure hinge driven by a piezo lever) [N/m or N·m/rad], 0 without
        one. It rests at the unloaded pose: the joint carries ``G + k_h delta`` (the
        drive's force plus the flexure's) at a displacement delta of that freedom."""
        return 0.0

    @model_validator(mode="after")
    def _drive_ratio(self) -> LegModel:
        """A linear actuator's rotor needs its gear ratio [rad/m] (no default: 1 rad/m
        is no drive)."""
        law = self.actuator
        if law is None:
            return self
        linear = joint_kind(self.actuated_kind()).linear
        if linear and law.rotor_inertia is not None and law.gear_ratio is None:
            raise ValueError(
                "actuator.rotor_inertia of a linear actuator needs actuator.gear_ratio "
                "[rad/m], the motor's rotation per metre of travel (2 pi / lead of a "
                "ball screw)"
            )
        return self

    @model_validator(mode="after")
    def _threshold_within_stroke(self) -> LegModel:
        """An actuator's ``threshold_displacement`` at most its stroke (the range of its
        coordinate): no deflection exceeds it, so a larger value is a unit slip (mm, µm
        typed as m)."""
        if self.actuator is None:
            return self
        lo, hi = self.limits().get(self.ACTUATED_COORDINATE, (-math.inf, math.inf))
        stroke, threshold = hi - lo, self.actuator.threshold_displacement
        if not math.isfinite(stroke) or threshold <= stroke:
            return self
        unit = joint_kind(self.actuated_kind()).actuator_units()[1]
        slip = (
            f"did you mean {math.radians(threshold):.6g} (deg)?"
            if unit == "rad"
            else f"did you mean {threshold / 1000:.6g} (mm)?"
            if threshold / 1000 <= stroke
            else f"did you mean {threshold * 1e-6:.6g} (µm)?"
        )
        raise ValueError(
            f"actuator.threshold_displacement = {threshold:g}: beyond the actuator's "
            f"stroke ({stroke:.4g} {unit}), which no deflection exceeds (an actuator "
            f"locked under every load is q = 1 with k_a = locked_stiffness); {slip}"
        )

    @model_validator(mode="after")
    def _carriage_mass(self, info: ValidationInfo) -> LegModel:
        """A carriage at most :data:`~ppm_stiffness.legs.parts.MAX_CARRIAGE_RATIO` times
        the platform's mass (validation context ``platform_mass`` [kg], when the design
        gives one)."""
        carriage = None if self.actuator is None else self.actuator.carriage_mass
        platform = (info.context or {}).get("platform_mass")
        if carriage is not None and isinstance(platform, float):
            check_mass_ratio(
                "actuator.carriage_mass",
                carriage,
                platform,
                "the platform's mass",
                MAX_CARRIAGE_RATIO,
            )
        return self

    @model_validator(mode="after")
    def _reflected_rotor(self) -> LegModel:
        """A rotor may not reflect more than :data:`~ppm_stiffness.legs.parts.
        MAX_REFLECTED` (kg, or kg·m^2 for a rotary actuator) onto its coordinate."""
        law = self.actuator
        if law is None or law.rotor_inertia is None or law.gear_ratio is None:
            return self
        reflected = law.rotor_inertia * law.gear_ratio**2
        if reflected > MAX_REFLECTED:
            unit = "kg" if joint_kind(self.actuated_kind()).linear else "kg·m^2"
            cm2 = law.rotor_inertia * 1e-4
            ratio = (
                "2 pi / lead [rad/m] (1257 for a 5 mm lead)"
                if unit == "kg"
                else "motor turns per joint turn [rad/rad]"
            )
            raise ValueError(
                f"actuator.gear_ratio = {law.gear_ratio:g} with actuator.rotor_inertia = "
                f"{law.rotor_inertia:g}: implausible reflected inertia, rotor_inertia * "
                f"gear_ratio^2 = {reflected:.3g} {unit} on the actuated coordinate (<= "
                f"{MAX_REFLECTED:g} {unit}); did you mean rotor_inertia = {cm2:.6g} "
                f"(kg·cm^2, reflecting {cm2 * law.gear_ratio**2:.3g} {unit})? gear_ratio "
                f"is {ratio}"
            )
        return self

    @model_validator(mode="after")
    def _link_bodies(self) -> LegModel:
        """Each link body's density against its section (a mass in grams) and its centre
        of mass within the leg (module doc of :mod:`ppm_stiffness.dynamics.links`)."""
        ranges = self.link_length_ranges()
        if any(not 0 < shortest <= longest for shortest, longest in ranges.values()):
            return self  # the leg type's own check of its lengths names what is wrong
        longest_leg = sum(longest for _, longest in ranges.values())
        for name, (shortest, longest) in ranges.items():
            section = getattr(self, name)
            if not isinstance(section, SectionModel) or section.mass is None:
                continue
            check_density(
                f"{name}.mass",
                section.mass,
                section.area * longest,
                f"a link of section {section.area:.3g} m^2 and {longest:.4g} m (its longest)",
                MAX_LINK_DENSITY,
                "ten times the densest material: a motor or a nut on a thin tube stays below",
            )
            if section.mass_centre is not None:
                _check_centre(name, section, shortest, longest, longest_leg)
        return self

    def link_length_ranges(self) -> dict[str, tuple[float, float]]:
        """The shortest and longest length [m] over the stroke of each link, by the name
        of its section's field (``{"rod": (0.035, 0.125)}``); a leg type that has links
        overrides it (the default: none, so its link bodies are not checked)."""
        return {}

    def drive_units(self) -> dict[str, str]:
        """SI units of the actuator's mass fields (carriage, rotor, gear ratio)."""
        ratio = "rad/m" if joint_kind(self.actuated_kind()).linear else "rad/rad"
        return {"carriage_mass": "kg", "rotor_inertia": "kg·m^2", "gear_ratio": ratio}

    @classmethod
    def pattern_copies(cls, raw: dict[str, Any]) -> list[dict[str, Any]]:
        """The legs a raw leg table stands for: itself, or the copies its ``pattern``
        writes (a leg type that has patterns overrides this).

        Raises
        ------
        ValueError
            A ``pattern`` on a leg type that has none.
        """
        if "pattern" in raw:
            raise ValueError(
                f'a {raw.get("type")} leg has no pattern (a chain leg\'s: type = "chain")'
            )
        return [raw]

    def parameter_items(self) -> list[tuple[str, Any]]:
        """The leg's parameters for tables, by dotted key within the leg: a part (a
        model, whose fields the table spreads) or a value; its ``type`` left out."""
        return [(key, value) for key, value in self if key != "type"]

    def joint_list(self, home: FloatArray) -> dict[str, Any] | None:
        """This leg written as a joint-list leg's table (``type = "chain"``,
        docs/legs.md) at the design's home pose (6,), or None where the leg type does not
        write one yet."""
        return None

    def link_mass(self) -> float:
        """The physical mass [kg] of the leg's links: every beam section's ``mass``."""
        total = 0.0
        for _, part in self.parameter_items():
            mass = getattr(part, "mass", None)
            if isinstance(mass, float) and hasattr(part, "young_modulus"):
                total += mass
        return total

    def field_path(self, keys: list[str]) -> list[str | int]:
        """The path through the leg's fields (and list indices) of a parameter's dotted
        keys within the leg (``["guide", "yaw"]``): the keys themselves, unless the leg
        names its parameters otherwise (a chain leg's by element name)."""
        return list(keys)

    def parameter_unit(self, key: str) -> str:
        """SI unit of a geometry value of :meth:`parameter_items` ("" if none)."""
        return self.UNITS.get(key, "")

    def architecture_name(self) -> str:
        """The leg's letters in a design's architecture (``"PPR"`` in ``"3-PPR"``)."""
        return self.type

    def actuated_kind(self) -> str:
        """Kind of the actuated joint ("P": linear actuator, "R": rotary)."""
        return self.ACTUATED_KIND

    def coordinate(self, name: str) -> Coordinate:
        """Label and unit of the joint coordinate ``name`` (a key of :meth:`limits`)."""
        return self.COORDINATES[name]

    def coordinate_names(self) -> list[str]:
        """The joint coordinates that have limits, in order."""
        return list(self.COORDINATES)

    # -- to be provided by each leg type ------------------------------------------
    def attachment(self) -> FloatArray:  # pragma: no cover - abstract
        """The platform point b (3,) of the leg in the platform frame F_p [m]."""
        raise NotImplementedError

    def solve(self, poses: ArrayLike) -> LegPose:  # pragma: no cover - abstract
        """Inverse kinematics at poses (..., 6) [m, rad]."""
        raise NotImplementedError

    def constraint(self, poses: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """The leg's closure residuals at poses (..., 6) and their wrenches.

        Returns
        -------
        residual : ndarray (..., c) [m or rad]
            Zero where the leg's joints can reach the pose; c = 0 for a leg with six
            freedoms.
        wrenches : ndarray (..., 6, c)
            ``d residual = wrenches^T t`` for a platform twist t (at P, axes of F_b):
            the unit wrenches the rigid leg exerts on the platform whatever its
            actuator does (its constraint wrenches).
        """
        shape = np.shape(poses)[:-1]
        return np.zeros(shape + (0,)), np.zeros(shape + (6, 0))

    def constraint_continued(
        self, poses: ArrayLike, start: tuple[FloatArray, FloatArray] | None
    ) -> tuple[FloatArray, FloatArray, tuple[FloatArray, FloatArray] | None]:
        """:meth:`constraint`, for a leg whose inverse kinematics is a continuation
        (a joint-list leg) continued from ``start`` (poses (n, 6) solved before and
        their joint coordinates), with what to continue from next; a leg with a closed
        form ignores ``start`` and returns None."""
        residual, wrenches = self.constraint(poses)
        return residual, wrenches, None

    def chain(self, leg_pose: LegPose) -> Sequence[Element]:  # pragma: no cover
        """The joint chain at the poses of ``leg_pose``, base to platform."""
        raise NotImplementedError

    def limits(self) -> dict[str, tuple[float, float]]:  # pragma: no cover
        """Admissible range of each joint coordinate of :data:`COORDINATES`."""
        raise NotImplementedError

    # -- shared ---------------------------------------------------------------------
    def platform_offset(self, poses: ArrayLike) -> FloatArray:
        """Platform point ``R b`` relative to P, axes of F_b, at poses (..., 6); (..., 3)."""
        return pose6.platform_offset(poses, self.attachment())

    def reachable(self, leg_pose: LegPose) -> FloatArray:
        """Mask of poses where the IK is solvable and every coordinate is in range."""
        ok = np.asarray(leg_pose.solvable, dtype=bool)
        for name, (lo, hi) in self.limits().items():
            ok = ok & within_limits(leg_pose.coordinates[name], lo, hi)
        return np.asarray(ok)

    def check(self, leg_pose: LegPose, label: str) -> None:
        """Raise :class:`UnreachablePoseError` naming the first violated limit (one pose)."""
        if not bool(np.all(leg_pose.solvable)):
            raise UnreachablePoseError(
                f"{label} ({self.type}): the platform point is out of the leg's reach "
                "(no inverse-kinematics solution)"
            )
        for name, (lo, hi) in self.limits().items():
            q = float(leg_pose.coordinates[name])
            if not within_limits(q, lo, hi):
                c = self.coordinate(name)
                scale, unit = (1e3, "mm") if c.unit == "m" else (180 / np.pi, "deg")
                raise UnreachablePoseError(
                    f"{label}: {c.label} {q * scale:.2f} {unit} outside "
                    f"[{lo * scale:.2f}, {hi * scale:.2f}] {unit}"
                )

    def actuator_screw(self, leg_pose: LegPose) -> FloatArray:
        """Unit twist of the actuated joint (..., 6): ``G = screw . w_leg``."""
        return actuator_screw(self.chain(leg_pose))

    def base_feature(self, leg_pose: LegPose) -> BaseFeature:
        """What the leg is fixed to on the base (:class:`BaseFeature`), for pictures.

        The default reads the first joint of the chain at the first pose of
        ``leg_pose``: a linear joint (every freedom a translation: a prismatic one) gives
        a rail through its point along its axis, any other a pivot at its point, without
        a stroke. Leg types override it to give the rail's origin and the actuator's
        stroke.
        """
        first = next(e for e in self.chain(leg_pose) if isinstance(e, Joint))
        pose = as_poses(leg_pose.poses).reshape(-1, 6)[0]
        point = np.asarray(first.point, dtype=float).reshape(-1, 3)[0] + pose6.position(pose)
        if joint_kind(first.kind).linear:
            axis = np.asarray(first.axis, dtype=float).reshape(-1, 3)[0]
            return BaseFeature("rail", point, axis / np.linalg.norm(axis))
        return BaseFeature("pivot", point, np.zeros(3))

    # -- optional capabilities (generic default: not offered) ------------------------
    def drawn_members(self, leg_pose: LegPose) -> tuple[list[Link], list[Joint]]:
        """Links and joints that pictures draw besides the chain's (an element's own
        parts where its chain is an equivalent one: a parallelogram's bars, crossbars
        and corner joints), at one pose, relative to P."""
        return [], []

    def moving_geometry_gap(self) -> str | None:
        """Why the loaded mode's moving geometry does not model this leg (its second-
        order terms), or None: it does."""
        return None

    def bar_pair(self, leg_pose: LegPose) -> BarPairGeometry | None:
        """A leg that ends in two two-force bars (a parallelogram with ball joints at its
        corners) for the moving geometry, which models the bars themselves: the chain up
        to the body carrying the bars' near ends, the near and far ends (..., 2, 3)
        relative to P [m] and one bar's axial compliance [m/N] (0: rigid); None for
        every other leg (the default)."""
        return None

    def reduced_form(self) -> Any | None:
        """An exact reduced form of the leg for fast batched maps, or None.

        A leg type that has one returns an object the maps know how to evaluate
        (:mod:`ppm_stiffness.maps.batch`); the default, None, sends the maps to the
        general path (IK, joint chain and bordered inverse at every pose).
        """
        return None

    def limit_half_planes(self, phi: float) -> tuple[FloatArray, FloatArray] | None:
        """The joint limits at orientation ``phi`` as half-planes, or None.

        When every joint coordinate with limits is affine in the platform position
        (x, y) at fixed phi, a leg type returns ``(normals (n, 2), offsets (n,))`` such
        that the pose (x, y, phi) is within limits iff ``normals @ (x, y) <= offsets``
        [m]; the workspace bounds are then exact (:mod:`ppm_stiffness.maps.workspace`).
        The default, None, means no such form (bounds come from sampling).
        """
        return None

    def actuator_units(self) -> tuple[str, str, str]:
        """Units of the actuator's force, displacement and stiffness."""
        return joint_kind(self.actuated_kind()).actuator_units()


def _check_centre(
    name: str, section: SectionModel, shortest: float, longest: float, leg_longest: float
) -> None:
    """Refuse a link body's centre of mass farther from its end than the leg's longest
    length over its stroke; warn of one beyond the link (module doc of
    :mod:`ppm_stiffness.dynamics.links`) but behind the start of a link that slides
    through it (a rod's centre inside its guide: ``mass_centre_from = "end"`` and a
    length that changes)."""
    centre = section.mass_centre
    assert centre is not None
    key = f"{name}.mass_centre"
    if centre > leg_longest:
        mm = f"; did you mean {centre / 1000:.6g} (mm)?" if centre > 10 * leg_longest else ""
        raise ValueError(
            f"{key} = {centre:g}: the link's centre of mass would lie outside the leg, "
            f"whose longest length over its stroke is {leg_longest:.4g} m (0 <= "
            f"mass_centre <= {leg_longest:.4g} m){mm}"
        )
    from_end = section.mass_centre_from == "end"
    sliding = longest > shortest
    if centre > shortest and not (from_end and sliding):
        where = "behind its start" if from_end else "past its end"
        warnings.warn(  # the same text for every value: one warning per optimisation
            f"{key} beyond {shortest:.4g} m puts the link's centre of mass {where} (the "
            f"link is {shortest:.4g} m long"
            + (f" at its shortest, {longest:.4g} m at its longest" if sliding else "")
            + "); the body is taken to move rigidly with that end's section; a centre "
            f"measured from the link's {'start' if from_end else 'end'} is "
            f'mass_centre_from = "{"start" if from_end else "end"}"',
            ImplausibleDesignWarning,
            stacklevel=2,
        )


class PlanarLegModel(LegModel):
    """A leg of a planar manipulator: every joint axis along z or in the plane z = 0.

    Fields (besides the actuator):

    psi : float [rad]
        Angle of the platform attachment, ``b = -platform_radius (cos psi, sin psi, 0)``
        (``D = P - r (cos(psi+phi), sin(psi+phi), 0)`` at orientation phi).
    platform_radius : float [m]

    The leg's kinematics are those of the plane: its residuals are the pose's
    out-of-plane coordinates, ``(z, n_x, n_y)`` with ``n = R e_z`` the platform's
    normal, zero exactly for the planar poses ``(x, y, 0, 0, 0, phi)``.
    """

    psi: Finite
    platform_radius: Positive

    UNITS: ClassVar[dict[str, str]] = {"psi": "rad", "platform_radius": "m"}
    TASK_COORDINATES: ClassVar[tuple[str, ...]] = ("x", "y", "rz")

    def attachment(self) -> FloatArray:
        return -self.platform_radius * unit_planar(self.psi)

    def platform_offset(self, poses: ArrayLike) -> FloatArray:
        """``D - P`` at poses (..., 6) of the plane (z = rx = ry = 0); (..., 3)."""
        phi = np.asarray(poses, dtype=float)[..., 5]
        return -self.platform_radius * unit_planar(self.psi + phi)

    def constraint(self, poses: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Residuals ``(z, n_x, n_y)`` (``n = R e_z``) and their wrenches:
        ``dz = v_z``, ``dn = omega x n``."""
        q = np.asarray(poses, dtype=float)
        n = pose6.rotation(q)[..., :, 2]
        residual = np.stack([q[..., 2], n[..., 0], n[..., 1]], axis=-1)
        wrenches = np.zeros(q.shape[:-1] + (6, 3))
        wrenches[..., 5, 0] = 1.0
        # (omega x n)_x = omega_y n_z - omega_z n_y; (omega x n)_y = omega_z n_x - omega_x n_z
        wrenches[..., 1, 1] = n[..., 2]
        wrenches[..., 2, 1] = -n[..., 1]
        wrenches[..., 2, 2] = n[..., 0]
        wrenches[..., 0, 2] = -n[..., 2]
        return residual, wrenches


def as_poses(poses: ArrayLike) -> FloatArray:
    """Poses as (..., 6) arrays; planar poses (..., 3) ``(x, y, phi)`` are read as
    ``(x, y, 0, 0, 0, phi)`` (transitional: callers that still hold planar poses)."""
    q = np.asarray(poses, dtype=float)
    if q.shape[-1:] == (3,):
        return pose6.planar_pose(q)
    return q


def planar_position(poses: ArrayLike) -> FloatArray:
    """``(x, y, 0)`` (..., 3) of poses (..., 6): P's position in the plane."""
    q = np.asarray(poses, dtype=float)
    return planar(q[..., :2])
