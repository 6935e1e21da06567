"""The manipulator at a pose as a 3D frame model in PyNite, and its stiffness at P.

Why PyNite (``pynitefea``): its frame members are Euler-Bernoulli, the beam theory of
the paper's eq. (3c), so the two models share their beam theory and differ only in
how they are built and solved; member-end releases and two-node axial springs give
exact lumped springs. pyfe3d (Timoshenko beams, 6-component springs) would add shear
deformation the virtual-joint model does not have.

Model (coordinates: F_b axes, origin at P; PyNite's global X, Y, Z are our x, y, z)
----------------------------------------------------------------------------------
Every leg is built from its joint chain (:meth:`LegModel.chain`, the same chain the
virtual-joint model reads), walked from the base to the platform:

* a **link** is an Euler-Bernoulli member from a node at its start to a node at its
  end with the link's section (built as two halves, see ``FrameBuilder.segment``);
* a **joint** joins the node before it (a grounded node for the first joint) to a
  new node at the same point (the node after it). In the joint frame (e1, e2, e3) of
  :mod:`ppm_stiffness.legs.chain`, each of the six relative motions (rotations about
  e1, e2, e3, translations along e1, e2, e3) is free (a passive freedom: no
  element), a spring (a hardware spring, or the actuator along the actuated joint's
  freedom) or rigid (no hardware spring given: a spring of the ``rigid`` scale);
  - rotations: two *moment-only* members (all end forces released at a common
    auxiliary node X, translations of X supported) from the two nodes to X along
    the frame axis normal to the plane; their local axes are the joint frame, so
    their ``GJ/L, EI_y/L, EI_z/L`` (each twice the spring, in series) are the three
    rotational springs; a free rotation is also released at X on the first member;
  - translations: per constrained or actuated direction, two axial ``Spring3D`` of
    twice the stiffness in series through an auxiliary node Y on the line through
    the joint point along that direction; Y's other freedoms are held by supports
    and a grounded spring that acts on nothing else;
* a link that does not start at the previous joint's point, or a joint away from the
  previous link's end, is joined by a stiff member (a rigid body in the chain);
* the **platform**: a stiff member from the last joint's node to P.

Every spring realisation is exact in linear analysis. The approximations are the
finite stiffness of the platform members and of the rigid joint directions, both
set by ``FESettings.rigid_stiffness`` (translations: that value [N/m]; rotations:
that value times ``LENGTH_SCALE**2`` [N·m/rad]); the difference to the virtual-joint
model scales as its inverse. The stiffness at P comes from six unit-load cases at P
(moments, then forces, along the base axes): the displacements are the compliance
columns, ``K = inv(C)``.

Only the chain (points, axes, springs, sections) and the design's numbers are
shared with the virtual-joint model: :mod:`ppm_stiffness.core.solver`,
:func:`ppm_stiffness.core.beam.cantilever_compliance` and
:func:`ppm_stiffness.legs.chain.leg_springs` are not used.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import (
    LENGTH_SCALE,
    Z_AXIS,
    FloatArray,
    length_balanced_compliance,
)
from ppm_stiffness.core.errors import DesignError, SingularConfigurationError
from ppm_stiffness.design import Design
from ppm_stiffness.design.schema import leg_label
from ppm_stiffness.legs.chain import Element, Joint, Link
from ppm_stiffness.model import actuator_stiffness_vector, solve_legs
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

#: Relative motions of a joint in its frame: 0-2 rotations about e1, e2, e3, 3-5
#: translations along e1, e2, e3. Constrained ones, in the order of the hardware
#: springs (:mod:`ppm_stiffness.legs.chain`), and freedoms (the actuated one first).
CONSTRAINED_MOTIONS: dict[str, tuple[int, ...]] = {
    "P": (0, 1, 2, 4, 5),
    "C": (1, 2, 4, 5),
    "R": (1, 2, 3, 4, 5),
}
FREE_MOTIONS: dict[str, tuple[int, ...]] = {"P": (3,), "C": (0, 3), "R": (0,)}
#: Two points closer than this are the same point [m].
_SAME_POINT = 1e-9


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


def joint_stiffness(joint: Joint, actuator_stiffness: float) -> FloatArray:
    """Stiffness of a joint's six relative motions in its frame, shape (6,).

    Order: rotations about e1, e2, e3 [N·m/rad], translations along e1, e2, e3 [N/m].
    0 is a free motion, ``inf`` a rigid one (a constrained direction without a
    hardware spring, or an ``inf`` spring).

    Raises
    ------
    DesignError
        Springs of the wrong number or not positive.
    """
    k = np.zeros(6)
    constrained = CONSTRAINED_MOTIONS[joint.kind]
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
    if joint.actuated:
        k[FREE_MOTIONS[joint.kind][0]] = actuator_stiffness
    return k


@dataclass
class _Planner:
    """Where auxiliary nodes may go: off the in-plane members, one z line per point."""

    segments: list[tuple[FloatArray, FloatArray]] = field(default_factory=list)
    points: list[FloatArray] = field(default_factory=list)
    joints_at: dict[tuple[int, int], int] = field(default_factory=dict)
    springs_at: dict[tuple[int, int], int] = field(default_factory=dict)

    @staticmethod
    def key(point: FloatArray) -> tuple[int, int]:
        return (round(float(point[0]) / _SAME_POINT), round(float(point[1]) / _SAME_POINT))

    def clear(self, q: FloatArray, margin: float) -> bool:
        """``q`` is farther than ``margin`` from every member and auxiliary node."""
        for a, b in self.segments:
            ab = b - a
            t = float(np.clip((q - a) @ ab / (ab @ ab), 0.0, 1.0))
            if np.linalg.norm(q - (a + t * ab)) <= margin:
                return False
        return all(np.linalg.norm(q - p) > margin for p in self.points)


def _point(v: FloatArray) -> FloatArray:
    p = np.asarray(v, dtype=float)
    if p.shape != (3,):
        raise DesignError(f"FE model: one pose at a time, got a point of shape {p.shape}")
    return p


def _along_z(axis: FloatArray) -> bool:
    return bool(abs(abs(float(axis @ Z_AXIS)) - 1.0) < 1e-9)


def _in_plane(axis: FloatArray) -> bool:
    return bool(abs(float(axis @ Z_AXIS)) < 1e-9)


def _rigid(fb: FrameBuilder) -> tuple[float, float]:
    """Stiffness of a rigid joint direction: rotation [N·m/rad], translation [N/m]."""
    k = fb.settings.rigid_stiffness
    return k * LENGTH_SCALE**2, k


def _add_joint_rotations(
    fb: FrameBuilder,
    plan: _Planner,
    before: str,
    after: str,
    point: FloatArray,
    frame: tuple[FloatArray, FloatArray, FloatArray],
    k_rot: FloatArray,
    label: str,
) -> None:
    """Rotational springs of a joint: two moment-only members through X (module doc)."""
    if not np.any(k_rot != 0):
        return
    normal = [i for i in range(3) if _along_z(frame[i])]
    if not normal:
        raise DesignError(f"FE model, {label}: the joint frame has no axis normal to the plane")
    i_x = normal[0]
    i_y, i_z = (i_x + 1) % 3, (i_x + 2) % 3
    key = plan.key(point)
    slot = plan.joints_at.get(key, 0)
    if slot >= 2:
        raise DesignError(f"FE model, {label}: more than two joints at one point")
    plan.joints_at[key] = slot + 1
    sign = 1.0 if slot == 0 else -1.0
    x_axis = sign * Z_AXIS
    y_axis = frame[i_y]
    rot_rigid = _rigid(fb)[0]
    k = np.array([k_rot[i_x], k_rot[i_y], k_rot[i_z]])
    free = (bool(k[0] == 0), bool(k[1] == 0), bool(k[2] == 0))
    k = np.where(np.isinf(k), rot_rigid, k)
    hold = float(np.max(k))  # the second member holds X about the free axes
    x_node = fb.node(point + sign * fb.s * Z_AXIS, "X")
    fb.support(x_node, "DX DY DZ")
    # local z of a member along x_axis with local y = frame[i_y] is x_axis x y_axis
    z_sign = float(np.cross(x_axis, y_axis) @ frame[i_z])
    if abs(abs(z_sign) - 1.0) > 1e-9:
        raise DesignError(f"FE model, {label}: joint frame is not orthonormal")
    stiff = 2.0 * np.where(np.array(free), 1.0, k)
    fb.moment_member(before, x_node, (x_axis, y_axis), stiff, free)
    fb.moment_member(
        after,
        x_node,
        (x_axis, y_axis),
        2.0 * np.where(np.array(free), hold, k),
        (False, False, False),
    )


def _add_joint_translation(
    fb: FrameBuilder,
    plan: _Planner,
    before: str,
    after: str,
    point: FloatArray,
    axis: FloatArray,
    stiffness: float,
    label: str,
) -> None:
    """A translational spring along ``axis``: two Spring3D in series through Y."""
    s = fb.s
    if _along_z(axis):
        key = plan.key(point)
        n = plan.springs_at.get(key, 0)
        plan.springs_at[key] = n + 1
        # beyond the moment-only members (|z| <= s), alternately up and down
        pos = point + (1.0 if n % 2 == 0 else -1.0) * (2 + n // 2) * s * Z_AXIS
        y_node = fb.node(pos, "Y")
        fb.support(y_node, "DX DY RX RY RZ")
    elif _in_plane(axis):
        pos = None
        for step in range(1, 10_000):
            for sign in (1.0, -1.0):
                q = point + sign * step * s * axis
                if plan.clear(q, 0.25 * s):
                    pos = q
                    break
            if pos is not None:
                break
        if pos is None:  # pragma: no cover - needs members everywhere on the line
            raise DesignError(f"FE model, {label}: no room for a spring node")
        plan.points.append(pos)
        y_node = fb.node(pos, "Y")
        fb.support(y_node, "DZ RX RY RZ")
        across = np.cross(Z_AXIS, axis)
        holder = fb.ground(pos + s * (across + Z_AXIS) / np.sqrt(2.0))
        fb.axial_spring(y_node, holder, stiffness)
    else:
        raise DesignError(f"FE model, {label}: joint axes must lie in the plane or along z")
    fb.axial_spring(before, y_node, 2.0 * stiffness)
    fb.axial_spring(y_node, after, 2.0 * stiffness)


def _add_joint(
    fb: FrameBuilder,
    plan: _Planner,
    before: str,
    joint: Joint,
    k_act: float,
    label: str,
) -> str:
    """Add one joint after node ``before``; returns the node after it."""
    point = _point(joint.point)
    e1, e2, e3 = (_point(e) for e in joint.frame())
    frame = (np.asarray(e1), np.asarray(e2), np.asarray(e3))
    k = joint_stiffness(joint, k_act)
    after = fb.node(point, "J")
    _add_joint_rotations(fb, plan, before, after, point, frame, k[:3], label)
    k_trans = np.where(np.isinf(k[3:]), _rigid(fb)[1], k[3:])
    for i in range(3):
        if k_trans[i] > 0:
            _add_joint_translation(
                fb, plan, before, after, point, frame[i], float(k_trans[i]), label
            )
    return after


def _plan_segments(chain: Sequence[Element], plan: _Planner) -> None:
    """Record the in-plane members of a chain (links, rigid offsets, platform)."""
    pos: FloatArray | None = None
    for element in chain:
        if isinstance(element, Link):
            start, end = _point(element.start), _point(element.end)
            if pos is not None and np.linalg.norm(start - pos) > _SAME_POINT:
                plan.segments.append((pos, start))
            plan.segments.append((start, end))
            pos = end
        else:
            point = _point(element.point)
            if pos is not None and np.linalg.norm(point - pos) > _SAME_POINT:
                plan.segments.append((pos, point))
            pos = point
    if pos is not None:
        plan.segments.append((pos, np.zeros(3)))


def _add_leg(
    fb: FrameBuilder,
    plan: _Planner,
    chain: Sequence[Element],
    k_act: float,
    p_node: str,
    label: str,
) -> None:
    """Add one leg's chain from the ground to node P (module doc)."""
    if not chain or not isinstance(chain[0], Joint):
        raise DesignError(f"FE model, {label}: the chain must start with a joint at the base")
    current: str | None = None
    pos = np.zeros(3)
    for n, element in enumerate(chain):
        name = f"{label}, {element.name or type(element).__name__.lower()} (element {n + 1})"
        if isinstance(element, Link):
            start, end = _point(element.start), _point(element.end)
            if np.linalg.norm(end - start) <= _SAME_POINT:
                raise DesignError(f"FE model, {name}: zero-length link")
            if current is None:  # pragma: no cover - excluded above
                raise DesignError(f"FE model, {label}: the chain must start with a joint")
            if np.linalg.norm(start - pos) > _SAME_POINT:
                offset = fb.node(start, "O")
                fb.rigid(current, offset)
                current = offset
            tip = fb.node(end, "L")
            fb.link(current, tip, element.section)
            current, pos = tip, end
        else:
            point = _point(element.point)
            if current is None:
                before = fb.ground(point)
            elif np.linalg.norm(point - pos) > _SAME_POINT:
                before = fb.node(point, "O")
                fb.rigid(current, before)
            else:
                before = current
            current = _add_joint(fb, plan, before, element, k_act, name)
            pos = point
    assert current is not None
    if np.linalg.norm(pos) <= _SAME_POINT:
        raise DesignError(f"FE model, {label}: the platform point coincides with P")
    fb.rigid(current, p_node)


