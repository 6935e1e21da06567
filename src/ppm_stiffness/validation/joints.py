"""A joint of the chain as FE elements between two coincident nodes, in any orientation.

A joint joins the node before it to a new node at the same point (the node after it).
In the joint frame (e1, e2, e3) (:meth:`ppm_stiffness.legs.chain.Joint.frame`), each of
the six relative motions (rotations about e1, e2, e3, translations along e1, e2, e3) is
free (a passive freedom: no element), a spring (a hardware spring, an elastic
freedom's stiffness, or the actuator along the actuated joint's freedom) or rigid (no
hardware spring given: a spring of the ``rigid`` scale, :attr:`FESettings.rigid_stiffness`):

* rotations: two *moment-only* members (all end forces released at a common auxiliary
  node X, X's translations supported) from the two nodes to X along one axis of the
  joint frame, turned so that their local axes are the joint frame; their
  ``GJ/L, EI_y/L, EI_z/L`` (each twice the spring, in series) are the three rotational
  springs; a free rotation is also released at X on the first member;
* translations: per constrained or actuated direction, two axial ``Spring3D`` of twice
  the stiffness in series through an auxiliary node Y on the line through the joint
  point along that direction; Y's rotations are supported and its two translations
  normal to the line are held, by supports along the global axes normal to the line
  and by grounded springs along the other normal directions (they act on nothing
  else).

Each element is exact in linear analysis, for any direction of the axes. Auxiliary
nodes are placed by :class:`Placement`: off every member, away from every node, and
no auxiliary member passes by a node (PyNite would split it there).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import LENGTH_SCALE, FloatArray
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.legs.chain import Joint, elastic_stiffnesses
from ppm_stiffness.legs.joint_kinds import JOINT_KINDS, joint_kind
from ppm_stiffness.validation.frame import FrameBuilder, unit_vector

#: Relative motions of a joint in its frame: 0-2 rotations about e1, e2, e3, 3-5
#: translations along e1, e2, e3 (:data:`MOTION`). Constrained ones, in the order of
#: the hardware springs, and freedoms (the actuated one first: the kind's FE releases),
#: from each kind's record (:mod:`ppm_stiffness.legs.joint_kinds`).
MOTION = {"r": 0, "t": 3}
CONSTRAINED_MOTIONS: dict[str, tuple[int, ...]] = {
    letter: tuple(MOTION[d] + k for d, k in record.constrained)
    for letter, record in JOINT_KINDS.items()
}
FREE_MOTIONS: dict[str, tuple[int, ...]] = {
    letter: record.fe_releases for letter, record in JOINT_KINDS.items()
}
#: Two points closer than this are the same point [m].
SAME_POINT = 1e-9
#: Auxiliary nodes keep this fraction of ``FESettings.connector_length`` from every
#: member and node.
CLEARANCE = 0.25
#: A spring axis with a component below this along a global axis is normal to it (its
#: auxiliary node is held along that axis by a support).
_NORMAL = 1e-12
_DOFS = ("DX", "DY", "DZ")
#: Candidate distances (in connector lengths) searched along each direction.
_MAX_STEPS = 64


def joint_stiffness(joint: Joint, actuator_stiffness: float) -> FloatArray:
    """Stiffness of a joint's six relative motions in its frame, shape (6,).

    Order: rotations about e1, e2, e3 [N·m/rad], translations along e1, e2, e3 [N/m].
    0 is a free motion, ``inf`` a rigid one (a constrained direction without a
    hardware spring, or an ``inf`` spring); an elastic freedom (a flexure) is a spring
    of its stiffness, added to the actuator's on the actuated joint (in parallel).

    Raises
    ------
    DesignError
        An unknown joint kind, springs of the wrong number or not positive.
    """
    record = joint_kind(joint.kind)
    k = np.zeros(6)
    constrained = CONSTRAINED_MOTIONS[record.letter]
    if joint.springs is None:
        k[list(constrained)] = np.inf
    else:
        springs = np.asarray(joint.springs, dtype=float)
        if springs.shape != (len(constrained),) or np.any(~(springs > 0)):
            raise DesignError(
                f"FE model, joint {joint.name or joint.kind}: {len(constrained)} positive "
                f"spring stiffnesses expected, got {springs}"
            )
        k[list(constrained)] = springs
    elastic = elastic_stiffnesses(joint)
    if elastic is not None:  # a flexure: a spring along each freedom
        for (motion, axis), stiffness in zip(record.freedoms, elastic, strict=True):
            k[MOTION[motion] + axis] = stiffness
    if joint.actuated:
        k[record.fe_releases[0]] = actuator_stiffness + (0.0 if elastic is None else elastic[0])
    return k


def normal_pair(axis: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Two unit vectors normal to ``axis`` and to each other."""
    a = unit_vector(axis)
    helper = np.eye(3)[int(np.argmin(np.abs(a)))]
    u = unit_vector(np.cross(a, helper))
    return u, np.cross(a, u)


