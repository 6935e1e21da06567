"""R-P-R leg: a base revolute, an actuated prismatic (a linear actuator with its guide)
along the leg, and a platform revolute.

Geometry. The base pivot A sits at ``base_point``; the leg runs along
``e = (D - A) / |D - A|`` and its actuator coordinate is the pivot distance
``rho = |D - A|``. The actuator housing (``proximal``) is a link of fixed length
``housing_length`` from A to the guide C = A + housing_length e, where the rod
enters; the rod (``distal``) runs from C to D, free length ``rho - housing_length``.
The inverse kinematics has one solution (``rho > 0``; the other root, the rod
pointing through the pivot, is not a configuration of the hardware), so the leg has
no working-mode key.

Chain: R at A (``base_revolute``) - link A->C (``proximal``) - P at C along e
(actuated, ``guide``) - link C->D (``distal``) - R at D (``platform_revolute``).
Revolute springs are rigid when absent.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike
from pydantic import model_validator

from ppm_stiffness.core.conventions import Z_AXIS
from ppm_stiffness.legs.base import (
    Coordinate,
    LegPose,
    PlanarLegModel,
    as_poses,
    planar,
    planar_position,
)
from ppm_stiffness.legs.chain import Element, Joint, Link, unit
from ppm_stiffness.legs.parts import (
    Finite,
    GuideModel,
    Positive,
    RevoluteModel,
    SectionModel,
    joint_springs,
)
from ppm_stiffness.legs.types._joint_lists import chain_table, home_points, joint_table, link_table


class RPRLeg(PlanarLegModel):
    """One R-P-R leg (module doc); lengths [m], angles [rad]."""

    type: Literal["RPR"] = "RPR"
    base_point: tuple[Finite, Finite]
    housing_length: Positive
    stroke: tuple[Positive, Positive]
    guide: GuideModel
    proximal: SectionModel
    distal: SectionModel
    base_revolute: RevoluteModel | None = None
    platform_revolute: RevoluteModel | None = None

    COORDINATES: ClassVar[dict[str, Coordinate]] = {
        "rho": Coordinate("pivot distance |AD|", "m"),
    }
    UNITS: ClassVar[dict[str, str]] = {
        **PlanarLegModel.UNITS,
        "base_point": "m",
        "housing_length": "m",
        "stroke": "m",
    }
    DESCRIPTION: ClassVar[str] = (
        "base revolute, actuated prismatic along the leg, revolute at the platform"
    )

    @model_validator(mode="after")
    def _ranges(self) -> RPRLeg:
        if not self.stroke[0] < self.stroke[1]:
            raise ValueError("stroke must be [min, max] with min < max")
        if not self.stroke[0] > self.housing_length:
            raise ValueError(
                "stroke: the smallest pivot distance must exceed housing_length "
                "(the rod needs a positive free length)"
            )
        return self

    def link_length_ranges(self) -> dict[str, tuple[float, float]]:
        """The housing's fixed length; the rod's free length over the stroke."""
        h = self.housing_length
        return {"proximal": (h, h), "distal": (self.stroke[0] - h, self.stroke[1] - h)}

    def limits(self) -> dict[str, tuple[float, float]]:
        return {"rho": self.stroke}

    def solve(self, poses: ArrayLike) -> LegPose:
        pose = as_poses(poses)
        d = self.platform_offset(pose)
        p_abs = planar_position(pose)
        a = planar(np.asarray(self.base_point)) - p_abs
        r = d - a
        rho = np.linalg.norm(r, axis=-1)
        c = a + self.housing_length * unit(r)
        return LegPose(
            poses=pose,
            points={"A": a, "C": c, "D": d},
            coordinates={"rho": rho},
            solvable=rho > 0,
        )

    def joint_list(self, home: ArrayLike) -> dict[str, Any]:
        """This leg as a joint-list leg's table at the home pose (6,): R at A, the
        proximal link, the actuated P at C along the home A -> D (its stroke the travel
        from the home length), the distal link, R at D; revolute axes along z."""
        h = np.asarray(home, dtype=float)
        points, coordinates = home_points(self, h)
        rho = coordinates["rho"]
        z = {"axis": [0.0, 0.0, 1.0]}
        return chain_table(
            self.law(),
            [
                joint_table("R", "base_revolute", points["A"], self.base_revolute, **z),
                link_table(self.proximal, "proximal"),
                joint_table(
                    "P",
                    "guide",
                    points["C"],
                    self.guide,
                    axis=unit(points["D"] - points["A"]).tolist(),
                    actuated=True,
                    stroke=[self.stroke[0] - rho, self.stroke[1] - rho],
                ),
                link_table(self.distal, "distal"),
                joint_table("R", "platform_revolute", points["D"], self.platform_revolute, **z),
            ],
        )

    def chain(self, leg_pose: LegPose) -> Sequence[Element]:
        pts = leg_pose.points
        e = unit(pts["D"] - pts["A"])
        return [
            Joint("R", Z_AXIS, pts["A"], joint_springs(self.base_revolute), name="base_revolute"),
            Link(
                pts["A"],
                pts["C"],
                self.proximal.section(),
                name="proximal",
                mass=self.proximal.link_mass(),
            ),
            Joint(
                "P",
                e,
                pts["C"],
                self.guide.stiffnesses(),
                actuated=True,
                name="guide",
                mass=self.law().moving_parts(),
            ),
            Link(
                pts["C"],
                pts["D"],
                self.distal.section(),
                name="distal",
                mass=self.distal.link_mass(),
            ),
            Joint(
                "R",
                Z_AXIS,
                pts["D"],
                joint_springs(self.platform_revolute),
                name="platform_revolute",
            ),
        ]
