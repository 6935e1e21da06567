"""P-R-R leg: an actuated prismatic on a base rail, a revolute on the carriage, a link
of fixed length, and a platform revolute.

Geometry. The rail runs through ``base_point`` A along ``u = (cos alpha, sin alpha)``;
the carriage revolute C = A + rho u (rho the actuator coordinate) carries a link of
length ``link_length`` to the platform point D. With ``r = D - A``,
``a = r . u`` and ``b = r . n`` (``n = z x u``), ``|D - C| = link_length`` gives
``rho = a - branch * sqrt(link_length^2 - b^2)``: ``branch = +1`` puts D ahead of C
along +u, ``branch = -1`` behind it (the two working modes). No real root when
``|b| > link_length``; the two modes meet (a serial singularity) at ``|b| =
link_length``.

Chain: P along u at C (actuated, ``guide``) - R at C (``carriage_revolute``) - link
C->D (``distal``) - R at D (``platform_revolute``). Revolute springs are rigid when
absent.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike
from pydantic import model_validator

from ppm_stiffness.core.conventions import Z_AXIS, FloatArray
from ppm_stiffness.legs.base import (
    BaseFeature,
    Branch,
    Coordinate,
    LegPose,
    PlanarLegModel,
    as_poses,
    planar,
    planar_position,
    unit_planar,
)
from ppm_stiffness.legs.chain import Element, Joint, Link
from ppm_stiffness.legs.parts import (
    Finite,
    GuideModel,
    Positive,
    RevoluteModel,
    SectionModel,
    joint_springs,
)
from ppm_stiffness.legs.types._joint_lists import chain_table, home_points, joint_table, link_table


class PRRLeg(PlanarLegModel):
    """One P-R-R leg (module doc); lengths [m], angles [rad]."""

    type: Literal["PRR"] = "PRR"
    base_point: tuple[Finite, Finite]
    alpha: Finite
    link_length: Positive
    branch: Branch = 1
    stroke: tuple[Finite, Finite]
    guide: GuideModel
    distal: SectionModel
    carriage_revolute: RevoluteModel | None = None
    platform_revolute: RevoluteModel | None = None

    DISCRETE_FIELDS: ClassVar[frozenset[str]] = frozenset({"branch"})
    COORDINATES: ClassVar[dict[str, Coordinate]] = {
        "rho": Coordinate("actuator coordinate", "m"),
    }
    UNITS: ClassVar[dict[str, str]] = {
        **PlanarLegModel.UNITS,
        "base_point": "m",
        "alpha": "rad",
        "link_length": "m",
        "stroke": "m",
        "branch": "1",
    }
    DESCRIPTION: ClassVar[str] = (
        "actuated prismatic on a rail, revolute on the carriage, link, platform revolute"
    )

    @model_validator(mode="after")
    def _ranges(self) -> PRRLeg:
        if not self.stroke[0] < self.stroke[1]:
            raise ValueError("stroke must be [min, max] with min < max")
        return self

    def rail_direction(self) -> FloatArray:
        return unit_planar(self.alpha)

    def base_feature(self, leg_pose: LegPose) -> BaseFeature:
        """The rail through ``base_point`` along u, over the stroke (pose-independent)."""
        return BaseFeature(
            "rail",
            planar(np.asarray(self.base_point)),
            self.rail_direction(),
            (float(self.stroke[0]), float(self.stroke[1])),
        )

    def link_length_ranges(self) -> dict[str, tuple[float, float]]:
        """The link's fixed length."""
        return {"distal": (self.link_length, self.link_length)}

    def limits(self) -> dict[str, tuple[float, float]]:
        return {"rho": self.stroke}

    def solve(self, poses: ArrayLike) -> LegPose:
        pose = as_poses(poses)
        u = self.rail_direction()
        n = np.array([-u[1], u[0], 0.0])
        d = self.platform_offset(pose)
        p_abs = planar_position(pose)
        a = planar(np.asarray(self.base_point)) - p_abs
        r = d - a
        along, across = r @ u, r @ n
        disc = self.link_length**2 - across**2
        rho = along - self.branch * np.sqrt(np.maximum(disc, 0.0))
        c = a + rho[..., None] * u
        return LegPose(
            poses=pose,
            points={"C": c, "D": d},
            coordinates={"rho": rho},
            solvable=disc >= 0,
        )

    def joint_list(self, home: ArrayLike) -> dict[str, Any]:
        """This leg as a joint-list leg's table at the home pose (6,): the actuated P at C
        along the rail (its stroke the travel from the home rho), carried by the carriage
        (``carried_by = "after"``: the guide's springs act at the moving carriage, as
        here), R at C, the distal link, R at D; revolute axes along z."""
        h = np.asarray(home, dtype=float)
        points, coordinates = home_points(self, h)
        rho = coordinates["rho"]
        z = {"axis": [0.0, 0.0, 1.0]}
        return chain_table(
            self.law(),
            [
                joint_table(
                    "P",
                    "guide",
                    points["C"],
                    self.guide,
                    axis=self.rail_direction().tolist(),
                    actuated=True,
                    stroke=[self.stroke[0] - rho, self.stroke[1] - rho],
                    carried_by="after",
                ),
                joint_table("R", "carriage_revolute", points["C"], self.carriage_revolute, **z),
                link_table(self.distal, "distal"),
                joint_table("R", "platform_revolute", points["D"], self.platform_revolute, **z),
            ],
        )

    def chain(self, leg_pose: LegPose) -> Sequence[Element]:
        pts = leg_pose.points
        u = self.rail_direction()
        return [
            Joint(
                "P",
                u,
                pts["C"],
                self.guide.stiffnesses(),
                actuated=True,
                name="guide",
                mass=self.law().moving_parts(),
            ),
            Joint(
                "R",
                Z_AXIS,
                pts["C"],
                joint_springs(self.carriage_revolute),
                name="carriage_revolute",
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