@dataclass
class Placement:
    """Where auxiliary nodes may go: clear of every member and node of the model.

    ``segments`` are the members (structural ones planned before any joint is built,
    auxiliary ones as they are added), ``points`` every node position [m].
    """

    spacing: float
    segments: list[tuple[FloatArray, FloatArray]] = field(default_factory=list)
    points: list[FloatArray] = field(default_factory=list)

    @property
    def margin(self) -> float:
        return CLEARANCE * self.spacing

    def add_point(self, q: ArrayLike) -> None:
        self.points.append(np.asarray(q, dtype=float))

    def add_segment(self, a: ArrayLike, b: ArrayLike) -> None:
        self.segments.append((np.asarray(a, dtype=float), np.asarray(b, dtype=float)))

    def point_clear(self, q: FloatArray) -> bool:
        """``q`` is farther than the margin from every member and node."""
        if self.points:
            pts = np.array(self.points)
            if np.min(np.linalg.norm(pts - q, axis=1)) <= self.margin:
                return False
        if self.segments:
            a = np.array([s[0] for s in self.segments])
            b = np.array([s[1] for s in self.segments])
            if np.min(_distance_to_segments(q, a, b)) <= self.margin:
                return False
        return True

    def segment_clear(self, a: FloatArray, b: FloatArray) -> bool:
        """No node other than those at ``a`` lies within the margin of segment a-b."""
        if not self.points:
            return True
        pts = np.array(self.points)
        others = pts[np.linalg.norm(pts - a, axis=1) > SAME_POINT]
        if len(others) == 0:
            return True
        d = distance_to_segment(others, a, b)
        return bool(np.min(d) > self.margin)

    def find(
        self,
        origin: FloatArray,
        directions: Sequence[FloatArray],
        first_step: int,
        member: bool,
        label: str,
    ) -> tuple[FloatArray, int]:
        """The nearest clear point ``origin + step * spacing * d`` (steps from
        ``first_step``, directions in order at each step); with ``member`` the segment
        from ``origin`` must be clear too. Returns the point and the direction's index.

        Raises
        ------
        DesignError
            If no clear point is found (members and nodes everywhere around).
        """
        for step in range(first_step, first_step + _MAX_STEPS):
            for i, d in enumerate(directions):
                q = origin + step * self.spacing * d
                if self.point_clear(q) and (not member or self.segment_clear(origin, q)):
                    return q, i
        raise DesignError(  # pragma: no cover - needs members everywhere around a joint
            f"FE model, {label}: no room for an auxiliary node (change FESettings.connector_length)"
        )


