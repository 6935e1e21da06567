"""The geometry every mechanism picture draws: legs at a pose, in F_b, as the model has it.

One source for the planar top view (:mod:`ppm_stiffness.visuals.mechanism`), the 3-D
view (:mod:`ppm_stiffness.visuals.mechanism3d`) and the backdrop of the screw-spring
picture (:mod:`ppm_stiffness.visuals.springs`): each leg's named points, joints (kind,
point, axes, actuated) and links come from its inverse kinematics
(:meth:`~ppm_stiffness.legs.base.LegModel.solve`) and joint chain
(:meth:`~ppm_stiffness.legs.base.LegModel.chain`) at the full 6-D pose
(:mod:`ppm_stiffness.poses`), moved from "relative to P" to absolute positions in F_b
[m]; the base feature and the violated limits come from the leg as well. Nothing here
knows a leg type's name.

The pose may be the design's task coordinates or a full pose (x, y, z, rx, ry, rz)
[m, rad]; a planar design's (x, y, phi) is its task coordinates. It is completed
(the parasitic coordinates of a tripod) but not checked against the legs' limits: a
picture may show an unreachable pose and name what is violated.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.design import Design
from ppm_stiffness.legs.base import BaseFeature, LegModel, LegPose, within_limits
from ppm_stiffness.legs.chain import Element, Joint, Link
from ppm_stiffness.legs.joint_kinds import joint_kind
from ppm_stiffness.poses import dependent_indices, full_pose, task_indices

MM = 1e3


@dataclass(frozen=True)
class JointView:
    """One joint of a leg at the pose (absolute, F_b).

    Attributes
    ----------
    kind : {"R", "P", "C", "U", "S"}
    point : ndarray (3,) [m]
    axis : ndarray (3,), unit
        e1 (an S joint: the direction that orients its springs).
    axis2 : ndarray (3,) or None
        The second axis e2 (unit) of a kind that has one (a U); None for the others.
    actuated : bool
    name : str
        The part's name in the design (``guide``, ``base_joint``, ...).
    """

    kind: str
    point: FloatArray
    axis: FloatArray
    axis2: FloatArray | None
    actuated: bool
    name: str


@dataclass(frozen=True)
class LinkView:
    """One link of a leg at the pose: a bar from ``start`` to ``end`` (F_b) [m]."""

    start: FloatArray
    end: FloatArray
    name: str


@dataclass(frozen=True)
class LegView:
    """One leg at one pose, ready to draw (absolute positions in F_b, [m]).

    Attributes
    ----------
    index : int
        Leg number, from 1.
    leg_pose : LegPose
        The leg's inverse kinematics at the pose (points relative to P).
    points : dict of str to ndarray (3,)
        The named points of ``leg_pose`` in F_b, base to platform [m].
    chain : sequence of Joint and Link, or None
        The joint chain at the pose (relative to P); None when the inverse kinematics
        has no solution.
    base : BaseFeature
    violations : list of str
        The violated limits (display units), or the missing IK solution.
    joints : list of JointView
        The chain's joints in F_b, base to platform (empty when unsolvable).
    links : list of LinkView
        The chain's links in F_b, base to platform (empty when unsolvable).
    platform_point : ndarray (3,) [m]
        Where the leg holds the platform (``p + R b``), solvable or not.
    """

    index: int
    leg_pose: LegPose
    points: dict[str, FloatArray]
    chain: Sequence[Element] | None
    base: BaseFeature
    violations: list[str]
    joints: list[JointView]
    links: list[LinkView]
    platform_point: FloatArray

    @property
    def solvable(self) -> bool:
        """The inverse kinematics has a solution (the leg is drawn)."""
        return self.chain is not None

    @property
    def platform_name(self) -> str:
        """The name of the leg's platform point with its number (``D1``, ``B1``)."""
        return f"{list(self.points)[-1]}{self.index}"


@dataclass(frozen=True)
class MechanismView:
    """A design at one pose, everything a picture needs (F_b, [m]).

    Attributes
    ----------
    design : Design
    pose : ndarray (6,)
        The full pose (x, y, z [m], rx, ry, rz [rad]).
    legs : list of LegView
    platform : ndarray (n_legs, 3)
        The legs' platform points, in leg order.
    platform_order : list of int
        Leg indices (from 0) of the platform polygon, counter-clockwise about the
        platform's z axis seen from above, from leg 1.
    tool : ndarray (3,)
        The tool point ``p + R t``.
    """

    design: Design
    pose: FloatArray
    legs: list[LegView]
    platform: FloatArray
    platform_order: list[int]
    tool: FloatArray

    @property
    def centre(self) -> FloatArray:
        """P in F_b (3,) [m]."""
        return np.asarray(self.pose[:3])

    @property
    def rotation(self) -> FloatArray:
        """R (3, 3): the platform axes (columns) in F_b."""
        return np.asarray(pose6.rotation(self.pose))

    @property
    def has_tool(self) -> bool:
        """The design has a tool point other than P."""
        return bool(np.any(np.asarray(self.design.tool_point) != 0.0))

    @property
    def violations(self) -> bool:
        """Some leg violates a limit or has no inverse-kinematics solution."""
        return any(v.violations for v in self.legs)


