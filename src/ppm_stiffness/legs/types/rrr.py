"""R-R-R leg: an actuated base revolute (a rotary actuator), a proximal link, an elbow
revolute, a distal link and a platform revolute.

Geometry. The base joint A sits at ``base_point``; the proximal link of length
``proximal_length`` leaves it at the angle theta from the x axis of F_b (the actuator
coordinate, [rad]); the elbow C = A + proximal_length (cos theta, sin theta); the
distal link of length ``distal_length`` runs from C to D. With ``r = D - A``,
``theta = atan2(r) + branch * acos((L1^2 + |r|^2 - L2^2) / (2 L1 |r|))``:
``branch = +1`` puts the elbow to the left of the line A -> D (counter-clockwise),
``branch = -1`` to its right (the two working modes). No real solution when
``|r|`` is outside ``[|L1 - L2|, L1 + L2]``; the modes meet at its ends (a serial
singularity). theta is reported in the turn that contains the middle of ``stroke``.

The actuator is rotary: its law (``actuator``) is in N·m, rad and N·m/rad.

Chain: R at A (actuated, ``base_revolute`` springs) - link A->C (``proximal``) - R at C
(``elbow_revolute``) - link C->D (``distal``) - R at D (``platform_revolute``).
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
    Positive,
    RevoluteModel,
    SectionModel,
    joint_springs,
)
from ppm_stiffness.legs.types._joint_lists import chain_table, home_points, joint_table, link_table


class RRRLeg(PlanarLegModel):
    """One R-R-R leg (module doc); lengths [m], angles [rad]."""

    type: Literal["RRR"] = "RRR"
    base_point: tuple[Finite, Finite]
    proximal_length: Positive
    distal_length: Positive
    branch: Branch = 1
    stroke: tuple[Finite, Finite]
    proximal: SectionModel
    distal: SectionModel
    base_revolute: RevoluteModel | None = None
    elbow_revolute: RevoluteModel | None = None
    platform_revolute: RevoluteModel | None = None

    DISCRETE_FIELDS: ClassVar[frozenset[str]] = frozenset({"branch"})
    COORDINATES: ClassVar[dict[str, Coordinate]] = {
        "theta": Coordinate("actuator angle", "rad"),
    }
    UNITS: ClassVar[dict[str, str]] = {
        **PlanarLegModel.UNITS,
        "base_point": "m",
        "proximal_length": "m",
        "distal_length": "m",
        "stroke": "rad",
        "branch": "1",
    }
    ACTUATED_KIND: ClassVar[str] = "R"
    ACTUATED_COORDINATE: ClassVar[str] = "theta"
    DESCRIPTION: ClassVar[str] = (
        "actuated base revolute, proximal link, elbow revolute, distal link, platform revolute"
    )

    @model_validator(mode="after")
    def _ranges(self) -> RRRLeg:
        if not self.stroke[0] < self.stroke[1]:
            raise ValueError("stroke must be [min, max] with min < max")
        if self.stroke[1] - self.stroke[0] >= 2 * np.pi:
            raise ValueError("stroke must span less than one turn")
        return self

    def base_feature(self, leg_pose: LegPose) -> BaseFeature:
        """The actuated pivot at ``base_point`` with the stroke of theta (pose-independent)."""
        return BaseFeature(
            "pivot",
            planar(np.asarray(self.base_point)),
            np.zeros(3),
            (float(self.stroke[0]), float(self.stroke[1])),
        )

    def link_length_ranges(self) -> dict[str, tuple[float, float]]:
        """The two links' fixed lengths."""
        l1, l2 = self.proximal_length, self.distal_length
        return {"proximal": (l1, l1), "distal": (l2, l2)}

    def limits(self) -> dict[str, tuple[float, float]]:
        return {"theta": self.stroke}

    def solve(self, poses: ArrayLike) -> LegPose:
        pose = as_poses(poses)
        d = self.platform_offset(pose)
        p_abs = planar_position(pose)
        a = planar(np.asarray(self.base_point)) - p_abs
        r = d - a
        dist = np.linalg.norm(r, axis=-1)
        l1, l2 = self.proximal_length, self.distal_length
        with np.errstate(divide="ignore", invalid="ignore"):
            cos_g = (l1**2 + dist**2 - l2**2) / (2 * l1 * dist)
        solvable = (dist > 0) & (np.abs(cos_g) <= 1.0)
        gamma = np.arccos(np.clip(np.nan_to_num(cos_g), -1.0, 1.0))
        theta = np.arctan2(r[..., 1], r[..., 0]) + self.branch * gamma
        mid = 0.5 * (self.stroke[0] + self.stroke[1])
        theta = mid + np.mod(theta - mid + np.pi, 2 * np.pi) - np.pi
        c = a + l1 * unit_planar(theta)
        return LegPose(
            poses=pose,
            points={"A": a, "C": c, "D": d},
            coordinates={"theta": theta},
            solvable=solvable,
        )

    def joint_list(self, home: ArrayLike) -> dict[str, Any]:
        """This leg as a joint-list leg's table at the home pose (6,): R at A (actuated,
        its stroke the turn from the home angle), the proximal link, R at C, the distal
        link, R at D on the platform, every axis along z."""
        h = np.asarray(home, dtype=float)
        at, coordinates = home_points(self, h)
        points = {k: v.tolist() for k, v in at.items()}
        theta = coordinates["theta"]
        z = {"axis": [0.0, 0.0, 1.0]}
        stroke = [self.stroke[0] - theta, self.stroke[1] - theta]
        return chain_table(
            self.law(),
            [
                joint_table(
                    "R",
                    "base_revolute",
                    points["A"],
                    self.base_revolute,
                    **z,
                    actuated=True,
                    stroke=stroke,
                ),
                link_table(self.proximal, "proximal"),
                joint_table("R", "elbow_revolute", points["C"], self.elbow_revolute, **z),
                link_table(self.distal, "distal"),
                joint_table("R", "platform_revolute", points["D"], self.platform_revolute, **z),
            ],
        )

    def chain(self, leg_pose: LegPose) -> Sequence[Element]:
        pts = leg_pose.points
        return [
            Joint(
                "R",
                Z_AXIS,
                pts["A"],
                joint_springs(self.base_revolute),
                actuated=True,
                name="base_revolute",
                mass=self.law().moving_parts(),
            ),
            Link(
                pts["A"],
                pts["C"],
                self.proximal.section(),
                name="proximal",
                mass=self.proximal.link_mass(),
            ),
            Joint("R", Z_AXIS, pts["C"], joint_springs(self.elbow_revolute), name="elbow_revolute"),
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
