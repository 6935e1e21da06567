"""The manipulator at a pose as a 3D frame model in PyNite, and its stiffness at P.

Why PyNite (``pynitefea``): its frame members are Euler-Bernoulli, the beam theory of
the paper's eq. (3c), so the two models share their beam theory and differ only in
how they are built and solved; member-end releases and two-node axial springs give
exact lumped springs. pyfe3d (Timoshenko beams, 6-component springs) would add shear
deformation the virtual-joint model does not have.

Model (coordinates: F_b axes, origin at P; PyNite's global X, Y, Z are our x, y, z)
----------------------------------------------------------------------------------
Every leg is built from its joint chain (:meth:`LegModel.chain`, the same chain the
virtual-joint model reads) at the full pose (x, y, z, rx, ry, rz), walked from the base
to the platform:

* a **link** is an Euler-Bernoulli member from a node at its start to a node at its
  end with the link's section, its section axes those of the link frame (built as two
  members, see ``FrameBuilder.segment``, meeting at the middle or, for a link given as
  a body whose centre lies inside it, at that centre: :func:`link_split`);
* a **joint** (R, P, C, U or S, any axes) joins the node before it (a grounded node
  for the first joint) to a new node at the same point (the node after it):
  moment-only members for its rotations, axial springs through auxiliary nodes for
  its translations, nothing for its passive freedoms (:mod:`.joints`);
* a **notch hinge** (a chain leg's R with a ``hinge`` table, no beam link beside it) is
  the notch itself, ``FESettings.hinge_segments`` beam members from its base-side end to
  its platform-side end (:mod:`.hinge_chain`), not the model's lumped elastic R;
* a link that does not start at the previous joint's point, or a joint away from the
  previous link's end, is joined by a stiff member (a rigid body in the chain);
* the **platform**: one node per distinct platform point (the point of each leg's last
  joint; legs meeting at one point share it, a point at P is P's node), each joined by
  a stiff member to P, or to the farthest other platform point on its way to P (so
  that no member passes through a node): a stiff frame joining the legs' platform
  points and P, for any platform geometry.

Every spring realisation is exact in linear analysis. The approximations are the
finite stiffness of the platform members and of the rigid joint directions, both
set by ``FESettings.rigid_stiffness`` (translations: that value [N/m]; rotations:
that value times ``LENGTH_SCALE**2`` [N·m/rad]); the difference to the virtual-joint
model scales as its inverse. The stiffness at P comes from six unit-load cases at P
(moments, then forces, along the base axes): the displacements are the compliance
columns, ``K = inv(C)``.

Only the chain (points, axes, joint kinds, springs, sections) and the design's numbers
are shared with the virtual-joint model: :mod:`ppm_stiffness.core.solver`,
:mod:`ppm_stiffness.legs.engine`, :func:`ppm_stiffness.core.beam.cantilever_compliance`
and :func:`ppm_stiffness.legs.chain.leg_springs` are not used.

Reuse. :func:`build_model` returns the builder and P's node with no load on it: a
caller may add its own load cases at P (or elsewhere) and run any PyNite analysis
(linear, P-Delta) on ``builder.model``; :func:`compliance_at_node` is the one used here.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, length_balanced_compliance
from ppm_stiffness.core.errors import DesignError, SingularConfigurationError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import leg_label
from ppm_stiffness.legs.chain import Element, Joint, Link, frame_from_axis
from ppm_stiffness.legs.flexure_hinge import FlexureHinge
from ppm_stiffness.legs.types._parallelogram import RIGID_PART
from ppm_stiffness.model import actuator_stiffness_vector, solve_legs, validate_pose
from ppm_stiffness.validation.frame import (
    DISPLACEMENTS,
    REACTIONS,
    FESettings,
    FrameBuilder,
    analyze_linear,
    compliance_at_node,
    fe_cantilever_compliance,
    node_vector,
    require_pynite,
    unit_scales,
)
from ppm_stiffness.validation.hinge_chain import add_hinge, notch_ends, notch_points
from ppm_stiffness.validation.joints import (
    SAME_POINT,
    Placement,
    add_joint,
    distance_to_segment,
    joint_stiffness,
    normal_pair,
)

__all__ = [
    "FEResult",
    "FESettings",
    "build_model",
    "fe_cantilever_compliance",
    "fe_leg_stiffness",
    "fe_stiffness_at_pose",
    "joint_stiffness",
    "require_pynite",
]


@dataclass(frozen=True)
class FEResult:
    """The FE stiffness at P and facts about the model that produced it.

    Attributes
    ----------
    stiffness : ndarray, shape (6, 6)
        ``inv(compliance)``, symmetrised, at P with the axes of F_b (SI, library order).
    compliance : ndarray, shape (6, 6)
        Displacements of P under the six unit loads (columns), as solved.
    asymmetry : float
        ``max|C - C^T|`` relative to ``max|C|`` after length balancing
        (Maxwell-Betti reciprocity check of the solution).
    n_nodes, n_members, n_springs : int
        Size of the PyNite model.
    """

    stiffness: FloatArray
    compliance: FloatArray
    asymmetry: float
    n_nodes: int
    n_members: int
    n_springs: int


def _point(v: ArrayLike) -> FloatArray:
    p = np.asarray(v, dtype=float)
    if p.shape != (3,):
        raise DesignError(f"FE model: one pose at a time, got a point of shape {p.shape}")
    return p


def _same(a: FloatArray, b: FloatArray) -> bool:
    return bool(np.linalg.norm(a - b) <= SAME_POINT)


#: A leg's notch hinges built as beam chains: chain index -> the hinge.
Hinges = dict[int, FlexureHinge]

#: A link body's centre closer than this fraction of the link's length to an end is
#: carried by that end's node on a rigid offset (no member shorter than that).
END_MARGIN = 1e-3


def body_station(link: Link) -> float | None:
    """Where a link given as a body has its centre: the distance [m] from the link's
    start along it (negative behind the start, beyond its length past the end), as
    the design gives it (``LinkMass``: ``centre`` from the start, or from the end with
    ``from_end``; the middle when only an inertia is given); None for a uniform link
    (no body: no ``centre`` and no ``transverse``) or a massless one."""
    body = link.mass
    if body is None or (body.centre is None and body.transverse is None):
        return None
    length = float(np.linalg.norm(_point(link.end) - _point(link.start)))
    if body.centre is None:
        return 0.5 * length
    return length - body.centre if body.from_end else float(body.centre)


def link_split(link: Link) -> float:
    """The fraction of a link's length from its start at which the frame's two members
    of the link meet (:meth:`FrameBuilder.segment`): its body's centre when that lies
    inside the link (more than :data:`END_MARGIN` from both ends), so that the body
    sits on a node of the beam; else the middle."""
    station = body_station(link)
    if station is None:
        return 0.5
    length = float(np.linalg.norm(_point(link.end) - _point(link.start)))
    xi = station / length
    return xi if END_MARGIN < xi < 1.0 - END_MARGIN else 0.5


def _end_point(chain: Sequence[Element], hinges: Hinges) -> FloatArray:
    last = chain[-1]
    if isinstance(last, Joint) and len(chain) - 1 in hinges:
        return _point(notch_ends(last, hinges[len(chain) - 1])[1])
    return _point(last.end if isinstance(last, Link) else last.point)


def _leg_hinges(design: Design, leg: int, chain: Sequence[Element], segments: int) -> Hinges:
    """The chain's notch hinges built as beam chains (:mod:`.hinge_chain`): every R
    joint of a chain leg with a ``hinge`` table, when ``segments`` > 0 and no beam link
    touches it (a link from the notch's centre would overlap the notch's members; such
    a hinge stays an elastic R, as in the virtual-joint model)."""
    from ppm_stiffness.legs.types.chain_leg import ChainLeg, JointElement

    model = design.legs[leg]
    if segments <= 0 or not isinstance(model, ChainLeg):
        return {}
    by_name = {
        model.element_name(k): e.hinge
        for k, e in enumerate(model.elements)
        if isinstance(e, JointElement) and e.hinge is not None
    }
    out: Hinges = {}
    for n, element in enumerate(chain):
        if not isinstance(element, Joint) or element.name not in by_name:
            continue
        beside = [chain[m] for m in (n - 1, n + 1) if 0 <= m < len(chain)]
        if not any(isinstance(e, Link) for e in beside):
            hinge = by_name[element.name]
            assert hinge is not None
            out[n] = hinge
    return out


def _platform_parents(points: list[FloatArray]) -> list[int]:
    """For each distinct platform point, the index of the point its stiff member goes
    to: the farthest other platform point lying on its segment to P (strictly inside),
    or -1 for P itself."""
    parents = []
    for i, q in enumerate(points):
        best, best_d = -1, 0.0
        qq = float(q @ q)
        for j, r in enumerate(points):
            if j == i:
                continue
            t = float(r @ q) / qq
            if 0.0 < t < 1.0 and np.linalg.norm(r - t * q) <= SAME_POINT and t > best_d:
                best, best_d = j, t
        parents.append(best)
    return parents


def _bend(plan: Placement, a: FloatArray, b: FloatArray) -> FloatArray | None:
    """None when the platform's stiff member a-b passes clear of every planned node
    (those at its ends aside); else a corner point off the line, clear of members and
    nodes, through which it goes instead (two stiff members: PyNite would otherwise
    split the member at a node lying on it, another leg's joint on the line from a
    platform point to P)."""
    if not plan.points:
        return None
    pts = np.array(plan.points)
    others = pts[
        (np.linalg.norm(pts - a, axis=1) > SAME_POINT)
        & (np.linalg.norm(pts - b, axis=1) > SAME_POINT)
    ]
    if len(others) == 0 or np.min(distance_to_segment(others, a, b)) > plan.margin:
        return None
    length = float(np.linalg.norm(b - a))
    u, v = normal_pair(b - a)
    directions = [d for w in (u, v) for d in (w, -w)]
    mid = 0.5 * (a + b)
    for step in range(1, 40):
        for d in directions:
            q = mid + (0.05 * step * length) * d
            if plan.point_clear(q) and all(
                np.min(distance_to_segment(others, *seg)) > plan.margin for seg in ((a, q), (q, b))
            ):
                return q
    raise DesignError("FE model: no room to join a platform point to P clear of the legs")


def _plan_structure(
    chains: Sequence[Sequence[Element]], plan: Placement, hinges: Sequence[Hinges], segments: int
) -> None:
    """Record every structural member (links, rigid offsets, notch chains) and node
    position of the chains (the platform is added by :func:`build_model`)."""
    for chain, notches in zip(chains, hinges, strict=True):
        pos: FloatArray | None = None
        for n, element in enumerate(chain):
            if isinstance(element, Joint) and n in notches:
                points = notch_points(element, notches[n], segments)
                if pos is not None and not _same(points[0], pos):
                    plan.add_segment(pos, points[0])
                    plan.add_point(0.5 * (pos + points[0]))
                # its ends only: the notch's line (a planned member) keeps auxiliary
                # nodes off its inner nodes, which would otherwise block the platform's
                # member from its far end (they lie within the margin of its start)
                plan.add_segment(points[0], points[-1])
                plan.add_point(points[0])
                plan.add_point(points[-1])
                pos = points[-1]
                continue
            if isinstance(element, Link):
                start, end = _point(element.start), _point(element.end)
                if pos is not None and not _same(start, pos):
                    plan.add_segment(pos, start)
                    plan.add_point(0.5 * (pos + start))
                plan.add_segment(start, end)
                plan.add_point(start)
                at = link_split(element)
                plan.add_point((1.0 - at) * start + at * end)
                plan.add_point(end)
                pos = end
            else:
                point = _point(element.point)
                if pos is not None and not _same(point, pos):
                    plan.add_segment(pos, point)
                    plan.add_point(0.5 * (pos + point))
                plan.add_point(point)
                pos = point


def _add_leg(
    fb: FrameBuilder,
    plan: Placement,
    chain: Sequence[Element],
    k_act: float,
    platform_node: str,
    label: str,
    members: tuple[list[Link], list[Joint]] = ([], []),
    hinges: Hinges | None = None,
) -> None:
    """Add one leg's chain from the ground to its platform node (module doc); an
    element modelled by an equivalent chain (a parallelogram) is built from its own
    ``members`` instead (:func:`_add_bars`), a notch hinge in ``hinges`` as a chain of
    beam members from its base-side end to its platform-side end (:mod:`.hinge_chain`)."""
    notches = hinges or {}
    if not chain or not isinstance(chain[0], Joint):
        raise DesignError(f"FE model, {label}: the chain must start with a joint at the base")
    current: str | None = None
    pos = np.zeros(3)
    last = len(chain) - 1
    for n, element in enumerate(chain):
        if isinstance(element, Joint) and element.equivalent:
            if current is None:
                raise DesignError(f"FE model, {label}: the chain must start with a joint")
            _add_bars(fb, plan, current, members, platform_node, label)
            return
        name = f"{label}, {element.name or type(element).__name__.lower()} (element {n + 1})"
        out = platform_node if n == last else None
        if isinstance(element, Link):
            start, end = _point(element.start), _point(element.end)
            if np.linalg.norm(end - start) <= SAME_POINT:
                raise DesignError(f"FE model, {name}: zero-length link")
            if current is None:  # pragma: no cover - excluded above
                raise DesignError(f"FE model, {label}: the chain must start with a joint")
            if not _same(start, pos):
                offset = fb.node(start, "O")
                fb.rigid(current, offset)
                current = offset
            tip = fb.node(end, "L") if out is None else out
            fb.link(current, tip, element.section, link_split(element))
            current, pos = tip, end
        else:
            notch = notches.get(n)
            point, end = (
                (_point(element.point), _point(element.point))
                if notch is None
                else (_point(q) for q in notch_ends(element, notch))
            )
            if current is None:
                before = fb.ground(point)
            elif not _same(point, pos):
                before = fb.node(point, "O")
                fb.rigid(current, before)
            else:
                before = current
            if notch is None:
                current = add_joint(fb, plan, before, element, k_act, name, out)
            else:
                segments = fb.settings.hinge_segments
                current = add_hinge(fb, plan, before, element, notch, segments, k_act, name, out)
            pos = end


def _add_bars(
    fb: FrameBuilder,
    plan: Placement,
    near_body: str,
    members: tuple[list[Link], list[Joint]],
    platform_node: str,
    label: str,
) -> None:
    """A parallelogram's own members: per bar (its corner joints in pairs, near and
    far), a stiff crossbar from the near body's node to the near corner, the corner
    joint, the bar (a beam, or stiff for rigid bars), the far corner joint and a stiff
    crossbar to the platform node. The far corner stands as a U blocking the bar's spin
    about its own axis (an internal mechanism of a ball-jointed bar, which transmits no
    moment about it either way: the transmitted stiffness is unchanged)."""
    links, joints = members
    for near, far in zip(joints[0::2], joints[1::2], strict=True):
        a, b = _point(near.point), _point(far.point)
        bar = next(
            link for link in links if _same(_point(link.start), a) and _same(_point(link.end), b)
        )
        name = f"{label}, {bar.name} bar"
        corner = fb.node(a, "O")
        fb.rigid(near_body, corner)
        start = add_joint(fb, plan, corner, near, 0.0, name)
        end = fb.node(b, "L")
        if bar.section is RIGID_PART:
            fb.rigid(start, end)
        else:
            fb.link(start, end, bar.section)
        _, e1, e2 = frame_from_axis(_point(far.axis))
        springs = None if far.springs is None else np.append(far.springs[[1, 2, 0]], np.inf)
        blocked = Joint("U", e1, far.point, springs, name=far.name, axis2=e2)
        tip = add_joint(fb, plan, end, blocked, 0.0, name)
        fb.rigid(tip, platform_node)


def build_model(
    design: Design,
    pose: ArrayLike,
    actuator_stiffness: ArrayLike | None = None,
    settings: FESettings | None = None,
    legs: tuple[int, ...] | None = None,
) -> tuple[FrameBuilder, str]:
    """The FE model of the manipulator (or of some legs) at ``pose``, without loads.

    Parameters
    ----------
    design : Design
    pose : array_like, shape (n_task,) or (6,)
        The design's task coordinates or a full pose (x, y, z [m], rx, ry, rz [rad])
        (:func:`ppm_stiffness.poses.full_pose`); the model is built with its origin at
        P and the axes of F_b.
    actuator_stiffness : array_like, shape (n_legs,) or scalar, optional
        Per-leg actuator stiffness [N/m, or N·m/rad for a rotary actuator]; the
        locked values when None.
    settings : FESettings, optional
    legs : tuple of int, optional
        Indices (from 0) of the legs to include; all when None.

    Returns
    -------
    (FrameBuilder, str)
        The builder (its ``model`` is the PyNite model) and the name of node P.

    Raises
    ------
    InputDataError, UnreachablePoseError, DesignError
    """
    st = settings or FESettings()
    p = validate_pose(design, pose)
    k_act = actuator_stiffness_vector(design, actuator_stiffness)
    chosen = range(len(design.legs)) if legs is None else legs
    for i in chosen:
        if not 0 <= i < len(design.legs):
            raise DesignError(f"FE model: no leg {i} (the design has {len(design.legs)})")
    leg_poses = solve_legs(design, p)
    chains = {i: design.legs[i].chain(leg_poses[i]) for i in chosen}
    members = {i: design.legs[i].drawn_members(leg_poses[i]) for i in chosen}
    for i, chain in chains.items():
        if not chain:
            raise DesignError(f"FE model, {leg_label(i)}: empty chain")
    hinges = {i: _leg_hinges(design, i, chain, st.hinge_segments) for i, chain in chains.items()}
    # the platform: distinct platform points (P first), their stiff members
    ends: list[FloatArray] = [np.zeros(3)]
    end_of: dict[int, int] = {}
    for i, chain in chains.items():
        q = _end_point(chain, hinges[i])
        found = next((j for j, r in enumerate(ends) if _same(q, r)), None)
        if found is None:
            ends.append(q)
            found = len(ends) - 1
        end_of[i] = found
    parents = _platform_parents(ends[1:])
    plan = Placement(st.connector_length)
    _plan_structure(list(chains.values()), plan, list(hinges.values()), st.hinge_segments)
    for links, _ in members.values():
        for link in links:
            plan.add_segment(_point(link.start), _point(link.end))
            plan.add_point(0.5 * (_point(link.start) + _point(link.end)))
    plan.add_point(np.zeros(3))
    bends = {j: _bend(plan, ends[j + 1], ends[parent + 1]) for j, parent in enumerate(parents)}
    for j, parent in enumerate(parents):
        a, b, bend = ends[j + 1], ends[parent + 1], bends[j]
        for u, v in ((a, b),) if bend is None else ((a, bend), (bend, b)):
            plan.add_segment(u, v)
            plan.add_point(0.5 * (u + v))
    fb = FrameBuilder(st)
    nodes = [fb.node(np.zeros(3), "P")] + [fb.node(q, "B") for q in ends[1:]]
    for j, parent in enumerate(parents):
        bend = bends[j]
        if bend is None:
            fb.rigid(nodes[j + 1], nodes[parent + 1])
        else:  # around another leg's joint on the straight line
            corner = fb.node(bend, "B")
            fb.rigid(nodes[j + 1], corner)
            fb.rigid(corner, nodes[parent + 1])
    for i, chain in chains.items():
        _add_leg(
            fb,
            plan,
            chain,
            float(k_act[i]),
            nodes[end_of[i]],
            leg_label(i),
            members[i],
            hinges[i],
        )
    return fb, nodes[0]


def _balanced_asymmetry(c: FloatArray) -> float:
    cb = length_balanced_compliance(c)
    return float(np.max(np.abs(cb - cb.T)) / np.max(np.abs(cb)))


def fe_stiffness_at_pose(
    design: Design,
    pose: ArrayLike,
    actuator_stiffness: ArrayLike | None = None,
    settings: FESettings | None = None,
) -> FEResult:
    """Cartesian stiffness at P of the FE frame model (unit loads, ``K = inv(C)``).

    Parameters
    ----------
    design : Design
    pose : array_like, shape (n_task,) or (6,)
        The design's task coordinates or a full pose [m, rad] (:func:`build_model`).
    actuator_stiffness : array_like, shape (n_legs,) or scalar, optional [N/m]
    settings : FESettings, optional

    Returns
    -------
    FEResult
        ``stiffness`` (6, 6) at P, axes of F_b, [[K_rr, K_rt], [K_rt^T, K_tt]].

    Raises
    ------
    InputDataError, UnreachablePoseError, DesignError, SingularConfigurationError
    """
    fb, p_node = build_model(design, pose, actuator_stiffness, settings)
    c = compliance_at_node(fb, p_node)
    if not np.all(np.isfinite(c)):
        raise SingularConfigurationError("FE model: the compliance at P is not finite")
    k = np.linalg.inv(c)
    m = fb.model
    return FEResult(
        stiffness=0.5 * (k + k.T),
        compliance=c,
        asymmetry=_balanced_asymmetry(c),
        n_nodes=len(m.nodes),
        n_members=len(m.members),
        n_springs=len(m.springs),
    )


def fe_leg_stiffness(
    design: Design,
    leg: int,
    pose: ArrayLike,
    actuator_stiffness: ArrayLike | None = None,
    settings: FESettings | None = None,
) -> FloatArray:
    """Stiffness at P of one leg alone (with the rigid platform member), by unit
    displacements: P is held and moved along each twist axis in turn; the reaction
    wrenches are the columns. Singular by nature (its passive joints).

    Parameters
    ----------
    leg : int
        Index of the leg, from 0.

    Returns
    -------
    ndarray, shape (6, 6)
        Symmetrised stiffness at P, axes of F_b (SI, library order).
    """
    fb, p_node = build_model(design, pose, actuator_stiffness, settings, legs=(leg,))
    model = fb.model
    model.def_support(p_node, True, True, True, True, True, True)
    cols = []
    for j in range(6):
        for i, dof in enumerate(DISPLACEMENTS):
            model.def_node_disp(p_node, dof, 1.0 if i == j else 0.0)
        analyze_linear(model, fb.settings.check_stability)
        combo = next(iter(model.load_combos))
        cols.append(node_vector(model.nodes[p_node], REACTIONS, combo))
    fb.check_topology()
    t, w = unit_scales(fb.unit)
    k = w[:, None] * np.stack(cols, axis=1) / t[None, :]
    return np.asarray(0.5 * (k + k.T))
