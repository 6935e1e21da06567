"""A leg written as a list of joints and links (``type = "chain"``): any serial leg.

The elements run from the base to the platform and are given at the design's home pose
(``[workspace]``), in F_b [m]:

- a **joint** (``joint = "R" | "P" | "C" | "U" | "S"``) at ``point``, with its axis
  ``axis`` (R, P, C; a U's first axis e1, fixed to the body before it) and a U's
  second axis ``axis2`` (e2, fixed to the body after it, normal to e1 at home); an S
  has no axis. At most one joint of the leg is ``actuated = true`` (an R or a P: the
  actuator's law acts along its freedom; none: a passive constraining leg, without an
  ``actuator`` table), with its ``stroke`` [lo, hi] [m or rad] measured from
  its home position (``lo <= 0 <= hi``; a revolute's is an angle about its own axis).
  ``springs`` are its hardware springs in its constrained directions, the part of its
  kind (:mod:`ppm_stiffness.legs.parts`: a P's ``GuideModel``, a C's ``BearingModel``,
  an R's ``RevoluteModel``, a U's ``UniversalModel``, an S's ``SphericalModel``), or one
  number [N/m or N·m/rad] for every constrained direction alike; absent, the joint is
  rigid in them. ``elastic`` makes its freedoms elastic (a flexure, a torsion spring):
  a stiffness along each freedom [N·m/rad or N/m], one number for all or a list in the
  order of its freedoms (an S: one number, the same about every axis through its
  centre; a U's two act about its current e1 and e2); on the actuated joint it acts in
  parallel with the drive (the stiffnesses add). Elastic joints rest at home. A U's or
  an S's ``max_angle`` limits the angle between its
  ``mounting_axis`` (default: its link's home direction; fixed to the body on the other
  side) and its link (the link after it; the link before it for the joint at the
  platform). A single-axis joint (R, P, C) may give ``axis2``, normal to ``axis``:
  the direction of e2 of its springs' frame (a guide whose lateral direction the
  hardware defines), carried by the body before it. A P's or C's point is its bushing,
  carried by the body before it, or with ``carried_by = "after"`` its carriage, carried
  by the body after it (a block on a rail: its springs act at the moving block, the
  next link starts there and the drive's moving mass sits there); a passive P's or
  C's ``travel`` [lo, hi] [m] limits its translation from home (``<name>_travel``);
- a **link** (``link = {section and material}`` or ``link = "rigid"``) between two
  joints: a beam from the preceding joint's current point (a P or C joint's point is its
  bushing, on the body before it unless carried by its carriage, so a ram's free length
  changes with the stroke) to
  the next joint's point, with the mass-model keys of any link; a rigid link adds no
  springs (and carries no mass).

- a **parallelogram** (``parallelogram = {bar section}`` or ``"rigid"``), the last
  element: two parallel bars with ball joints at their corners, between the body
  before it and the platform (a Delta robot's forearm;
  :mod:`ppm_stiffness.legs.types._parallelogram`).

The platform is the body after the last element: a joint at a platform point (the
usual S), a link fixed to the platform (``end``: the point [m] of F_b at home where
it is fixed, as a Tricept's central tube), or a parallelogram's far crossbar. Joints
without a link between them are joined rigidly.

Spring frames, at every pose. A joint's frame (:mod:`ppm_stiffness.legs.chain`) is its
current axis e1 (carried by the body before it) and, for a U, its current e2 (carried by
the cross, after e1's rotation): a U's springs act along e1, e2, e1 x e2 and about
e1 x e2. An S's frame has e1 along its link (the one before it; the one after it at the
base), as the strut legs' spherical joints.

Kinematics (:mod:`ppm_stiffness.legs.kinematics`): joint coordinates are zero at home,
every body moves by the product of exponentials of the joints' screws at home, and the
inverse kinematics at a pose is Newton's method on the leg's closure from home, by
continuation (the home pose's assembly mode). A leg with fewer than six independent
freedoms constrains the platform: its constraint residuals are the closure error along
the wrenches reciprocal to its freedoms, and the design completes its dependent pose
coordinates from them (``task_coordinates`` must then be given).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Annotated, Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike
from pydantic import Discriminator, Field, PrivateAttr, Tag, ValidationInfo, model_validator

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import FloatArray, rotation_z
from ppm_stiffness.legs import kinematics as kin
from ppm_stiffness.legs.base import (
    BarPairGeometry,
    BaseFeature,
    Coordinate,
    LegModel,
    LegPose,
    check_plausible,
)
from ppm_stiffness.legs.chain import Element, Joint, Link, frame_from_axis, unit
from ppm_stiffness.legs.flexure_hinge import (
    SYMMETRY_TOLERANCE,
    FlexureHinge,
    asymmetry,
    joint_stiffnesses,
)
from ppm_stiffness.legs.joint_kinds import JointKind, JointKindRecord, joint_kind
from ppm_stiffness.legs.parts import (
    BearingModel,
    Finite,
    GuideModel,
    PartModel,
    Positive,
    RevoluteModel,
    SectionModel,
    SphericalModel,
    UniversalModel,
)
from ppm_stiffness.legs.types._parallelogram import (
    SKEW_TOLERANCE,
    ParallelogramElement,
    parallelogram_joints,
    parallelogram_members,
    skew,
)
from ppm_stiffness.legs.types._spatial import check_normal, check_unit, joint_angle

Vector3 = tuple[Finite, Finite, Finite]


def _home_frame(element: JointElement) -> tuple[FloatArray, FloatArray, FloatArray]:
    """A joint's frame at home: its axes (a second axis as given), or F_b's axes for a
    joint without an axis (an S, whose rotations are parametrised about x, y, z)."""
    if element.axis is None:
        return np.eye(3)[0], np.eye(3)[1], np.eye(3)[2]
    if element.axis2 is None:
        return frame_from_axis(np.asarray(element.axis, dtype=float))
    e1, e2 = unit(element.axis), unit(element.axis2)  # normal to e1 (validated)
    return e1, e2, np.cross(e1, e2)


JointSprings = (
    Positive | GuideModel | BearingModel | RevoluteModel | UniversalModel | SphericalModel | None
)


class JointElement(PartModel):
    """A joint of a chain leg (module doc); lengths [m], angles [rad]."""

    joint: JointKind
    name: str = ""
    point: Vector3
    axis: Vector3 | None = None
    axis2: Vector3 | None = None
    actuated: bool = False
    stroke: tuple[Finite, Finite] | None = None
    springs: JointSprings = None
    mounting_axis: Vector3 | None = None
    elastic: Positive | list[Positive] | None = None
    hinge: FlexureHinge | None = None
    carried_by: Literal["before", "after"] | None = None  # None: "before" (a bushing)
    travel: tuple[Finite, Finite] | None = None

    @model_validator(mode="after")
    def _axes(self) -> JointElement:
        record = joint_kind(self.joint)
        for v in self.point:
            check_plausible("point", v, "m")
        if record.spherical:
            if self.axis is not None or self.axis2 is not None:
                raise ValueError(f"a {record.name} joint has no axis (its springs follow its link)")
        elif self.axis is None:
            raise ValueError(f"a {record.name} joint needs its axis")
        else:
            e1 = check_unit("axis", self.axis)
            if record.second_axis:
                if self.axis2 is None:
                    raise ValueError(f"a {record.name} joint needs axis2 (e2, normal to axis)")
                check_normal("axis", e1, "axis2", check_unit("axis2", self.axis2))
            elif self.axis2 is not None:  # the direction of e2 of its springs' frame
                check_normal("axis", e1, "axis2", check_unit("axis2", self.axis2))
        if self.carried_by == "after" and not record.slides:
            raise ValueError(
                f'carried_by = "after": a {record.name} joint\'s point is on its axes, the '
                "same point of the bodies before and after it (only a joint that slides, "
                "a P or a C, has a bushing on the body before it or a carriage after it)"
            )
        if self.mounting_axis is not None:
            check_unit("mounting_axis", self.mounting_axis)
        part = record.springs_model()
        if self.springs is not None and not isinstance(self.springs, (float, int, part)):
            raise ValueError(
                f"springs: a {record.name} joint's springs are a {part.__name__} table "
                f"({', '.join(part.model_fields)}) or one stiffness"
            )
        self._check_elastic(record)
        self._check_hinge(record)
        if self.actuated:
            self._check_stroke(record)
        elif self.stroke is not None:
            raise ValueError("stroke is the actuated joint's; this joint is passive")
        self._check_travel(record)
        return self

    def _check_elastic(self, record: JointKindRecord) -> None:
        if not isinstance(self.elastic, list):
            return
        if record.spherical:
            raise ValueError(
                "elastic: a spherical joint has one stiffness [N·m/rad], the same about "
                "every axis through its centre"
            )
        if len(self.elastic) != record.freedom_count:
            raise ValueError(
                f"elastic: one stiffness, or one per freedom ({record.freedom_count} for a "
                f"{record.name} joint), got {len(self.elastic)}"
            )

    def _check_hinge(self, record: JointKindRecord) -> None:
        """A ``hinge`` (:mod:`ppm_stiffness.legs.flexure_hinge`) at the notch's centre
        ``point``: a kind with ``hinge_axes`` (an R), ``axis2`` along the notch, a
        symmetric profile, neither ``springs`` nor ``elastic`` (the hinge gives both)."""
        if self.hinge is None:
            return
        if record.hinge_axes is None:
            raise ValueError(f"hinge: a notch hinge is an R joint, not a {record.name} joint")
        if self.springs is not None or self.elastic is not None:
            raise ValueError("hinge: the hinge gives the joint's springs and elastic; remove them")
        if self.axis2 is None:
            raise ValueError(
                "hinge: give axis2, the notch's direction (hinge x, towards the platform)"
            )
        assert self.axis is not None  # an R has one (checked before)
        check_normal("axis", unit(self.axis), "axis2", check_unit("axis2", self.axis2))
        if (defect := asymmetry(self.hinge)) > SYMMETRY_TOLERANCE:
            raise ValueError(
                f"hinge: the profile is not symmetric about its centre (coupling {defect:.3g});"
                " only a symmetric notch is an R joint"
            )

    def elastic_stiffnesses(self) -> FloatArray | None:
        """The stiffness along each freedom (f,) [N·m/rad or N/m], or None."""
        record = joint_kind(self.joint)
        if self.hinge is not None and record.hinge_axes is not None:
            return joint_stiffnesses(self.hinge, record.freedoms, record.hinge_axes)
        if self.elastic is None:
            return None
        count = joint_kind(self.joint).freedom_count
        return np.broadcast_to(np.asarray(self.elastic, dtype=float), (count,)).copy()

    def _check_travel(self, record: JointKindRecord) -> None:
        """A ``travel`` [lo, hi] [m] from home only on a passive joint that slides."""
        if self.travel is None:
            return
        if not record.slides or self.actuated:
            raise ValueError(
                "travel limits a passive P's or C's translation; "
                + (
                    "an actuated joint has its stroke"
                    if self.actuated
                    else f"a {record.name} joint does not slide"
                )
            )
        lo, hi = self.travel
        for v in self.travel:
            check_plausible("travel", v, "m")
        if not lo <= 0.0 <= hi or not lo < hi:
            raise ValueError(
                f"travel = [{lo:g}, {hi:g}]: measured from the home position, so "
                "lo <= 0 <= hi with lo < hi"
            )

    def _check_stroke(self, record: JointKindRecord) -> None:
        if record.freedom_count != 1:
            raise ValueError(
                f"an actuated joint has one freedom; a {record.name} joint has "
                f"{record.freedom_count}"
            )
        if self.stroke is None:
            raise ValueError("an actuated joint needs its stroke [lo, hi] from home")
        lo, hi = self.stroke
        for v in self.stroke:
            check_plausible("stroke", v, record.actuator_units()[1])
        if not lo <= 0.0 <= hi or not lo < hi:
            raise ValueError(
                f"stroke = [{lo:g}, {hi:g}]: measured from the home position, so "
                "lo <= 0 <= hi with lo < hi"
            )

    def stiffnesses(self) -> FloatArray | None:
        """The hardware springs in the kind's constrained order, or None (rigid)."""
        record = joint_kind(self.joint)
        if self.hinge is not None and record.hinge_axes is not None:
            return joint_stiffnesses(self.hinge, record.constrained, record.hinge_axes)
        if self.springs is None:
            return None
        if isinstance(self.springs, (float, int)):
            return np.full(joint_kind(self.joint).constrained_count, float(self.springs))
        return np.asarray(self.springs.stiffnesses(), dtype=float)

    def max_angle(self) -> float | None:
        return getattr(self.springs, "max_angle", None)


