"""P-R-S leg (a tripod leg): an actuated carriage on a rail, a passive revolute on the
carriage, a link of fixed length and a platform spherical joint.

Geometry. The rail runs through ``base_point`` A along the unit ``rail_direction``
u (F_b); the carriage is at ``C = A + rho u`` (rho the actuator coordinate, ``stroke``
= [min, max] of rho). The revolute at C turns about the unit ``revolute_axis`` e_R
(F_b, normal to u); the link of length ``link_length`` runs from C to the platform's
spherical joint B (``platform_point``, platform frame, at ``p + R b``). The revolute
keeps B in the plane through A normal to e_R: the leg's constraint is
``(B - A) . e_R = 0`` (its wrench: a force along e_R through B). With ``d = B - A``,
``s = d . u`` and ``h = |d - s u|``, ``|B - C| = link_length`` gives
``rho = s - branch sqrt(link_length^2 - h^2)``: ``branch = +1`` puts the carriage
below B along u (the link leans towards +u), ``-1`` above it. No solution where
``h > link_length``.

Joints. The guide's springs (``guide``) act at the carriage C with the rail as its
axis, its lateral direction (e2) along the revolute axis e_R (the guide rail's
mounting face holds the revolute's bearings) and its vertical direction (e3) normal
to both; the revolute's (``carriage_revolute``) at C; the spherical joint's
(``platform_joint``, axial along the link) at B. A joint is rigid in its constrained
directions when its part is absent. ``platform_joint.max_angle`` limits the angle
between the link (from B to C) and ``platform_joint_axis`` (platform frame).

A design of three such legs with vertical rails is a 3-PRS tripod: its task
coordinates are (z, rx, ry), and x, y and rz follow from the three constraints
(the parasitic motion).

Chain: P along u at C (actuated, ``guide``) - R about e_R at C (``carriage_revolute``)
- link C->B (``link``) - S at B (``platform_joint``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike
from pydantic import model_validator

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.legs.base import BaseFeature, Branch, Coordinate, LegModel, LegPose
from ppm_stiffness.legs.chain import Element, Joint, Link, unit
from ppm_stiffness.legs.parts import (
    Finite,
    GuideModel,
    Positive,
    RevoluteModel,
    SectionModel,
    SphericalModel,
    joint_springs,
)
from ppm_stiffness.legs.types._joint_lists import chain_table, home_points, joint_table, link_table
from ppm_stiffness.legs.types._spatial import (
    angle_limit,
    check_normal,
    check_unit,
    joint_angle,
    plane_constraint,
)

Vector3 = tuple[Finite, Finite, Finite]


class PRSLeg(LegModel):
    """One P-R-S leg (module doc); lengths [m], angles [rad]."""

    type: Literal["PRS"] = "PRS"
    base_point: Vector3
    rail_direction: Vector3
    revolute_axis: Vector3
    link_length: Positive
    platform_point: Vector3
    branch: Branch = 1
    stroke: tuple[Finite, Finite]
    link: SectionModel
    guide: GuideModel | None = None
    carriage_revolute: RevoluteModel | None = None
    platform_joint: SphericalModel | None = None
    platform_joint_axis: Vector3 = (0.0, 0.0, -1.0)

    DISCRETE_FIELDS: ClassVar[frozenset[str]] = frozenset({"branch"})
    COORDINATES: ClassVar[dict[str, Coordinate]] = {
        "rho": Coordinate("carriage position", "m"),
        "platform_joint_angle": Coordinate("platform joint angle", "rad"),
    }
    UNITS: ClassVar[dict[str, str]] = {
        "base_point": "m",
        "rail_direction": "1",
        "revolute_axis": "1",
        "link_length": "m",
        "platform_point": "m",
        "stroke": "m",
        "branch": "1",
        "platform_joint_axis": "1",
    }
    DESCRIPTION: ClassVar[str] = (
        "actuated carriage on a rail, revolute on the carriage, link, platform spherical joint"
    )
    TASK_COORDINATES: ClassVar[tuple[str, ...]] = ("z", "rx", "ry")

    @model_validator(mode="after")
    def _ranges(self) -> PRSLeg:
        if not self.stroke[0] < self.stroke[1]:
            raise ValueError("stroke must be [min, max] with min < max")
        u = check_unit("rail_direction", self.rail_direction)
        e = check_unit("revolute_axis", self.revolute_axis)
        check_normal("rail_direction", u, "revolute_axis", e)
        check_unit("platform_joint_axis", self.platform_joint_axis)
        return self

    def directions(self) -> tuple[FloatArray, FloatArray]:
        """Rail direction u and revolute axis e_R (unit, F_b)."""
        return unit(np.array(self.rail_direction)), unit(np.array(self.revolute_axis))

    def attachment(self) -> FloatArray:
        return np.array(self.platform_point, dtype=float)

    def link_length_ranges(self) -> dict[str, tuple[float, float]]:
        """The link's fixed length."""
        return {"link": (self.link_length, self.link_length)}

    def limits(self) -> dict[str, tuple[float, float]]:
        out = {"rho": (float(self.stroke[0]), float(self.stroke[1]))}
        limit = angle_limit(self.platform_joint)
        if limit is not None:
            out["platform_joint_angle"] = (0.0, limit)
        return out

    def solve(self, poses: ArrayLike) -> LegPose:
        pose = np.asarray(poses, dtype=float)
        u, _ = self.directions()
        b = self.platform_offset(pose)
        a = np.asarray(self.base_point, dtype=float) - pose6.position(pose)
        d = b - a
        along = d @ u
        across = np.linalg.norm(d - along[..., None] * u, axis=-1)
        disc = self.link_length**2 - across**2
        rho = along - self.branch * np.sqrt(np.maximum(disc, 0.0))
        c = a + rho[..., None] * u
        platform_axis = pose6.platform_offset(pose, np.asarray(self.platform_joint_axis))
        return LegPose(
            poses=pose,
            points={"A": a, "C": c, "B": b},
            coordinates={"rho": rho, "platform_joint_angle": joint_angle(c - b, platform_axis)},
            solvable=np.asarray(disc >= 0),
        )

    def constraint(self, poses: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """``(B - A) . e_R`` [m] and its wrench, a force along e_R through B."""
        pose = np.asarray(poses, dtype=float)
        _, e = self.directions()
        b = self.platform_offset(pose)
        return plane_constraint(
            np.asarray(self.base_point, dtype=float), e, pose6.position(pose) + b, b
        )

    def joint_list(self, home: FloatArray) -> dict[str, Any]:
        """This leg as a joint-list leg's table at the home pose (6,): the actuated P at C
        along the rail, its springs' lateral axis (``axis2``) along e_R and carried by the
        carriage (``carried_by = "after"``: they act at the moving carriage, as here),
        its stroke the travel from the home rho; R about e_R at C, the link, S at B (its
        ``mounting_axis`` the platform joint's axis at home)."""
        h = np.asarray(home, dtype=float)
        points, coordinates = home_points(self, h)
        rho = coordinates["rho"]
        u, e = self.directions()
        axis = pose6.platform_offset(h, np.asarray(self.platform_joint_axis))
        return chain_table(
            self.law(),
            [
                joint_table(
                    "P",
                    "guide",
                    points["C"],
                    self.guide,
                    axis=u.tolist(),
                    axis2=e.tolist(),
                    actuated=True,
                    stroke=[self.stroke[0] - rho, self.stroke[1] - rho],
                    carried_by="after",
                ),
                joint_table(
                    "R", "carriage_revolute", points["C"], self.carriage_revolute, axis=e.tolist()
                ),
                link_table(self.link, "link"),
                joint_table(
                    "S",
                    "platform_joint",
                    points["B"],
                    self.platform_joint,
                    mounting_axis=axis.tolist(),
                ),
            ],
        )

    def chain(self, leg_pose: LegPose) -> Sequence[Element]:
        pts = leg_pose.points
        u, e = self.directions()
        s = unit(pts["B"] - pts["C"])
        return [
            Joint(
                "P",
                u,
                pts["C"],
                joint_springs(self.guide),
                actuated=True,
                name="guide",
                mass=self.law().moving_parts(),
                axis2=e,
            ),
            Joint(
                "R", e, pts["C"], joint_springs(self.carriage_revolute), name="carriage_revolute"
            ),
            Link(pts["C"], pts["B"], self.link.section(), name="link", mass=self.link.link_mass()),
            Joint("S", s, pts["B"], joint_springs(self.platform_joint), name="platform_joint"),
        ]

    def base_feature(self, leg_pose: LegPose) -> BaseFeature:
        """The rail through ``base_point`` along u over the stroke (pose-independent)."""
        u, _ = self.directions()
        return BaseFeature(
            "rail",
            np.array(self.base_point, dtype=float),
            u,
            (float(self.stroke[0]), float(self.stroke[1])),
        )