def display(value: float, si_unit: str) -> tuple[float, str]:
    """An SI joint coordinate in the picture's units: m -> mm, rad -> deg."""
    return (value * MM, "mm") if si_unit == "m" else (float(np.degrees(value)), "deg")


def limit_violations(leg: LegModel, leg_pose: LegPose) -> list[str]:
    """Every limit of ``leg`` violated at one pose, e.g. ``"rod free length 35.00 mm
    outside [1.00, 30.00] mm"``; ``["no inverse-kinematics solution (not drawn)"]`` if
    the inverse kinematics has no solution."""
    if not bool(np.all(leg_pose.solvable)):
        return ["no inverse-kinematics solution (not drawn)"]
    out = []
    for name, (lo, hi) in leg.limits().items():
        q = float(leg_pose.coordinates[name])
        if not within_limits(q, lo, hi):  # the model's own test (round-off at the ends)
            c = leg.coordinate(name)
            v, unit = display(q, c.unit)
            a, _ = display(lo, c.unit)
            b, _ = display(hi, c.unit)
            out.append(f"{c.label} {v:.2f} {unit} outside [{a:.2f}, {b:.2f}] {unit}")
    return out


def _joint_view(joint: Joint, origin: FloatArray) -> JointView:
    two_axes = joint_kind(joint.kind).second_axis
    e1, e2, _ = joint.frame() if two_axes else (np.asarray(joint.axis), None, None)
    return JointView(
        kind=joint.kind,
        point=np.asarray(joint.point, dtype=float).reshape(3) + origin,
        axis=np.asarray(e1, dtype=float).reshape(3) / float(np.linalg.norm(e1)),
        axis2=None if e2 is None else np.asarray(e2, dtype=float).reshape(3),
        actuated=joint.actuated,
        name=joint.name,
    )


def leg_view(leg: LegModel, index: int, pose: FloatArray) -> LegView:
    """One leg of a design at one full pose (6,) (:class:`LegView`)."""
    origin = np.asarray(pose[:3], dtype=float)
    lp = leg.solve(pose)
    solvable = bool(np.all(lp.solvable))
    chain = leg.chain(lp) if solvable else None
    elements = list(chain or [])
    if solvable:
        links, joints = leg.drawn_members(lp)
        elements += [*links, *joints]
    return LegView(
        index=index,
        leg_pose=lp,
        points={k: np.asarray(v, dtype=float).reshape(3) + origin for k, v in lp.points.items()},
        chain=chain,
        base=leg.base_feature(lp),
        violations=limit_violations(leg, lp),
        joints=[
            _joint_view(e, origin) for e in elements if isinstance(e, Joint) and not e.equivalent
        ],
        links=[
            LinkView(
                np.asarray(e.start, dtype=float).reshape(3) + origin,
                np.asarray(e.end, dtype=float).reshape(3) + origin,
                e.name,
            )
            for e in elements
            if isinstance(e, Link)
        ],
        platform_point=np.asarray(leg.platform_offset(pose), dtype=float).reshape(3) + origin,
    )


def platform_order(d: ArrayLike, centre: ArrayLike) -> list[int]:
    """Indices of the platform points D_i counter-clockwise around P, from the first
    on the polygon's rim (D_1 unless it is inside).

    A point strictly inside the polygon of the others (a Tricept's central tube, fixed
    at P) is no corner of it: it is left out while three or more points remain.

    Parameters
    ----------
    d : array_like (n, 2) or (n, 3)
        The points; only their first two coordinates count (give them in the
        platform frame for a platform out of the plane).
    centre : array_like (2,) or (3,)
    """
    rel = np.asarray(d, dtype=float)[:, :2] - np.asarray(centre, dtype=float)[:2]
    rim = [i for i in range(len(rel)) if not _inside_others(rel, i)]
    if len(rim) < 3:
        rim = list(range(len(rel)))
    ring = rel[rim] - rel[rim].mean(axis=0) if len(rim) < len(rel) else rel
    order = [rim[int(k)] for k in np.argsort(np.arctan2(ring[:, 1], ring[:, 0]))]
    start = order.index(min(order))
    return order[start:] + order[:start]