def _distance_to_segments(q: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
    """Distance (n,) of point ``q`` (3,) to segments ``a``-``b`` (n, 3)."""
    ab = b - a
    den = np.einsum("ij,ij->i", ab, ab)
    t = np.clip(np.einsum("ij,ij->i", q - a, ab) / np.where(den > 0, den, 1.0), 0.0, 1.0)
    return np.asarray(np.linalg.norm(q - (a + t[:, None] * ab), axis=1))


def distance_to_segment(q: FloatArray, a: FloatArray, b: FloatArray) -> FloatArray:
    """Distance (n,) of points ``q`` (n, 3) to one segment ``a``-``b``."""
    ab = b - a
    t = np.clip((q - a) @ ab / float(ab @ ab), 0.0, 1.0)
    return np.asarray(np.linalg.norm(q - (a + t[:, None] * ab), axis=1))


def _rigid(fb: FrameBuilder) -> tuple[float, float]:
    """Stiffness of a rigid joint direction: rotation [N·m/rad], translation [N/m]."""
    k = fb.settings.rigid_stiffness
    return k * LENGTH_SCALE**2, k


def add_rotations(
    fb: FrameBuilder,
    plan: Placement,
    nodes: tuple[str, str],
    point: FloatArray,
    frame: tuple[FloatArray, FloatArray, FloatArray],
    k_rot: FloatArray,
    label: str,
) -> None:
    """Rotational springs of a joint: two moment-only members through X (module doc).

    The members lie along the frame axis nearest to z that leaves room (for a planar
    mechanism: normal to its plane, above or below it).
    """
    if not np.any(k_rot != 0):
        return
    before, after = nodes
    order = sorted(range(3), key=lambda i: -abs(float(frame[i][2])))
    directions = [sign * frame[i] for i in order for sign in (1.0, -1.0)]
    pos, which = plan.find(point, directions, 1, True, label)
    i_x = order[which // 2]
    x_axis = directions[which]
    i_y, i_z = (i_x + 1) % 3, (i_x + 2) % 3
    y_axis = frame[i_y]
    if abs(abs(float(np.cross(x_axis, y_axis) @ frame[i_z])) - 1.0) > 1e-9:
        raise DesignError(f"FE model, {label}: joint frame is not orthonormal")
    k = np.array([k_rot[i_x], k_rot[i_y], k_rot[i_z]])
    free = (bool(k[0] == 0), bool(k[1] == 0), bool(k[2] == 0))
    k = np.where(np.isinf(k), _rigid(fb)[0], k)
    hold = float(np.max(k))  # the second member holds X about the free axes
    x_node = fb.node(pos, "X")
    plan.add_point(pos)
    plan.add_segment(point, pos)
    fb.support(x_node, "DX DY DZ")
    fb.moment_member(before, x_node, (x_axis, y_axis), 2.0 * np.where(free, 1.0, k), free)
    fb.moment_member(
        after, x_node, (x_axis, y_axis), 2.0 * np.where(free, hold, k), (False, False, False)
    )


def add_translation(
    fb: FrameBuilder,
    plan: Placement,
    nodes: tuple[str, str],
    point: FloatArray,
    axis: FloatArray,
    stiffness: float,
    label: str,
) -> None:
    """A translational spring along ``axis``: two Spring3D in series through Y, whose
    other translations are held by two grounded springs normal to ``axis``."""
    before, after = nodes
    a = unit_vector(axis)
    # step 1 is left to the moment-only members of rotations
    pos, _ = plan.find(point, [a, -a], 2, False, label)
    plan.add_point(pos)
    y_node = fb.node(pos, "Y")
    # global axes normal to the spring are held by supports, the rest by springs
    held = [i for i in range(3) if abs(float(a[i])) <= _NORMAL]
    fb.support(y_node, " ".join(["RX RY RZ", *(_DOFS[i] for i in held)]))
    if len(held) == 1:
        holders: tuple[FloatArray, ...] = (unit_vector(np.cross(np.eye(3)[held[0]], a)),)
    else:
        holders = normal_pair(a) if not held else ()
    for d in holders:
        ground, _ = plan.find(pos, [d, -d], 1, False, label)
        plan.add_point(ground)
        fb.axial_spring(y_node, fb.ground(ground), stiffness)
    fb.axial_spring(before, y_node, 2.0 * stiffness)
    fb.axial_spring(y_node, after, 2.0 * stiffness)


def add_joint(
    fb: FrameBuilder,
    plan: Placement,
    before: str,
    joint: Joint,
    k_act: float,
    label: str,
    after: str | None = None,
) -> str:
    """Add one joint after node ``before`` (module doc); returns the node after it
    (``after`` if given: a node at the joint's point, such as a platform node)."""
    point = np.asarray(joint.point, dtype=float)
    if point.shape != (3,):
        raise DesignError(f"FE model: one pose at a time, got a point of shape {point.shape}")
    e1, e2, e3 = (np.asarray(e, dtype=float) for e in joint.frame())
    frame = (e1, e2, e3)
    k = joint_stiffness(joint, k_act)
    out = fb.node(point, "J") if after is None else after
    add_rotations(fb, plan, (before, out), point, frame, k[:3], label)
    k_trans = np.where(np.isinf(k[3:]), _rigid(fb)[1], k[3:])
    for i in range(3):
        if k_trans[i] > 0:
            add_translation(fb, plan, (before, out), point, frame[i], float(k_trans[i]), label)
    return out
