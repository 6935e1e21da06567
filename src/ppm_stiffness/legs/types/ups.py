"""U-P-S leg (the Gough-Stewart leg): a base universal joint, an actuated prismatic
along the leg (a strut: cylinder and rod) and a platform spherical joint.

Geometry. The U joint A sits at ``base_point`` (F_b), the S joint B at
``platform_point`` (platform frame), at ``p + R b`` in F_b. The leg runs along
``n = (B - A) / |B - A|``; its actuator coordinate is the length ``l = |B - A|``
(``stroke`` = [min, max] of l). The cylinder (``cylinder``, a link of fixed length
``cylinder_length``) runs from A to the actuated prismatic joint at
``C = A + cylinder_length n``, where the rod enters; the rod (``rod``) runs from C to
B, free length ``l - cylinder_length``. The leg has six freedoms: it constrains
nothing, and a design of such legs takes all six pose coordinates as task
coordinates.

Joints. The U's axes at each pose are e1 = unit(z x n) (fixed to the base) and
e2 = n x e1 (fixed to the cylinder), so that e1 x e2 = n: its springs
(``base_joint``, :class:`~ppm_stiffness.legs.parts.UniversalModel`) are radial in the
plane normal to the leg, axial along it, and torsion about it; with isotropic radial
springs the choice of e1 about n does not change K. The S joint's springs
(``platform_joint``) are axial along n and radial normal to it. The prismatic joint's
hardware springs (``guide``, the rod's bushing in the cylinder) act at C. Each joint is
rigid in its constrained directions when its part is absent. A joint part's
``max_angle`` limits the angle between the leg and the joint's mounting axis
(``base_joint_axis`` in F_b, ``platform_joint_axis`` in the platform frame).

With passive U and S joints the leg transmits only a force along n (a two-force
member): its stiffness is ``k w w^T`` with ``w = ((B - P) x n ; n)`` and ``1/k`` the sum
of the axial compliances of the actuator, cylinder, rod and joints.

Chain: U at A (``base_joint``) - link A->C (``cylinder``) - P along n at C (actuated,
``guide``) - link C->B (``rod``) - S at B (``platform_joint``).
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
    SectionModel,
    SphericalModel,
    UniversalModel,
    joint_springs,
)
from ppm_stiffness.legs.types._joint_lists import joint_table
from ppm_stiffness.legs.types._spatial import angle_limit, check_unit, universal_axes
from ppm_stiffness.legs.types._strut import (
    check_stroke,
    strut_elements,
    strut_joint_list,
    strut_link_lengths,
    strut_pose,
)

Vector3 = tuple[Finite, Finite, Finite]


class UPSLeg(LegModel):
    """One U-P-S leg (module doc); lengths [m], angles [rad]."""

    type: Literal["UPS"] = "UPS"
    base_point: Vector3
    platform_point: Vector3
    cylinder_length: Positive
    stroke: tuple[Positive, Positive]
    cylinder: SectionModel
    rod: SectionModel
    guide: GuideModel | None = None
    base_joint: UniversalModel | None = None
    platform_joint: SphericalModel | None = None
    base_joint_axis: Vector3 = (0.0, 0.0, 1.0)
    platform_joint_axis: Vector3 = (0.0, 0.0, -1.0)

    COORDINATES: ClassVar[dict[str, Coordinate]] = {
        "length": Coordinate("leg length |AB|", "m"),
        "base_joint_angle": Coordinate("base joint angle", "rad"),
        "platform_joint_angle": Coordinate("platform joint angle", "rad"),
    }
    UNITS: ClassVar[dict[str, str]] = {
        "base_point": "m",
        "platform_point": "m",
        "cylinder_length": "m",
        "stroke": "m",
        "base_joint_axis": "1",
        "platform_joint_axis": "1",
    }
    ACTUATED_COORDINATE: ClassVar[str] = "length"
    DESCRIPTION: ClassVar[str] = (
        "base universal joint, actuated strut (prismatic along the leg), platform spherical joint"
    )
    TASK_COORDINATES: ClassVar[tuple[str, ...]] = pose6.POSE_COORDINATES

    @model_validator(mode="after")
    def _ranges(self) -> UPSLeg:
        check_stroke(self.stroke, self.cylinder_length)
        check_unit("base_joint_axis", self.base_joint_axis)
        check_unit("platform_joint_axis", self.platform_joint_axis)
        return self

    def attachment(self) -> FloatArray:
        return np.array(self.platform_point, dtype=float)

    def link_length_ranges(self) -> dict[str, tuple[float, float]]:
        """The cylinder's fixed length; the rod's free length over the stroke."""
        return strut_link_lengths(self)

    def limits(self) -> dict[str, tuple[float, float]]:
        out = {"length": (float(self.stroke[0]), float(self.stroke[1]))}
        for name, part in (
            ("base_joint_angle", self.base_joint),
            ("platform_joint_angle", self.platform_joint),
        ):
            limit = angle_limit(part)
            if limit is not None:
                out[name] = (0.0, limit)
        return out

    def solve(self, poses: ArrayLike) -> LegPose:
        return strut_pose(self, poses, self.base_joint_axis)

    def chain(self, leg_pose: LegPose) -> Sequence[Element]:
        pts = leg_pose.points
        e1, e2 = universal_axes(unit(pts["B"] - pts["A"]))
        base = Joint("U", e1, pts["A"], joint_springs(self.base_joint), name="base_joint", axis2=e2)
        return [base, *strut_elements(self, leg_pose)]

    def joint_list(self, home: FloatArray) -> dict[str, Any]:
        """This leg as a joint-list leg's table at the home pose (6,): U at A with its
        axes at home (e1, e2 of the home n), then the strut
        (:func:`~ppm_stiffness.legs.types._strut.strut_joint_list`)."""
        a = np.asarray(self.base_point, dtype=float)
        b = pose6.position(home) + pose6.platform_offset(home, self.attachment())
        e1, e2 = universal_axes(unit(b - a))
        base = joint_table(
            "U",
            "base_joint",
            a,
            self.base_joint,
            axis=e1.tolist(),
            axis2=e2.tolist(),
            mounting_axis=list(self.base_joint_axis),
        )
        return strut_joint_list(self, home, base)

    def base_feature(self, leg_pose: LegPose) -> BaseFeature:
        """The universal joint at ``base_point`` (pose-independent)."""
        return BaseFeature("pivot", np.array(self.base_point, dtype=float), np.zeros(3))