def _inside_others(points: FloatArray, index: int) -> bool:
    """Whether point ``index`` of ``points`` (n, 2) lies strictly inside the polygon of
    the others taken in angular order about their mean (n >= 4; an even-odd ray test,
    a margin of 1e-9 of the polygon's size)."""
    if len(points) < 4:
        return False
    others = np.delete(points, index, axis=0)
    mean = others.mean(axis=0)
    rel = others - mean
    ring = others[np.argsort(np.arctan2(rel[:, 1], rel[:, 0]))]
    p = points[index]
    margin = 1e-9 * float(np.max(np.abs(rel)))
    inside = False
    for a, b in zip(ring, np.roll(ring, -1, axis=0), strict=True):
        edge = b - a
        cross = edge[0] * (p[1] - a[1]) - edge[1] * (p[0] - a[0])
        if abs(cross) <= margin * float(np.hypot(*edge)):
            on_segment = np.dot(p - a, edge) >= 0 and np.dot(p - b, -edge) >= 0
            if on_segment:
                return False  # on an edge: a corner of the rim
        if (a[1] > p[1]) != (b[1] > p[1]):
            x = a[0] + (p[1] - a[1]) * edge[0] / edge[1]
            inside ^= bool(p[0] < x)
    return inside


def mechanism_view(design: Design, pose: ArrayLike | None = None) -> MechanismView:
    """Every leg of ``design`` at one pose, reachable or not (module doc).

    Parameters
    ----------
    design : Design
    pose : array_like (n_task,) or (6,), optional
        Task coordinates or a full pose [m, rad]; the home pose if None.

    Raises
    ------
    InputDataError, UnreachablePoseError
        As :func:`ppm_stiffness.poses.full_pose`: a pose of the wrong width, a
        dependent coordinate given another value, or a completion that fails.
    """
    p = full_pose(design, pose)
    legs = [leg_view(leg, i, p) for i, leg in enumerate(design.legs, start=1)]
    platform = np.array([v.platform_point for v in legs])
    # the order about the platform's own z axis (its frame: R^T (d - p))
    local = (platform - p[:3]) @ pose6.rotation(p)
    tool = p[:3] + pose6.platform_offset(p, np.asarray(design.tool_point, dtype=float))
    return MechanismView(
        design=design,
        pose=p,
        legs=legs,
        platform=platform,
        platform_order=platform_order(local, np.zeros(3)),
        tool=np.asarray(tool),
    )


def _coordinate(name: str, value: float, decimals: int) -> str:
    if name in pose6.ANGLE_COORDINATES:
        return f"{name} = {math.degrees(value):.{decimals}f} deg"
    return f"{name} = {value * MM:.{decimals}f} mm"


def pose_text(design: Design, pose: FloatArray) -> str:
    """The pose for a title: a planar design's ``pose x = .. mm, y = .. mm, phi = ..
    deg``; a spatial design's task coordinates, then its parasitic coordinates (those
    the legs impose; finer digits, they are small) if it has any."""
    p = np.asarray(pose, dtype=float)
    if design.planar:
        return (
            f"pose x = {p[0] * MM:.2f} mm, y = {p[1] * MM:.2f} mm, phi = {np.degrees(p[5]):.2f} deg"
        )
    names = pose6.POSE_COORDINATES
    text = "task " + ", ".join(_coordinate(names[i], p[i], 2) for i in task_indices(design))
    dependent = dependent_indices(design)
    if dependent:
        text += "; parasitic " + ", ".join(_coordinate(names[i], p[i], 4) for i in dependent)
    return text


def _join_lines(parts: list[str], width: int) -> list[str]:
    """``parts`` joined by "; " into lines of at most ``width`` characters, a part
    never split (one longer than ``width`` has a line of its own)."""
    lines: list[str] = []
    for part in parts:
        if lines and len(lines[-1]) + 2 + len(part) <= width:
            lines[-1] += "; " + part
        else:
            lines.append(part)
    return lines


def title_text(view: MechanismView, head: str | None = None, width: int = 110) -> str:
    """The picture's title: the design and pose (or ``head``), each joint coordinate of
    every leg (mm, deg), and every violated limit after ``UNREACHABLE:``."""
    design = view.design
    lines = [head or f"{design.name} ({design.architecture})\n{pose_text(design, view.pose)}"]
    names: list[str] = []
    units: dict[str, str] = {}
    for leg in design.legs:
        for name in leg.coordinate_names():
            c = leg.coordinate(name)
            if name not in names:
                names.append(name)
                units[name] = c.unit
    parts = []
    for name in names:
        vals = []
        for v in view.legs:
            q = v.leg_pose.coordinates.get(name)
            vals.append(
                "–" if q is None or not v.solvable else f"{display(float(q), units[name])[0]:.1f}"
            )
        parts.append(f"{name} [{display(0.0, units[name])[1]}] = ({', '.join(vals)})")
    lines += _join_lines(parts, width)
    bad = [f"leg {v.index}: " + ", ".join(v.violations) for v in view.legs if v.violations]
    if bad:
        lines += textwrap.wrap("UNREACHABLE: " + "; ".join(bad), width, break_on_hyphens=False)
    return "\n".join(lines)


__all__ = [
    "JointView",
    "LegView",
    "LinkView",
    "MechanismView",
    "display",
    "leg_view",
    "limit_violations",
    "mechanism_view",
    "platform_order",
    "pose_text",
    "title_text",
]
