"""The actuated strut shared by the U-P-S and R-P-S legs (a private module: the leg
registry skips it): from the base joint at A a cylinder of ``cylinder_length`` along
n = unit(B - A), the actuated prismatic joint C where the rod enters, the rod to the
spherical joint at B. The leg type supplies its base joint; everything from the
cylinder on is built here once.

Points are relative to P, axes of F_b, with leading batch axes (..., 3), SI.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.legs.base import LegPose
from ppm_stiffness.legs.chain import Element, Joint, Link, unit
from ppm_stiffness.legs.parts import joint_springs
from ppm_stiffness.legs.types._joint_lists import chain_table, joint_table, link_table
from ppm_stiffness.legs.types._spatial import joint_angle

if TYPE_CHECKING:
    from ppm_stiffness.legs.parts import (
        ActuatorModel,
        GuideModel,
        SectionModel,
        SphericalModel,
    )


class StrutLeg(Protocol):
    """What a strut leg (U-P-S, R-P-S) has: its fields (read-only: designs are frozen)
    and its platform offset."""

    @property
    def base_point(self) -> tuple[float, float, float]: ...
    @property
    def cylinder_length(self) -> float: ...
    @property
    def stroke(self) -> tuple[float, float]: ...
    @property
    def cylinder(self) -> SectionModel: ...
    @property
    def rod(self) -> SectionModel: ...
    @property
    def guide(self) -> GuideModel | None: ...
    @property
    def platform_joint(self) -> SphericalModel | None: ...
    @property
    def platform_joint_axis(self) -> tuple[float, float, float]: ...
    def law(self, what: str = "this") -> ActuatorModel: ...

    def platform_offset(self, poses: ArrayLike) -> FloatArray: ...


def check_stroke(stroke: tuple[float, float], cylinder_length: float) -> None:
    """Refuse a stroke that is not [min, max] or whose shortest leg leaves the rod no
    free length (ValueError, for the design's validator)."""
    if not stroke[0] < stroke[1]:
        raise ValueError("stroke must be [min, max] with min < max")
    if not stroke[0] > cylinder_length:
        raise ValueError(
            "stroke: the shortest leg must exceed cylinder_length (the rod needs a "
            "positive free length)"
        )


def strut_link_lengths(leg: StrutLeg) -> dict[str, tuple[float, float]]:
    """The shortest and longest length [m] of the cylinder (fixed) and of the rod (its
    free length ``l - cylinder_length``) over the stroke."""
    c = leg.cylinder_length
    stroke = leg.stroke
    return {"cylinder": (c, c), "rod": (stroke[0] - c, stroke[1] - c)}


def strut_pose(
    leg: StrutLeg, poses: ArrayLike, base_joint_axis: ArrayLike | None = None
) -> LegPose:
    """The strut at poses (..., 6): points A, C, B, the coordinates ``length`` |AB| [m]
    and ``platform_joint_angle`` [rad] (and ``base_joint_angle`` against
    ``base_joint_axis`` when given), solvable where |AB| exceeds the cylinder."""
    pose = np.asarray(poses, dtype=float)
    b = leg.platform_offset(pose)
    a = np.asarray(leg.base_point, dtype=float) - pose6.position(pose)
    r = b - a
    length = np.linalg.norm(r, axis=-1)
    n = unit(r)
    c = a + leg.cylinder_length * n
    platform_axis = pose6.platform_offset(pose, np.asarray(leg.platform_joint_axis))
    coordinates = {"length": length}
    if base_joint_axis is not None:
        coordinates["base_joint_angle"] = joint_angle(n, np.asarray(base_joint_axis))
    coordinates["platform_joint_angle"] = joint_angle(-n, platform_axis)
    return LegPose(
        poses=pose,
        points={"A": a, "C": c, "B": b},
        coordinates=coordinates,
        solvable=np.asarray(length > leg.cylinder_length),
    )


def strut_elements(leg: StrutLeg, leg_pose: LegPose) -> Sequence[Element]:
    """The chain from A on, after the leg's base joint: the cylinder, the actuated
    prismatic joint at C along n, the rod and the spherical joint at B."""
    pts = leg_pose.points
    n = unit(pts["B"] - pts["A"])
    return [
        Link(
            pts["A"],
            pts["C"],
            leg.cylinder.section(),
            name="cylinder",
            mass=leg.cylinder.link_mass(),
        ),
        Joint(
            "P",
            n,
            pts["C"],
            joint_springs(leg.guide),
            actuated=True,
            name="guide",
            mass=leg.law().moving_parts(),
        ),
        Link(pts["C"], pts["B"], leg.rod.section(), name="rod", mass=leg.rod.link_mass()),
        Joint("S", n, pts["B"], joint_springs(leg.platform_joint), name="platform_joint"),
    ]


def strut_joint_list(leg: StrutLeg, home: FloatArray, base: dict[str, Any]) -> dict[str, Any]:
    """The strut leg as a joint-list leg's table (``type = "chain"``, docs/legs.md) at the
    design's home pose ``home`` (6,): ``base`` (the leg's base joint element, at A),
    the cylinder, the actuated P at C along the home n (its stroke the travel from the
    home length), the rod and the S at B (its ``mounting_axis`` the platform joint's
    axis at home)."""
    a = np.asarray(leg.base_point, dtype=float)
    b = pose6.position(home) + leg.platform_offset(home)
    length = float(np.linalg.norm(b - a))
    n = (b - a) / length
    guide = joint_table(
        "P",
        "guide",
        a + leg.cylinder_length * n,
        leg.guide,
        axis=n.tolist(),
        actuated=True,
        stroke=[leg.stroke[0] - length, leg.stroke[1] - length],
    )
    axis = pose6.platform_offset(home, np.asarray(leg.platform_joint_axis))
    spherical = joint_table(
        "S", "platform_joint", b, leg.platform_joint, mounting_axis=axis.tolist()
    )
    return chain_table(
        leg.law(),
        [base, link_table(leg.cylinder, "cylinder"), guide, link_table(leg.rod, "rod"), spherical],
    )


__all__ = [
    "StrutLeg",
    "check_stroke",
    "strut_elements",
    "strut_joint_list",
    "strut_link_lengths",
    "strut_pose",
]
