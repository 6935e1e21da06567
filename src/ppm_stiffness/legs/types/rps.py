"""R-P-S leg (a tripod leg): a passive base revolute, an actuated prismatic along the
leg (a strut: cylinder and rod) and a platform spherical joint.

Geometry. The revolute at A (``base_point``, F_b) turns about the unit
``revolute_axis`` e_R (F_b); it keeps the leg, and the platform's spherical joint B
(``platform_point``, platform frame, at ``p + R b``), in the plane through A normal to
e_R: the leg's constraint is ``(B - A) . e_R = 0`` (its wrench: a force along e_R
through B). The leg runs along ``n = (B - A) / |B - A|``; its actuator coordinate is
the length ``l = |B - A|`` (``stroke`` = [min, max] of l). The cylinder (``cylinder``,
fixed length ``cylinder_length``) runs from A to the actuated prismatic joint at
``C = A + cylinder_length n``; the rod (``rod``) from C to B.

Joints. The revolute's springs (``base_revolute``) act at A, the guide's (``guide``,
the rod's bushing) at C, the spherical joint's (``platform_joint``, axial along n) at
B; a joint is rigid in its constrained directions when its part is absent.
``platform_joint.max_angle`` limits the angle between the leg (from B to A) and
``platform_joint_axis`` (platform frame).

A design of three such legs is a 3-RPS tripod: its task coordinates are (z, rx, ry),
and x, y and rz follow from the three constraints (the parasitic motion).

Chain: R about e_R at A (``base_revolute``) - link A->C (``cylinder``) - P along n at
C (actuated, ``guide``) - link C->B (``rod``) - S at B (``platform_joint``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike
from pydantic import model_validator

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.legs.base import BaseFeature, Coordinate, LegModel, LegPose
from ppm_stiffness.legs.chain import Element, Joint, unit
from ppm_stiffness.legs.parts import (
    Finite,
    GuideModel,
    Positive,
    RevoluteModel,
    SectionModel,
    SphericalModel,
    joint_springs,
)
from ppm_stiffness.legs.types._joint_lists import joint_table
from ppm_stiffness.legs.types._spatial import angle_limit, check_unit, plane_constraint
from ppm_stiffness.legs.types._strut import (
    check_stroke,
    strut_elements,
    strut_joint_list,
    strut_link_lengths,
    strut_pose,
)

Vector3 = tuple[Finite, Finite, Finite]


class RPSLeg(LegModel):
    """One R-P-S leg (module doc); lengths [m], angles [rad]."""

    type: Literal["RPS"] = "RPS"
    base_point: Vector3
    revolute_axis: Vector3
    cylinder_length: Positive
    platform_point: Vector3
    stroke: tuple[Positive, Positive]
    cylinder: SectionModel
    rod: SectionModel
    guide: GuideModel | None = None
    base_revolute: RevoluteModel | None = None
    platform_joint: SphericalModel | None = None
    platform_joint_axis: Vector3 = (0.0, 0.0, -1.0)

    COORDINATES: ClassVar[dict[str, Coordinate]] = {
        "length": Coordinate("leg length |AB|", "m"),
        "platform_joint_angle": Coordinate("platform joint angle", "rad"),
    }
    UNITS: ClassVar[dict[str, str]] = {
        "base_point": "m",
        "revolute_axis": "1",
        "cylinder_length": "m",
        "platform_point": "m",
        "stroke": "m",
        "platform_joint_axis": "1",
    }
    ACTUATED_COORDINATE: ClassVar[str] = "length"
    DESCRIPTION: ClassVar[str] = (
        "base revolute, actuated strut (prismatic along the leg), platform spherical joint"
    )
    TASK_COORDINATES: ClassVar[tuple[str, ...]] = ("z", "rx", "ry")

    @model_validator(mode="after")
    def _ranges(self) -> RPSLeg:
        check_stroke(self.stroke, self.cylinder_length)
        check_unit("revolute_axis", self.revolute_axis)
        check_unit("platform_joint_axis", self.platform_joint_axis)
        return self

    def revolute_direction(self) -> FloatArray:
        """The revolute axis e_R (unit, F_b)."""
        return unit(np.array(self.revolute_axis, dtype=float))

    def attachment(self) -> FloatArray:
        return np.array(self.platform_point, dtype=float)

    def link_length_ranges(self) -> dict[str, tuple[float, float]]:
        """The cylinder's fixed length; the rod's free length over the stroke."""
        return strut_link_lengths(self)

    def limits(self) -> dict[str, tuple[float, float]]:
        out = {"length": (float(self.stroke[0]), float(self.stroke[1]))}
        limit = angle_limit(self.platform_joint)
        if limit is not None:
            out["platform_joint_angle"] = (0.0, limit)
        return out

    def solve(self, poses: ArrayLike) -> LegPose:
        return strut_pose(self, poses)

    def constraint(self, poses: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """``(B - A) . e_R`` [m] and its wrench, a force along e_R through B."""
        pose = np.asarray(poses, dtype=float)
        b = self.platform_offset(pose)
        return plane_constraint(
            np.asarray(self.base_point, dtype=float),
            self.revolute_direction(),
            pose6.position(pose) + b,
            b,
        )

    def chain(self, leg_pose: LegPose) -> Sequence[Element]:
        e = self.revolute_direction()
        base_point = leg_pose.points["A"]
        base = Joint("R", e, base_point, joint_springs(self.base_revolute), name="base_revolute")
        return [base, *strut_elements(self, leg_pose)]

    def joint_list(self, home: FloatArray) -> dict[str, Any]:
        """This leg as a joint-list leg's table at the home pose (6,): R about e_R at A,
        then the strut (:func:`~ppm_stiffness.legs.types._strut.strut_joint_list`)."""
        base = joint_table(
            "R",
            "base_revolute",
            self.base_point,
            self.base_revolute,
            axis=self.revolute_direction().tolist(),
        )
        return strut_joint_list(self, home, base)

    def base_feature(self, leg_pose: LegPose) -> BaseFeature:
        """The revolute at ``base_point`` (pose-independent)."""
        return BaseFeature("pivot", np.array(self.base_point, dtype=float), np.zeros(3))