class LinkElement(PartModel):
    """A link of a chain leg: a beam (section and material) or ``"rigid"``; ``end``
    [m] (F_b, home) only for a last link fixed to the platform."""

    link: SectionModel | Literal["rigid"]
    name: str = ""
    end: Vector3 | None = None


def _element_kind(value: Any) -> str:
    if isinstance(value, dict):
        for key in ("link", "parallelogram"):
            if key in value:
                return key
        return "joint"
    if isinstance(value, ParallelogramElement):
        return "parallelogram"
    return "link" if isinstance(value, LinkElement) else "joint"


ChainElement = Annotated[
    Annotated[JointElement, Tag("joint")]
    | Annotated[LinkElement, Tag("link")]
    | Annotated[ParallelogramElement, Tag("parallelogram")],
    Discriminator(_element_kind),
]


def turned_leg(raw: dict[str, Any], turn: FloatArray, mirror: bool = False) -> dict[str, Any]:
    """A raw chain leg mirrored (y -> -y, when ``mirror``) then turned by ``turn``
    (3, 3): points and directions turn as vectors; a revolute's axis is an axial
    vector (its mirror image is -M a, so that the mirrored joint's coordinate equals
    the original's at mirrored poses and its stroke stays)."""
    m = np.diag([1.0, -1.0, 1.0]) if mirror else np.eye(3)

    def polar(v: Any) -> Any:
        return (turn @ m @ np.asarray(v, dtype=float)).tolist() if _is_vector(v) else v

    def axial(v: Any) -> Any:
        sign = -1.0 if mirror else 1.0
        return (sign * turn @ m @ np.asarray(v, dtype=float)).tolist() if _is_vector(v) else v

    out = {k: v for k, v in raw.items() if k != "pattern"}
    elements = []
    for element in raw.get("elements", []):
        if not isinstance(element, dict):
            elements.append(element)
            continue
        e = dict(element)
        letter = e.get("joint")
        rotation = isinstance(letter, str) and joint_kind(letter).first_rotates
        for key in ("point", "end", "mounting_axis", "near", "far", "crossbar"):
            if key in e:
                e[key] = polar(e[key])
        for key in ("axis", "axis2"):
            if key in e:
                e[key] = axial(e[key]) if rotation else polar(e[key])
        elements.append(e)
    out["elements"] = elements
    return out


