"""P-P-R leg (the paper's): actuated prismatic on a linear guide, passive prismatic rod
sliding in a linear bearing (a cylindrical joint), revolute at the platform.

Geometry (Table 1 plus the carriage layout, which the paper does not publish). The
rail runs through ``base_point`` A along ``u = (cos alpha, sin alpha)``; the rod runs
along ``w = rot(beta) u`` through the bearing C to the platform point D. In the leg
frame (u, w) with origin A: ``C = A + rho u + bearing_offset w`` with rho the actuator
coordinate, and D on the rod line, ``D = C + rod w`` (rod: the free length of the
rod). The guide block is ``B = A + (rho + guide_offset_u) u + guide_offset_w w``; the
proximal link runs from B to C. Any rail-rod angle beta with ``sin(beta) != 0`` is
allowed: ``D - A = rho u + (bearing_offset + rod) w`` is solved as a 2x2 system.

Chain: P (actuated, ``guide`` springs at B) - link B->C (``proximal``) - C (``bearing``
at C, axis w) - link C->D (``distal``, the rod) - R at D (``platform_revolute``,
rigid when absent, as in the paper).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike
from pydantic import model_validator

from ppm_stiffness.core.conventions import Z_AXIS, FloatArray
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.legs.base import (
    BaseFeature,
    Coordinate,
    LegPose,
    PlanarLegModel,
    as_poses,
    cross_z,
    planar,
    planar_position,
    unit_planar,
)
from ppm_stiffness.legs.chain import Element, Joint, Link
from ppm_stiffness.legs.parts import (
    BearingModel,
    Finite,
    GuideModel,
    Positive,
    RevoluteModel,
    SectionModel,
)
from ppm_stiffness.legs.types._joint_lists import chain_table, home_points, joint_table, link_table
from ppm_stiffness.legs.types._ppr_reduced import reduce_ppr_leg


class PPRLeg(PlanarLegModel):
    """One P-P-R leg (module doc); lengths [m], angles [rad]."""

    type: Literal["PPR"] = "PPR"
    base_point: tuple[Finite, Finite]
    alpha: Finite
    beta: Finite
    bearing_offset: Finite
    guide_offset_u: Finite
    guide_offset_w: Finite
    stroke: tuple[Finite, Finite] = (-1.0, 1.0)
    rod_length_range: tuple[Positive, Positive] = (1e-3, 1.0)
    guide: GuideModel
    bearing: BearingModel
    proximal: SectionModel
    distal: SectionModel
    platform_revolute: RevoluteModel | None = None

    COORDINATES: ClassVar[dict[str, Coordinate]] = {
        "rho": Coordinate("actuator coordinate", "m"),
        "rod": Coordinate("rod free length", "m"),
    }
    UNITS: ClassVar[dict[str, str]] = {
        **PlanarLegModel.UNITS,
        "base_point": "m",
        "alpha": "rad",
        "beta": "rad",
        "bearing_offset": "m",
        "guide_offset_u": "m",
        "guide_offset_w": "m",
        "stroke": "m",
        "rod_length_range": "m",
    }
    DESCRIPTION: ClassVar[str] = (
        "actuated prismatic on a rail, rod sliding in a bearing, revolute at the platform"
    )

    @model_validator(mode="after")
    def _ranges(self) -> PPRLeg:
        if not self.stroke[0] < self.stroke[1]:
            raise ValueError("stroke must be [min, max] with min < max")
        if not self.rod_length_range[0] < self.rod_length_range[1]:
            raise ValueError("rod_length_range must be [min, max] with min < max")
        if abs(np.sin(self.beta)) < 1e-3:
            raise ValueError("beta: the rod must not be parallel to the rail (sin(beta) = 0)")
        return self

    def directions(self) -> tuple[FloatArray, FloatArray]:
        """Rail direction u and rod direction w (unit, F_b)."""
        return unit_planar(self.alpha), unit_planar(self.alpha + self.beta)

    def base_feature(self, leg_pose: LegPose) -> BaseFeature:
        """The rail through ``base_point`` along u, over the stroke (pose-independent)."""
        return BaseFeature(
            "rail",
            planar(np.asarray(self.base_point)),
            self.directions()[0],
            (float(self.stroke[0]), float(self.stroke[1])),
        )

    def link_length_ranges(self) -> dict[str, tuple[float, float]]:
        """The carriage link's fixed length |C - B|; the rod's free length over its
        range."""
        u, w = self.directions()
        arm = float(
            np.linalg.norm(
                self.guide_offset_u * u + (self.guide_offset_w - self.bearing_offset) * w
            )
        )
        return {
            "proximal": (arm, arm),
            "distal": (self.rod_length_range[0], self.rod_length_range[1]),
        }

    def limits(self) -> dict[str, tuple[float, float]]:
        return {"rho": self.stroke, "rod": self.rod_length_range}

    def solve(self, poses: ArrayLike) -> LegPose:
        pose = as_poses(poses)
        u, w = self.directions()
        d = self.platform_offset(pose)
        p_abs = planar_position(pose)
        a = planar(np.asarray(self.base_point))
        r = p_abs + d - a
        det = cross_z(u, w)
        rho = cross_z(r, np.broadcast_to(w, r.shape)) / det
        along = cross_z(np.broadcast_to(u, r.shape), r) / det
        rod = along - self.bearing_offset
        c = a + rho[..., None] * u + self.bearing_offset * w - p_abs
        b = a + (rho[..., None] + self.guide_offset_u) * u + self.guide_offset_w * w - p_abs
        rail = a + rho[..., None] * u - p_abs
        return LegPose(
            poses=pose,
            points={"A": rail, "B": b, "C": c, "D": d},
            coordinates={"rho": rho, "rod": rod},
            solvable=np.ones(rho.shape, dtype=bool),
        )

    def joint_list(self, home: ArrayLike) -> dict[str, Any]:
        """This leg as a joint-list leg's table at the home pose (6,): the actuated P at
        the guide block B along the rail, carried by the carriage (``carried_by =
        "after"``: the guide's springs act at the moving block, and the proximal link
        from it keeps its length), its stroke the travel from the home rho; the proximal
        link, C at the bearing C along the rod (its ``travel`` the rod length range less
        the home rod length), the distal link (the rod, from the bearing), R at D about
        z."""
        h = np.asarray(home, dtype=float)
        points, coordinates = home_points(self, h)
        rho, rod = coordinates["rho"], coordinates["rod"]
        u, w = self.directions()
        return chain_table(
            self.law(),
            [
                joint_table(
                    "P",
                    "guide",
                    points["B"],
                    self.guide,
                    axis=u.tolist(),
                    actuated=True,
                    stroke=[self.stroke[0] - rho, self.stroke[1] - rho],
                    carried_by="after",
                ),
                link_table(self.proximal, "proximal"),
                joint_table(
                    "C",
                    "bearing",
                    points["C"],
                    self.bearing,
                    axis=w.tolist(),
                    travel=[self.rod_length_range[0] - rod, self.rod_length_range[1] - rod],
                ),
                link_table(self.distal, "distal"),
                joint_table(
                    "R",
                    "platform_revolute",
                    points["D"],
                    self.platform_revolute,
                    axis=[0.0, 0.0, 1.0],
                ),
            ],
        )

    def chain(self, leg_pose: LegPose) -> Sequence[Element]:
        u, w = self.directions()
        pts = leg_pose.points
        return [
            Joint(
                "P",
                u,
                pts["B"],
                self.guide.stiffnesses(),
                actuated=True,
                name="guide",
                mass=self.law().moving_parts(),
            ),
            Link(
                pts["B"],
                pts["C"],
                self.proximal.section(),
                name="proximal",
                mass=self.proximal.link_mass(),
            ),
            Joint("C", w, pts["C"], self.bearing.stiffnesses(), name="bearing"),
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
                None if self.platform_revolute is None else self.platform_revolute.stiffnesses(),
                name="platform_revolute",
            ),
        ]

    def reduced_form(self) -> Any | None:
        """The exact reduced form of :mod:`._ppr_reduced` (None when the leg does not
        have the structure it assumes, e.g. a compliant platform revolute)."""
        try:
            return reduce_ppr_leg(self)
        except DesignError:
            return None

    def limit_half_planes(self, phi: float) -> tuple[FloatArray, FloatArray] | None:
        """Stroke and rod-length limits at ``phi`` as half-planes in (x, y) [m].

        With ``r = D - A`` (D moves with P at fixed phi), ``rho = (r x w)_z / det`` and
        ``bearing_offset + rod = (u x r)_z / det``, ``det = (u x w)_z``: both affine in
        (x, y) with gradients ``(w_y, -w_x) / det`` and ``(-u_y, u_x) / det``.
        """
        u, w = self.directions()
        det = float(cross_z(u, w))
        grads = (np.array([w[1], -w[0]]) / det, np.array([-u[1], u[0]]) / det)
        at_origin = self.solve(np.array([0.0, 0.0, 0.0, 0.0, 0.0, float(phi)]))
        normals, offsets = [], []
        for grad, name in zip(grads, ("rho", "rod"), strict=True):
            lo, hi = self.limits()[name]
            q0 = float(at_origin.coordinates[name])
            normals += [grad, -grad]
            offsets += [hi - q0, q0 - lo]
        return np.array(normals), np.array(offsets)