def build_model(
    design: Design,
    pose: ArrayLike,
    actuator_stiffness: ArrayLike | None = None,
    settings: FESettings | None = None,
    legs: tuple[int, ...] | None = None,
) -> tuple[FrameBuilder, str]:
    """The FE model of the manipulator (or of some legs) at ``pose``.

    Parameters
    ----------
    design : Design
    pose : array_like, shape (3,)
        (x [m], y [m], phi [rad]); the model is built with its origin at P.
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
    UnreachablePoseError, DesignError
    """
    st = settings or FESettings()
    p = np.asarray(pose, dtype=float)
    if p.shape != (3,) or not np.all(np.isfinite(p)):
        raise DesignError(f"FE model: a pose is 3 finite numbers (x, y, phi), got {p}")
    k_act = actuator_stiffness_vector(design, actuator_stiffness)
    chosen = range(len(design.legs)) if legs is None else legs
    for i in chosen:
        if not 0 <= i < len(design.legs):
            raise DesignError(f"FE model: no leg {i} (the design has {len(design.legs)})")
    leg_poses = solve_legs(design, p)
    chains = {i: design.legs[i].chain(leg_poses[i]) for i in chosen}
    plan = _Planner()
    for chain in chains.values():
        _plan_segments(chain, plan)
    fb = FrameBuilder(st)
    p_node = fb.node(np.zeros(3), "P")
    for i, chain in chains.items():
        _add_leg(fb, plan, chain, float(k_act[i]), p_node, leg_label(i))
    return fb, p_node


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
    pose : array_like, shape (3,)
        (x [m], y [m], phi [rad]).
    actuator_stiffness : array_like, shape (n_legs,) or scalar, optional [N/m]
    settings : FESettings, optional

    Returns
    -------
    FEResult
        ``stiffness`` (6, 6) at P, axes of F_b, [[K_rr, K_rt], [K_rt^T, K_tt]].

    Raises
    ------
    UnreachablePoseError, DesignError, SingularConfigurationError
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