def _is_vector(v: Any) -> bool:
    return (
        isinstance(v, (list, tuple))
        and len(v) == 3
        and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v)
    )


def _beam_beside_hinge(link: object, joint: object) -> bool:
    """A beam link (not rigid) next to a joint with a notch ``hinge``."""
    return (
        isinstance(link, LinkElement)
        and link.link != "rigid"
        and isinstance(joint, JointElement)
        and joint.hinge is not None
    )


class ChainLeg(LegModel):
    """A leg written as its joints and links (module doc).

    A leg table may carry ``pattern = {copies = n, mirror = true}``: it then stands for
    n copies of the leg turned about the z axis of F_b by 2 pi k / n (k = 0 .. n - 1),
    each preceded, with ``mirror``, by its mirror image in the plane y = 0 of F_b (the
    legs of a hexapod in pairs: leg, mirror, turned leg, turned mirror, ...).
    """

    type: Literal["chain"] = "chain"
    elements: Annotated[list[ChainElement], Field(min_length=1)]

    ACTUATED_COORDINATE: ClassVar[str] = "actuated"
    DESCRIPTION: ClassVar[str] = "any serial leg, written as its joints and links"

    _home: tuple[float, ...] = PrivateAttr(default=(0.0,) * 6)
    _constrained: int = PrivateAttr(default=0)
    _freedoms: tuple[kin.Freedoms, list[int]] | None = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _structure(self, info: ValidationInfo) -> ChainLeg:
        home = (info.context or {}).get("home_pose")
        if home is not None:
            self._home = tuple(float(v) for v in home)
        elements = self.elements
        if not isinstance(elements[0], JointElement):
            raise ValueError("elements: a leg starts at a joint on the base")
        for a, b in zip(elements, elements[1:], strict=False):
            if isinstance(a, LinkElement) and isinstance(b, LinkElement):
                raise ValueError("elements: two links in a row (join them into one)")
        for e in elements[:-1]:
            if isinstance(e, LinkElement) and e.end is not None:
                raise ValueError("elements: only the last link, fixed to the platform, has end")
        last = elements[-1]
        if isinstance(last, LinkElement) and last.end is None:
            raise ValueError("elements: a last link is fixed to the platform: give its end")
        for i, e in enumerate(elements[:-1]):
            if isinstance(e, ParallelogramElement):
                raise ValueError(
                    f"elements: {self.element_name(i)}: a parallelogram is the last element "
                    "(its far crossbar is fixed to the platform)"
                )
        carried = isinstance(last, ParallelogramElement) and last.bar_mass() > 0.0
        arm = elements[-2] if len(elements) > 1 else None
        if carried and not (isinstance(arm, LinkElement) and arm.link != "rigid"):
            raise ValueError(
                "elements: a parallelogram's bar masses need a beam link before it (the "
                "arm's end carries their near halves)"
            )
        actuated = [e for e in self.joints() if e.actuated]
        if len(actuated) > 1:
            raise ValueError(
                f"elements: at most one actuated joint (none: a passive constraining "
                f"leg), got {len(actuated)}"
            )
        for i, (a, b) in enumerate(zip(elements, elements[1:], strict=False)):
            pair = ((a, b), (b, a))
            if any(_beam_beside_hinge(link, joint) for link, joint in pair):
                raise ValueError(
                    f"elements: {self.element_name(i)} and {self.element_name(i + 1)}: a "
                    "beam link beside a notch hinge is not modelled (its span would start "
                    "at the notch's centre and count the notch's half-length twice): make "
                    'it "rigid" (the rigid bodies end at the notch\'s ends)'
                )
        names = [e.name for e in elements if e.name]
        if len(set(names)) != len(names):
            raise ValueError("elements: element names must differ")
        for i, element in enumerate(elements):
            limited = isinstance(element, JointElement) and element.max_angle() is not None
            if limited and self._adjacent_link(i, prefer_before=False) is None:
                raise ValueError(
                    f"elements: {self.element_name(i)}: max_angle needs a link at the "
                    "joint to measure against"
                )
        self._freedoms = self._build_freedoms()
        self._constrained = self._count_constraints()
        return self

    # -- the chain at home -----------------------------------------------------------
    def joints(self) -> list[JointElement]:
        return [e for e in self.elements if isinstance(e, JointElement)]

    def home(self) -> FloatArray:
        """The design's home pose (6,) [m, rad], where every joint coordinate is zero."""
        return np.array(self._home)

    def _point_name(self, index: int) -> str:
        """The name of the point of element ``index`` (a joint, or a last link's end) in
        a :class:`LegPose`: A, B, C, ... from the base, as the coded legs' points."""
        points = [
            i
            for i, e in enumerate(self.elements)
            if not isinstance(e, LinkElement) or i == len(self.elements) - 1
        ]
        return chr(ord("A") + points.index(index))

    def _parallelogram(self) -> ParallelogramElement | None:
        last = self.elements[-1]
        return last if isinstance(last, ParallelogramElement) else None

    def _bars(self) -> kin.Bars | None:
        """The closure by a last parallelogram's bars, or None."""
        element = self._parallelogram()
        if element is None:
            return None
        near, far = element.corners()
        return kin.Bars(near, far)

    def element_name(self, index: int) -> str:
        element = self.elements[index]
        if element.name:
            return element.name
        if isinstance(element, LinkElement):
            kind = "link"
        elif isinstance(element, ParallelogramElement):
            kind = "parallelogram"
        else:
            kind = element.joint
        return f"{kind}{index + 1}"

    def freedoms(self) -> tuple[kin.Freedoms, list[int]]:
        """The chain's freedoms at home and, for each element, the index of the body
        after it (0: the base); built once, when the leg is validated."""
        if self._freedoms is None:
            self._freedoms = self._build_freedoms()
        return self._freedoms

    def _build_freedoms(self) -> tuple[kin.Freedoms, list[int]]:
        axes, points, prismatic, bodies = [], [], [], []
        for element in self.elements:
            if isinstance(element, JointElement):
                frame = _home_frame(element)
                for motion, k in joint_kind(element.joint).freedoms:
                    axes.append(frame[k])
                    points.append(np.array(element.point, dtype=float))
                    prismatic.append(motion == "t")
            bodies.append(len(axes))
        freedoms = kin.Freedoms(
            np.array(axes).reshape(-1, 3), np.array(points).reshape(-1, 3), np.array(prismatic)
        )
        return freedoms, bodies

    def _end_point(self) -> FloatArray:
        last = self.elements[-1]
        if isinstance(last, ParallelogramElement):
            return np.array(last.far, dtype=float)
        point = last.end if isinstance(last, LinkElement) else last.point
        return np.array(point, dtype=float)

    def attachment(self) -> FloatArray:
        """The platform point of the leg (its last joint's point, or its last link's
        end) in the platform frame [m]."""
        home = self.home()
        return np.asarray(pose6.rotation(home).T @ (self._end_point() - home[:3]))

    def constraint_count(self) -> int:
        """Number of pose coordinates the leg constrains (6 - the rank of its freedoms
        at home)."""
        return self._constrained

    def _count_constraints(self) -> int:
        freedoms, _ = self.freedoms()
        bars = self._bars()
        if bars is not None:  # the bars' lengths less what the joints can adjust
            zero = np.zeros((1, freedoms.count))
            _, jac = kin.closure(freedoms, self.home(), self.home()[None], zero, bars)
            return bars.near.shape[0] - kin.rank(jac[0])
        state = kin.solve(freedoms, self.home(), self.home()[None])
        jac = kin.jacobian(freedoms, state.rotations, state.translations, self.home()[None, :3])
        return 6 - kin.rank(jac[0] * _BALANCED_ROWS[:, None])

    # -- kinematics ----------------------------------------------------------------
    def _state(self, poses: ArrayLike) -> tuple[kin.ChainState, tuple[int, ...]]:
        q = np.asarray(poses, dtype=float)
        freedoms, _ = self.freedoms()
        return kin.solve(freedoms, self.home(), q.reshape(-1, 6), self._bars()), q.shape[:-1]

    def solve(self, poses: ArrayLike) -> LegPose:
        """Inverse kinematics at poses (..., 6) (module doc); the coordinates are the
        actuated joint's (``actuated``), each limited U's or S's angle
        (``<name>_angle``) and every freedom's (``q1``, ``q2``, ... from the base)."""
        pose = np.asarray(poses, dtype=float)
        state, shape = self._state(pose)
        _, bodies = self.freedoms()
        p = pose.reshape(-1, 6)[:, :3]
        points: dict[str, FloatArray] = {}
        for i, element in enumerate(self.elements):
            if isinstance(element, JointElement):
                carrier = self._carrier(i, bodies)
                points[self._point_name(i)] = state.carry(carrier, element.point) - p
        last = len(self.elements) - 1
        if isinstance(self.elements[-1], LinkElement):
            points[self._point_name(last)] = state.carry(bodies[-1], self._end_point()) - p
        bars = self._bars()
        if bars is not None:
            far = bars.far_points(self.home(), pose.reshape(-1, 6))
            points[self._point_name(last)] = state.carry(bodies[-1], bars.near.mean(axis=0)) - p
            points[chr(ord(self._point_name(last)) + 1)] = far.mean(axis=1) - p
        coordinates = {f"q{j + 1}": state.q[:, j] for j in range(state.q.shape[1])}
        if self.is_actuated():
            coordinates["actuated"] = state.q[:, self._actuated_freedom()]
        for name, value in self._joint_angles(state, points).items():
            coordinates[name] = value
        for name, index in self._travels().items():
            coordinates[name] = state.q[:, index]
        solvable = state.converged
        if bars is not None:  # a parallelogram's bars stay parallel
            near = bars.near_points(state.rotations[:, -1], state.translations[:, -1])
            far = bars.far_points(self.home(), pose.reshape(-1, 6))
            solvable = solvable & (skew(near, far) <= SKEW_TOLERANCE)
            forearm = self._parallelogram()
            if forearm is not None and forearm.max_angle() is not None:
                name = f"{self.element_name(last)}_angle"
                coordinates[name] = self._corner_angles(state, pose.reshape(-1, 6), near, far)
        if self.constraint_count() == 0:  # a leg that constrains nothing closes at every pose
            solvable = solvable & (np.max(np.abs(state.error), axis=-1) <= kin.CLOSED)
        return LegPose(
            poses=pose,
            points={k: v.reshape(shape + (3,)) for k, v in points.items()},
            coordinates={k: v.reshape(shape) for k, v in coordinates.items()},
            solvable=np.asarray(solvable).reshape(shape),  # type: ignore[arg-type]  # bool, as every leg's
        )

    def is_actuated(self) -> bool:
        """Whether a joint is ``actuated = true``; without one the leg is a passive
        constraining leg (no ``actuator`` table, no ``actuated`` coordinate)."""
        return any(e.actuated for e in self.joints())

    def _travels(self) -> dict[str, int]:
        """The limited travel of each passive P or C (``<name>_travel``): the index of
        its translational freedom."""
        _, bodies = self.freedoms()
        out = {}
        for i, element in enumerate(self.elements):
            if isinstance(element, JointElement) and element.travel is not None:
                freedoms = joint_kind(element.joint).freedoms
                slide = next(j for j, (motion, _) in enumerate(freedoms) if motion == "t")
                out[f"{self.element_name(i)}_travel"] = (bodies[i - 1] if i else 0) + slide
        return out

    def _actuated_freedom(self) -> int:
        _, bodies = self.freedoms()
        for i, element in enumerate(self.elements):
            if isinstance(element, JointElement) and element.actuated:
                return bodies[i] - 1
        raise AssertionError("validated: one actuated joint")

    def _joint_angles(
        self, state: kin.ChainState, points: dict[str, FloatArray]
    ) -> dict[str, FloatArray]:
        """Angle [rad] between each limited U's or S's mounting axis and its link (the
        link after it; before it for a joint with none after it)."""
        out: dict[str, FloatArray] = {}
        _, bodies = self.freedoms()
        home_points = self._home_points()
        for i, element in enumerate(self.elements):
            if not isinstance(element, JointElement) or element.max_angle() is None:
                continue
            found = self._adjacent_link(i, prefer_before=False)
            assert found is not None  # validated (_structure)
            far, before = found
            here, there = self._point_name(i), self._point_name(far)
            direction_now = unit(points[there] - points[here])
            mount = (
                np.asarray(element.mounting_axis, dtype=float)
                if element.mounting_axis is not None
                else unit(home_points[far] - home_points[i])
            )
            # the mounting axis is fixed to the body on the side away from the link
            side = bodies[i] if before else (bodies[i - 1] if i else 0)
            out[f"{self.element_name(i)}_angle"] = joint_angle(
                direction_now, state.turn(side, mount)
            )
        return out

    def _corner_angles(
        self, state: kin.ChainState, poses: FloatArray, near: FloatArray, far: FloatArray
    ) -> FloatArray:
        """The largest angle [rad] (n,) at a parallelogram's four corners between its bar
        and the bar's home direction carried by the corner's body (the arm at the near
        corners, the platform at the far ones)."""
        bars = self._bars()
        assert bars is not None
        home = bars.far - bars.near
        at_near = np.einsum("nij,mj->nmi", state.rotations[:, -1], home)
        turn = pose6.rotation(poses) @ pose6.rotation(self.home()).T
        at_far = np.einsum("nij,mj->nmi", turn, home)
        now = far - near
        return np.asarray(
            np.maximum(joint_angle(now, at_near), joint_angle(now, at_far)).max(axis=-1)
        )

    def _adjacent_link(self, index: int, prefer_before: bool) -> tuple[int, bool] | None:
        """The link beside joint ``index``, on the preferred side if it has one there:
        (the element whose point ends it: the joint past it, or a last link itself, for
        its ``end``; whether it is before the joint), or None without a link beside."""
        sides = (True, False) if prefer_before else (False, True)
        for before in sides:
            step = -1 if before else 1
            link = index + step
            if 0 <= link < len(self.elements) and isinstance(self.elements[link], LinkElement):
                return (link if link == len(self.elements) - 1 else link + step), before
        return None

    def _carrier(self, index: int, bodies: list[int]) -> int:
        """The body that carries element ``index``'s point: the one before it (a P or C
        joint's bushing; any other joint's point is on its axes; a link adds no body),
        or the one after it for a joint ``carried_by = "after"`` (a carriage)."""
        element = self.elements[index]
        if isinstance(element, JointElement) and element.carried_by == "after":
            return bodies[index]
        return bodies[index - 1] if index else 0

    def _home_points(self) -> dict[int, FloatArray]:
        out = {}
        for i, element in enumerate(self.elements):
            if isinstance(element, (JointElement, ParallelogramElement)):
                out[i] = np.array(element.point, dtype=float)
            elif element.end is not None:
                out[i] = np.array(element.end, dtype=float)
        return out

    def limits(self) -> dict[str, tuple[float, float]]:
        out = {}
        for i, element in enumerate(self.elements):
            if isinstance(element, JointElement):
                if element.actuated:
                    assert element.stroke is not None
                    out["actuated"] = (float(element.stroke[0]), float(element.stroke[1]))
                limit = element.max_angle()
                if limit is not None:
                    out[f"{self.element_name(i)}_angle"] = (0.0, float(limit))
                if element.travel is not None:
                    travel = (float(element.travel[0]), float(element.travel[1]))
                    out[f"{self.element_name(i)}_travel"] = travel
            elif isinstance(element, ParallelogramElement) and element.max_angle() is not None:
                out[f"{self.element_name(i)}_angle"] = (0.0, float(element.max_angle() or 0.0))
        return out

    def coordinate(self, name: str) -> Coordinate:
        if name == "actuated":
            joint = next(e for e in self.joints() if e.actuated)
            unit_ = joint_kind(joint.joint).actuator_units()[1]
            return Coordinate(f"actuated joint {joint.name or joint.joint} travel", unit_)
        if name.endswith("_angle"):
            return Coordinate(f"{name[: -len('_angle')]} joint angle", "rad")
        if name.endswith("_travel"):
            return Coordinate(f"{name[: -len('_travel')]} joint travel", "m")
        return Coordinate(f"joint coordinate {name}", "m or rad")

    def coordinate_names(self) -> list[str]:
        return list(self.limits())

    @classmethod
    def pattern_copies(cls, raw: dict[str, Any]) -> list[dict[str, Any]]:
        """The legs of a leg table with a ``pattern`` (class doc), or the table."""
        pattern = raw.get("pattern")
        if pattern is None:
            return [raw]
        if not isinstance(pattern, dict) or set(pattern) - {"copies", "mirror"}:
            raise ValueError("a table {copies = n, mirror = true or false}")
        copies, mirror = pattern.get("copies", 1), pattern.get("mirror", False)
        if not isinstance(copies, int) or isinstance(copies, bool) or not 1 <= copies <= 12:
            raise ValueError(f"copies = {copies!r}: a whole number of copies, 1 to 12")
        if not isinstance(mirror, bool):
            raise ValueError(f"mirror = {mirror!r}: true or false")
        out = []
        for k in range(copies):
            turn = rotation_z(2.0 * np.pi * k / copies)
            out.append(turned_leg(raw, turn, False))
            if mirror:
                out.append(turned_leg(raw, turn, True))
        return out

    def parameter_items(self) -> list[tuple[str, Any]]:
        """The actuator, then each element's fields under its name: a beam link's
        section as the element (``rod.area``), a joint's keys (``crank_drive.springs.tilt``,
        ``crank_joint.point``)."""
        items: list[tuple[str, Any]] = [("actuator", self.actuator)] if self.actuator else []
        for i, element in enumerate(self.elements):
            name = self.element_name(i)
            if isinstance(element, LinkElement):
                items.append((name, element.link))
                if element.end is not None:
                    items.append((f"{name}.end", element.end))
                continue
            if isinstance(element, ParallelogramElement):
                items.append((name, element.parallelogram))
                for key, value in element:
                    if key not in ("name", "parallelogram") and value is not None:
                        items.append((f"{name}.{key}", value))
                continue
            for key, value in element:
                if key != "name" and value is not None:
                    items.append((f"{name}.{key}", value))
        return items

    def link_mass(self) -> float:
        """The physical mass [kg] of the leg's links: every beam link's ``mass``, and a
        parallelogram's two bars (its ``mass`` is each bar's)."""
        second_bars = sum(
            e.bar_mass() for e in self.elements if isinstance(e, ParallelogramElement)
        )
        return super().link_mass() + second_bars

    def field_path(self, keys: list[str]) -> list[str | int]:
        """An element's parameter by its name (:meth:`parameter_items`): its index in
        ``elements``, then ``link`` for a beam link's section."""
        names = [self.element_name(i) for i in range(len(self.elements))]
        if not keys or keys[0] not in names:
            return list(keys)
        index = names.index(keys[0])
        element = self.elements[index]
        if isinstance(element, LinkElement) and keys[1:2] != ["end"]:
            return ["elements", index, "link", *keys[1:]]
        if isinstance(element, ParallelogramElement) and not set(keys[1:2]) & set(
            ParallelogramElement.model_fields
        ):
            return ["elements", index, "parallelogram", *keys[1:]]
        return ["elements", index, *keys[1:]]

    def parameter_unit(self, key: str) -> str:
        """m for points, rad or m for a stroke, 1 for axes, N·m/rad or N/m for an elastic
        stiffness (the element's field)."""
        field = key.rsplit(".", 1)[-1]
        if field == "stroke":
            return joint_kind(self.actuated_kind()).actuator_units()[1]
        if field == "elastic":
            return "N·m/rad or N/m"
        units = {"point": "m", "end": "m", "near": "m", "far": "m", "width": "m", "travel": "m"}
        return units.get(field, "1" if "axis" in field or field == "crossbar" else "")

    def architecture_name(self) -> str:
        """The joints' letters from the base (``"RUS"``; a parallelogram with its ball
        joints ``(SS)2``, as a Delta's ``R(SS)2``), the actuated one marked by its letter
        only (plain text cannot underline it)."""
        bars = "(SS)2" if self._parallelogram() is not None else ""
        return "".join(e.joint for e in self.joints()) + bars

    def parallel_stiffness(self) -> float:
        """The actuated joint's elastic stiffness along its freedom (an ``elastic``
        joint or a notch ``hinge``: the drive acts in parallel with it), 0 without."""
        for element in self.joints():
            if element.actuated:
                k = element.elastic_stiffnesses()
                return 0.0 if k is None else float(k[0])
        return 0.0

    def actuated_kind(self) -> str:
        """The actuated joint's kind ("P" until the leg's own check has refused a leg
        without one: the base checks run first)."""
        return next((e.joint for e in self.joints() if e.actuated), "P")

    def constraint(self, poses: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """The closure error along the wrenches reciprocal to the leg's freedoms (module
        doc): residuals (..., c) [m, balanced] and wrenches (..., 6, c)."""
        residual, wrenches, _ = self.constraint_continued(poses, None)
        return residual, wrenches

    def constraint_continued(
        self, poses: ArrayLike, start: tuple[FloatArray, FloatArray] | None
    ) -> tuple[FloatArray, FloatArray, tuple[FloatArray, FloatArray] | None]:
        """:meth:`constraint` with the inverse kinematics continued from ``start``
        (poses (n, 6) already solved and their joint coordinates (n, f); see
        :func:`ppm_stiffness.legs.kinematics.solve`), and this call's (poses, joint
        coordinates) to continue from next."""
        c = self.constraint_count()
        q = np.asarray(poses, dtype=float)
        shape = q.shape[:-1]
        if c == 0:
            return np.zeros(shape + (0,)), np.zeros(shape + (6, 0)), None
        freedoms, _ = self.freedoms()
        bars = self._bars()
        flat = q.reshape(-1, 6)
        state = kin.solve(freedoms, self.home(), flat, bars, start)
        # a pose whose solve failed continues from home next time, not from its last try
        onward = (flat, np.where(state.converged[:, None], state.q, np.nan))
        if bars is not None:
            residual, wrenches = self._bar_constraint(state, flat, bars, shape)
            return residual, wrenches, onward
        jac = kin.jacobian(freedoms, state.rotations, state.translations, flat[:, :3])
        basis = kin.constraint_basis(jac * _BALANCED_ROWS[:, None], c)
        residual = np.einsum("nic,ni->nc", basis, state.error)
        wrenches = basis * _BALANCED_ROWS[:, None]
        return residual.reshape(shape + (c,)), wrenches.reshape(shape + (6, c)), onward

    def _bar_constraint(
        self, state: kin.ChainState, poses: FloatArray, bars: kin.Bars, shape: tuple[int, ...]
    ) -> tuple[FloatArray, FloatArray]:
        """The bars' length errors (length less distance) along the combinations the
        joints cannot adjust (the left null space of their Jacobian), and the wrenches
        of those combinations: each bar's distance grows with the platform twist as its
        line's wrench ``((F_k - P) x n_k ; n_k)``."""
        freedoms, _ = self.freedoms()
        error, jac = kin.closure(freedoms, self.home(), poses, state.q, bars)
        u, _, _ = np.linalg.svd(jac, full_matrices=True)
        basis = u[..., jac.shape[-2] - self.constraint_count() :]  # (n, m, c)
        near = bars.near_points(state.rotations[:, -1], state.translations[:, -1])
        far = bars.far_points(self.home(), poses)
        n = bars.directions(near, far)
        lines = np.concatenate([np.cross(far - poses[:, None, :3], n), n], axis=-1)  # (n, m, 6)
        residual = np.einsum("nmc,nm->nc", basis, error)
        wrenches = -np.einsum("nmi,nmc->nic", lines, basis)  # error: length less distance
        c = basis.shape[-1]
        return residual.reshape(shape + (c,)), wrenches.reshape(shape + (6, c))

    # -- the chain for the stiffness ----------------------------------------------
    def chain(self, leg_pose: LegPose) -> Sequence[Element]:
        """Joints and links at the poses of ``leg_pose`` (module doc)."""
        shape = np.shape(leg_pose.poses)[:-1]
        freedoms, bodies = self.freedoms()
        q = np.stack(
            [np.reshape(leg_pose.coordinates[f"q{j + 1}"], -1) for j in range(freedoms.count)],
            axis=-1,
        ).reshape(-1, freedoms.count)
        rot, trans = kin.forward(freedoms, q)
        state = kin.ChainState(q, rot, trans, np.zeros((q.shape[0], 6)), np.ones(q.shape[0], bool))
        poses = np.asarray(leg_pose.poses, dtype=float).reshape(-1, 6)
        p = poses[:, :3]

        def where(body: int, point: ArrayLike) -> FloatArray:
            return (state.carry(body, point) - p).reshape(shape + (3,))

        def turn(body: int, axis: ArrayLike) -> FloatArray:
            return state.turn(body, unit(axis)).reshape(shape + (3,))

        out: list[Element] = []
        previous_point: FloatArray | None = None
        law = self.actuator
        for i, element in enumerate(self.elements):
            before = bodies[i - 1] if i else 0
            if isinstance(element, LinkElement):
                assert previous_point is not None
                end_mass = 0.0
                if i + 1 < len(self.elements):
                    nxt = self.elements[i + 1]
                    assert not isinstance(nxt, LinkElement)
                    end = where(bodies[i], nxt.point)
                    if isinstance(nxt, ParallelogramElement):
                        end_mass = nxt.bar_mass()  # two near halves
                else:
                    end = where(bodies[i], self._end_point())
                if isinstance(element.link, SectionModel):
                    out.append(
                        Link(
                            previous_point,
                            end,
                            element.link.section(),
                            name=self.element_name(i),
                            mass=element.link.link_mass(),
                            end_mass=end_mass,
                        )
                    )
                continue
            if isinstance(element, ParallelogramElement):
                bars = self._bars()
                assert bars is not None
                near = bars.near_points(state.rotations[:, -1], state.translations[:, -1])
                near = near - p[:, None]
                far = bars.far_points(self.home(), poses) - p[:, None]
                out += parallelogram_joints(
                    element,
                    near.reshape(shape + (2, 3)),
                    far.reshape(shape + (2, 3)),
                    self.element_name(i),
                )
                continue
            point = where(self._carrier(i, bodies), element.point)
            name = self.element_name(i)
            mass = law.moving_parts() if element.actuated and law is not None else None
            springs = element.stiffnesses()
            record = joint_kind(element.joint)
            elastic = element.elastic_stiffnesses()
            if record.spherical:
                direction = self._spherical_axis(i, where, bodies)
                out.append(
                    Joint(element.joint, direction, point, springs, name=name, elastic=elastic)
                )
            elif record.second_axis:
                assert element.axis is not None and element.axis2 is not None
                e1 = turn(before, element.axis)
                e2 = turn(before + 1, element.axis2)
                out.append(
                    Joint(element.joint, e1, point, springs, name=name, axis2=e2, elastic=elastic)
                )
            else:
                assert element.axis is not None
                axis = turn(before, element.axis)
                out.append(
                    Joint(
                        element.joint,
                        axis,
                        point,
                        springs,
                        actuated=element.actuated,
                        name=name,
                        mass=mass,
                        elastic=elastic,
                        axis2=None if element.axis2 is None else turn(before, element.axis2),
                    )
                )
            previous_point = point
        return out

    def _spherical_axis(self, index: int, where: Any, bodies: list[int]) -> FloatArray:
        """An S joint's spring axis: along its link (before it; after it at the base),
        from the joint into the link's far end."""
        element = self.elements[index]
        assert isinstance(element, JointElement)
        here = where(self._carrier(index, bodies), element.point)
        found = self._adjacent_link(index, prefer_before=True)
        if found is None:
            return np.broadcast_to(np.array([0.0, 0.0, 1.0]), np.shape(here)).copy()
        far, before = found
        there = where(self._carrier(far, bodies), self._home_points()[far])
        return unit(here - there) if before else unit(there - here)

    def link_length_ranges(self) -> dict[str, tuple[float, float]]:
        return {}

    def drawn_members(self, leg_pose: LegPose) -> tuple[list[Link], list[Joint]]:
        """A parallelogram's bars, crossbars and corner joints (one pose)."""
        element, bars = self._parallelogram(), self._bars()
        if element is None or bars is None:
            return [], []
        pose = np.asarray(leg_pose.poses, dtype=float).reshape(-1, 6)[:1]
        state, _ = self._state(pose)
        near = bars.near_points(state.rotations[:, -1], state.translations[:, -1])[0] - pose[0, :3]
        far = bars.far_points(self.home(), pose)[0] - pose[0, :3]
        name = self.element_name(len(self.elements) - 1)
        return parallelogram_members(element, near, far, name)

    def bar_pair(self, leg_pose: LegPose) -> BarPairGeometry | None:
        """A last parallelogram's bars for the moving geometry (its chain of two P
        joints and a U is exact to first order only: the bars' swing under their axial
        loads, their geometric stiffness, is not in it): the chain without that
        equivalent part, the corners and one bar's axial compliance."""
        element = self._parallelogram()
        if element is None:
            return None
        chain = list(self.chain(leg_pose))
        name = self.element_name(len(self.elements) - 1)
        tail = chain[-3:]
        assert all(isinstance(j, Joint) and j.name.startswith(name) for j in tail)
        shape = np.shape(leg_pose.poses)[:-1]
        pose = np.asarray(leg_pose.poses, dtype=float).reshape(-1, 6)
        bars = self._bars()
        assert bars is not None
        freedoms, _ = self.freedoms()
        q = np.stack(
            [np.reshape(leg_pose.coordinates[f"q{j + 1}"], -1) for j in range(freedoms.count)],
            axis=-1,
        ).reshape(-1, freedoms.count)
        rot, trans = kin.forward(freedoms, q)  # as :meth:`chain` carries the near ends
        near = bars.near_points(rot[:, -1], trans[:, -1])
        far = bars.far_points(self.home(), pose)
        k_bar = element.bar_stiffness()
        return BarPairGeometry(
            chain[:-3],
            (near - pose[:, None, :3]).reshape(shape + (2, 3)),
            (far - pose[:, None, :3]).reshape(shape + (2, 3)),
            0.0 if not np.isfinite(k_bar) else 1.0 / k_bar,
        )

    def base_feature(self, leg_pose: LegPose) -> BaseFeature:
        """The first joint: a rail along a base P (its stroke from its home point) or a
        pivot."""
        first = self.joints()[0]
        if joint_kind(first.joint).linear:
            assert first.axis is not None
            stroke = None if first.stroke is None else (first.stroke[0], first.stroke[1])
            return BaseFeature("rail", np.array(first.point, dtype=float), unit(first.axis), stroke)
        return BaseFeature("pivot", np.array(first.point, dtype=float), np.zeros(3))


_BALANCED_ROWS = np.array([kin.LENGTH_SCALE] * 3 + [1.0] * 3)

__all__ = ["ChainLeg", "JointElement", "LinkElement", "turned_leg"]
