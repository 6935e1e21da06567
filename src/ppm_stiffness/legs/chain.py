"""A leg as a chain of joints and links, and the virtual springs it produces.

A leg runs from the base to the platform through joints and links (the joint chain):

- a **joint** is revolute (``"R"``), prismatic (``"P"``), cylindrical (``"C"``, a
  coaxial P + R), universal (``"U"``: rotations about ``e1`` and a second axis
  ``e2``, ``e1 . e2 = 0``) or spherical (``"S"``: three rotations) with an axis ``e1``
  and a point (where its hardware springs act); it is actuated or passive, and may
  carry hardware springs in its constrained directions
  (:mod:`ppm_stiffness.legs.parts`);
- a **link** is a straight beam (material + section) clamped at its start and loaded
  at its end: the cantilever of eq. (3c) with its tip frame at the end point.

Axes are 3-D: the planar mechanism is modelled as a spatial one.

Frames. A joint frame is ``e1`` = the axis, ``e2 = unit(z x e1)`` (``unit(e1 x x)``
when the axis is along z), ``e3 = e1 x e2``; a U joint's frame is its two axes and
``e3 = e1 x e2``; an S joint has no axis of its own: its ``axis`` orients the frame of
its springs (the adjacent link, typically). A link's tip frame has its local x along
the link (start -> end) and local y, z built the same way.

The freedoms and constrained directions of each kind (its hardware springs, in that
order) are in its record (:mod:`ppm_stiffness.legs.joint_kinds`, with their table); the
tables below are views of the records, kept for their importers.

The builder (:func:`leg_springs`) turns a chain at one or many poses (every point and
axis has the batch shape plus a trailing 3) into the arrays of
:class:`~ppm_stiffness.core.solver.LegSprings`, in chain order:

- an actuated joint: first its actuator spring, along its freedom (translation along
  e1 for P, rotation about e1 for R), then its hardware springs;
- a passive joint: its hardware springs; its freedoms become passive-joint screws
  (P: translation e1; C: rotation about e1, then translation e1; R: rotation e1);
- an elastic joint (``Joint.elastic``: a stiffness along each freedom, a flexure): its
  hardware springs; its freedoms become elastic freedoms (``LegSprings.elastic``), with
  their stiffnesses, in chain order; the bordered solve keeps them
  (:mod:`ppm_stiffness.core.solver`). An elastic S's freedoms are the rotations about
  the three orthonormal axes of its frame with one stiffness (the same about every axis
  through its centre); an elastic U's act about its current e1 and e2. An actuated
  joint's elastic stiffness acts in parallel with its actuator: the actuator spring's
  stiffness is their sum;
- a link: six columns (rotation about local x, y, z; translation along x, y, z) at
  its end point, with the 6x6 cantilever compliance.

The paper's P-P-R leg is ``P(actuated, guide) - link - C(bearing) - link - R``, and
the builder gives exactly its 22 springs in the order of the paper's appendix.

Masses (optional; :mod:`ppm_stiffness.dynamics`): a link may carry a
:class:`LinkMass` (a rigid body moving with the link's start, i.e. upstream of its own
tip springs), a joint a :class:`JointMass` (a body at the joint's point moving with the
joint's output, and a rotor inertia reflected to its first freedom: the actuated
joint's moving drive parts). The stiffness ignores them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.beam import BeamSection, cantilever_compliance
from ppm_stiffness.core.conventions import (
    Z_AXIS,
    FloatArray,
    cross,
    rotation_screw,
    translation_screw,
)
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.core.solver import LegSprings
from ppm_stiffness.legs.joint_kinds import JOINT_KINDS, Direction, JointKind, joint_kind

#: Freedoms of each joint kind, in order (:mod:`ppm_stiffness.legs.joint_kinds`).
FREEDOM_DIRECTIONS: dict[str, tuple[Direction, ...]] = {
    letter: record.freedoms for letter, record in JOINT_KINDS.items()
}
#: Constrained directions of each joint kind, in the order of its hardware springs.
CONSTRAINED_DIRECTIONS: dict[str, tuple[Direction, ...]] = {
    letter: record.constrained for letter, record in JOINT_KINDS.items()
}
#: Number of constrained directions (hardware springs) of each joint kind.
CONSTRAINED = {letter: record.constrained_count for letter, record in JOINT_KINDS.items()}
#: Number of freedoms of each joint kind.
FREEDOMS = {letter: record.freedom_count for letter, record in JOINT_KINDS.items()}


@dataclass(frozen=True)
class LinkMass:
    """A link's mass properties (a rigid body fixed to the link).

    Attributes
    ----------
    mass : float [kg]
    centre : float or None [m]
        Distance of the centre of mass along the link from its start (or its end, with
        ``from_end``); None: the middle of the link's current length.
    from_end : bool
        ``centre`` is measured from the link's end (the platform side) rather than its
        start: a body fixed to the joint at that end keeps its distance to it when the
        link's length changes.
    transverse : float or None [kg·m^2]
        Inertia about any axis through the centre of mass normal to the link; None: a
        uniform slender rod of the link's current length L, ``mass L^2 / 12``.
    axial : float [kg·m^2]
        Inertia about the link's axis (0: spin neglected).
    """

    mass: float
    centre: float | None = None
    from_end: bool = False
    transverse: float | None = None
    axial: float = 0.0


@dataclass(frozen=True)
class JointMass:
    """Moving parts carried by a joint (an actuator's drive).

    Attributes
    ----------
    mass : float [kg]
        A body at the joint's point moving with the joint's output (a carriage).
    rotor : float [kg·m^2 or kg]
        Inertia reflected to the joint's first freedom (its actuated coordinate):
        ``rotor_inertia * gear_ratio^2``, kinetic energy ``rotor * rate^2 / 2``.
    """

    mass: float = 0.0
    rotor: float = 0.0


@dataclass(frozen=True)
class Joint:
    """One joint of a chain (arrays: batch shape + (3,), relative to P, axes of F_b).

    Attributes
    ----------
    kind : {"R", "P", "C", "U", "S"}
    axis : ndarray (..., 3), unit
        The joint axis e1 (an S joint: the direction that orients its springs' frame).
    point : ndarray (..., 3) [m]
    springs : ndarray (CONSTRAINED[kind],) or (..., CONSTRAINED[kind]), or None
        Stiffness of each constrained direction, in the joint frame's order (see
        :mod:`ppm_stiffness.legs.parts`), the same at every pose or one row per pose
        (a parallelogram's couple); ``inf`` is rigid; None: no springs at all (the
        joint is rigid in its constrained directions).
    actuated : bool
    name : str
        The part's name in the design (``guide``, ``bearing``, ...), for pictures
        and the FE model.
    axis2 : ndarray (..., 3) or None
        A U joint's second axis e2 (unit, normal to e1). For other kinds, optional: the
        direction of e2 of the joint frame (its component normal to e1), where the
        default ``unit(z x e1)`` does not follow the hardware (a guide on a vertical
        rail, whose lateral direction the leg's geometry defines).
    mass : JointMass or None
        Moving parts the joint carries (the actuated joint's drive), for the mass model.
    equivalent : bool
        A joint of an element's equivalent chain (a parallelogram's two P joints and
        U): exact for the stiffness and the masses, not a part; pictures draw the
        element's parts instead (:meth:`~ppm_stiffness.legs.base.LegModel.
        drawn_members`) and the FE frame builds those parts, with their masses, in
        its place.
    elastic : ndarray (FREEDOMS[kind],) or None
        Stiffness along each freedom [N·m/rad or N/m] (a flexure, a torsion spring),
        positive and finite: the freedoms are elastic, not passive (module doc); an
        actuated joint's adds to its actuator's (in parallel). None: none.
    """

    kind: JointKind
    axis: FloatArray
    point: FloatArray
    springs: FloatArray | None = None
    actuated: bool = False
    name: str = ""
    axis2: FloatArray | None = None
    mass: JointMass | None = None
    equivalent: bool = False
    elastic: FloatArray | None = None

    def frame(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        """The joint frame ``(e1, e2, e3)`` (module doc), each (..., 3)."""
        second_axis = joint_kind(self.kind).second_axis
        if self.axis2 is None:
            if second_axis:
                raise DesignError(f"universal joint {self.name or ''}: its second axis is missing")
            return frame_from_axis(self.axis)
        e1, e2 = np.broadcast_arrays(unit(self.axis), np.asarray(self.axis2, dtype=float))
        if second_axis:  # the two axes as given
            e2 = unit(e2)
        else:  # e2 along the part of axis2 normal to e1
            e2 = unit(e2 - np.einsum("...i,...i->...", e2, e1)[..., None] * e1)
        return e1, e2, cross(e1, e2)


@dataclass(frozen=True)
class Link:
    """A straight beam from ``start`` to ``end`` (relative to P, axes of F_b) [m], and
    its mass properties (None: massless); ``end_mass`` [kg] is a point mass at its end
    moving with its end (what the element after it hands over: a parallelogram's
    bars' near halves)."""

    start: FloatArray
    end: FloatArray
    section: BeamSection
    name: str = ""
    mass: LinkMass | None = None
    end_mass: float = 0.0


Element = Joint | Link


def unit(v: ArrayLike) -> FloatArray:
    """``v / |v|`` along the last axis (zero vectors stay zero)."""
    a = np.asarray(v, dtype=float)
    n = np.sqrt(np.einsum("...i,...i->...", a, a))[..., None]
    return np.asarray(a / np.where(n > 0, n, 1.0))


def frame_from_axis(axis: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The right-handed frame ``(e1, e2, e3)`` of a joint or link axis (module doc)."""
    e1 = unit(axis)
    z = np.broadcast_to(Z_AXIS, e1.shape)
    e2 = cross(z, e1)
    along_z = np.linalg.norm(e2, axis=-1, keepdims=True) < 1e-12
    if np.any(along_z):
        e2 = np.where(along_z, cross(e1, np.broadcast_to([1.0, 0.0, 0.0], e1.shape)), e2)
    e2 = unit(e2)
    return e1, e2, cross(e1, e2)


def _screws(joint: Joint, directions: tuple[Direction, ...]) -> FloatArray:
    """Unit twists (..., 6, n) of frame directions of a joint at its point."""
    frame = joint.frame()
    shape = np.broadcast_shapes(frame[0].shape, np.shape(joint.point))
    c = np.broadcast_to(np.asarray(joint.point, dtype=float), shape)
    axes = [np.broadcast_to(e, shape) for e in frame]
    cols = [
        rotation_screw(axes[k], c) if kind == "r" else translation_screw(axes[k])
        for kind, k in directions
    ]
    return np.stack(cols, axis=-1)


def constrained_screws(joint: Joint) -> FloatArray:
    """Unit twists of a joint's constrained directions, shape (..., 6, n)."""
    return _screws(joint, joint_kind(joint.kind).constrained)


def freedom_screws(joint: Joint) -> FloatArray:
    """Unit twists of a joint's freedoms, shape (..., 6, f)."""
    return _screws(joint, joint_kind(joint.kind).freedoms)


def link_screws(link: Link) -> tuple[FloatArray, FloatArray]:
    """Tip-frame unit twists (..., 6, 6) and the free length (...) [m] of a link."""
    axis = np.asarray(link.end, dtype=float) - np.asarray(link.start, dtype=float)
    length = np.linalg.norm(axis, axis=-1)
    ex, ey, ez = frame_from_axis(axis)
    end = link.end
    cols = [
        rotation_screw(ex, end),
        rotation_screw(ey, end),
        rotation_screw(ez, end),
        translation_screw(ex),
        translation_screw(ey),
        translation_screw(ez),
    ]
    return np.stack(cols, axis=-1), length


def check_chain(chain: Sequence[Element]) -> None:
    """Refuse a chain with more than one actuated joint, or with an actuated joint of
    more than one freedom (C, U, S). A chain without one is a passive constraining leg
    (a Tricept's central leg): it has no actuator spring."""
    actuated = [e for e in chain if isinstance(e, Joint) and e.actuated]
    if len(actuated) > 1:
        raise DesignError(f"a leg has at most one actuated joint, got {len(actuated)}")
    if not actuated:
        return
    count = joint_kind(actuated[0].kind).freedom_count
    if count != 1:
        raise DesignError(
            f"a joint of kind {actuated[0].kind} ({count} freedoms) cannot be the actuated joint"
        )


def actuator_screw(chain: Sequence[Element]) -> FloatArray:
    """Unit twist of the actuated joint's freedom, shape (..., 6).

    Raises
    ------
    DesignError
        For a passive constraining leg (no actuated joint): it transmits no actuator
        force.
    """
    check_chain(chain)
    joint = next((e for e in chain if isinstance(e, Joint) and e.actuated), None)
    if joint is None:
        raise DesignError(
            "a passive constraining leg (no actuated joint) has no actuator screw: its "
            "load is carried by its constraint wrenches, not by an actuator force"
        )
    return np.asarray(freedom_screws(joint)[..., 0])


def elastic_stiffnesses(joint: Joint) -> FloatArray | None:
    """A joint's elastic stiffnesses (f,) [N·m/rad or N/m], checked, or None.

    Raises
    ------
    DesignError
        Not one positive finite stiffness per freedom.
    """
    if joint.elastic is None:
        return None
    k = np.asarray(joint.elastic, dtype=float)
    f = freedom_count(joint)
    if k.shape != (f,) or np.any(~(k > 0)) or np.any(~np.isfinite(k)):
        raise DesignError(
            f"joint {joint.name or joint.kind}: {f} positive finite elastic stiffnesses "
            f"expected, got {k}"
        )
    return k


def parallel_stiffness(chain: Sequence[Element]) -> float:
    """The elastic stiffness in parallel with the actuator (its joint's elastic
    stiffness, 0 without one) [N·m/rad or N/m]."""
    for element in chain:
        if isinstance(element, Joint) and element.actuated:
            k = elastic_stiffnesses(element)
            return 0.0 if k is None else float(k[0])
    return 0.0


def leg_springs(chain: Sequence[Element], actuator_stiffness: ArrayLike) -> LegSprings:
    """Virtual springs and passive joints of a leg from its chain (module doc).

    Parameters
    ----------
    chain : sequence of Joint and Link
        From the base to the platform; every array with the same batch shape.
    actuator_stiffness : array_like, broadcastable to the batch shape
        [N/m] for a prismatic actuator, [N·m/rad] for a revolute one.

    Returns
    -------
    LegSprings
        screws (..., 6, m), compliance (..., m, m), passive (..., 6, p); its
        ``actuator_index`` None for a passive constraining leg (no actuator column, and
        ``actuator_stiffness`` unused).
    """
    check_chain(chain)
    batch = np.broadcast_shapes(
        *[np.shape(e.point)[:-1] if isinstance(e, Joint) else np.shape(e.end)[:-1] for e in chain]
    )
    columns: list[FloatArray] = []
    blocks: list[FloatArray] = []  # (..., n, n) compliance blocks, in column order
    passive: list[FloatArray] = []
    actuator_index: int | None = None
    elastic: list[FloatArray] = []
    elastic_k: list[FloatArray] = []
    k_act = np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), batch)
    k_act = k_act + parallel_stiffness(chain)
    for element in chain:
        if isinstance(element, Link):
            screws, length = link_screws(element)
            columns.append(np.broadcast_to(screws, batch + (6, 6)))
            blocks.append(
                np.broadcast_to(cantilever_compliance(element.section, length), batch + (6, 6))
            )
            continue
        free = np.broadcast_to(freedom_screws(element), batch + (6, freedom_count(element)))
        if element.actuated:
            actuator_index = sum(c.shape[-1] for c in columns)
            columns.append(free[..., :1])
            blocks.append((1.0 / k_act)[..., None, None])
        elif (k_joint := elastic_stiffnesses(element)) is not None:
            elastic.append(free)
            elastic_k.append(np.broadcast_to(k_joint, batch + free.shape[-1:]))
        else:
            passive.append(free)
        if element.springs is not None:
            n = joint_kind(element.kind).constrained_count
            k = spring_stiffnesses(element, n)
            columns.append(np.broadcast_to(constrained_screws(element), batch + (6, n)))
            blocks.append(np.broadcast_to(np.eye(n) / k[..., None, :], batch + (n, n)))
    screws = np.concatenate(columns, axis=-1)
    m = screws.shape[-1]
    compliance = np.zeros(batch + (m, m))
    i = 0
    for block in blocks:
        n = block.shape[-1]
        compliance[..., i : i + n, i : i + n] = block
        i += n
    return LegSprings(
        screws=screws,
        compliance=compliance,
        passive=np.concatenate(passive, axis=-1) if passive else np.zeros(batch + (6, 0)),
        actuator_index=actuator_index,
        elastic=np.concatenate(elastic, axis=-1) if elastic else None,
        elastic_stiffness=np.concatenate(elastic_k, axis=-1) if elastic else None,
    )


def spring_stiffnesses(joint: Joint, count: int) -> FloatArray:
    """A joint's hardware springs (count,) or (..., count), checked positive."""
    k = np.asarray(joint.springs, dtype=float)
    if k.ndim == 0 or k.shape[-1] != count or np.any(~(k > 0)):
        raise DesignError(
            f"joint {joint.name or joint.kind}: {count} positive spring "
            f"stiffnesses expected, got {k}"
        )
    return k


def freedom_count(joint: Joint) -> int:
    """Number of freedoms of a joint (its kind's record)."""
    return joint_kind(joint.kind).freedom_count


def chain_batch(chain: Sequence[Element]) -> tuple[int, ...]:
    """The batch shape of a chain's points (every array (..., 3) or (3,))."""
    return np.broadcast_shapes(
        *[np.shape(e.point)[:-1] if isinstance(e, Joint) else np.shape(e.end)[:-1] for e in chain]
    )


def _same_array(arrays: Sequence[FloatArray | None]) -> bool:
    """All None, or all equal arrays."""
    first = arrays[0]
    if first is None:
        return all(a is None for a in arrays)
    return all(a is not None and np.array_equal(a, first) for a in arrays[1:])


def _same_kind(elements: Sequence[Element]) -> bool:
    """Elements that differ only in their points and axes (and names)."""
    e0 = elements[0]
    if isinstance(e0, Link):
        return all(
            isinstance(e, Link)
            and e.section == e0.section
            and e.mass == e0.mass
            and e.end_mass == e0.end_mass
            for e in elements[1:]
        )
    key = (e0.kind, e0.actuated, e0.mass, e0.equivalent, e0.axis2 is None)
    return (
        all(
            isinstance(e, Joint)
            and (e.kind, e.actuated, e.mass, e.equivalent, e.axis2 is None) == key
            for e in elements[1:]
        )
        and _same_array([e.springs for e in elements])  # type: ignore[union-attr]
        and _same_array([e.elastic for e in elements])  # type: ignore[union-attr]
    )


def same_structure(a: Sequence[Element], b: Sequence[Element]) -> bool:
    """Two chains that differ only in their points and axes (and names): the same
    kinds, sections, springs and masses element by element (the legs of a symmetric
    design)."""
    return len(a) == len(b) and all(_same_kind(pair) for pair in zip(a, b, strict=True))


def structure_groups(chains: Sequence[Sequence[Element]]) -> list[list[int]]:
    """The chains' indices in groups of one structure (:func:`same_structure`), each in
    order, the groups by their first."""
    groups: list[list[int]] = []
    for i, chain in enumerate(chains):
        for group in groups:
            if same_structure(chains[group[0]], chain):
                group.append(i)
                break
        else:
            groups.append([i])
    return groups


def stack_chains(
    chains: Sequence[Sequence[Element]], batch: tuple[int, ...] = ()
) -> list[Element] | None:
    """Chains of one structure (:func:`same_structure`) as one chain whose points and
    axes have a leading axis over the chains (L, *batch, 3), so that the batched models
    evaluate every leg in one call; None if their structures differ.

    Parameters
    ----------
    chains : sequence of chains
        Each base to platform, arrays (..., 3) or (3,).
    batch : tuple of int
        A shape every chain's arrays broadcast to (with theirs, :func:`chain_batch`).
    """
    if not chains or not all(same_structure(chains[0], c) for c in chains[1:]):
        return None
    shape = np.broadcast_shapes(batch, *[chain_batch(c) for c in chains]) + (3,)

    def stacked(arrays: Sequence[ArrayLike]) -> FloatArray:
        return np.stack([np.broadcast_to(np.asarray(a, dtype=float), shape) for a in arrays])

    out: list[Element] = []
    for elements in zip(*chains, strict=True):
        e0 = elements[0]
        if isinstance(e0, Link):
            links: Sequence[Link] = elements
            start = stacked([e.start for e in links])
            out.append(replace(e0, start=start, end=stacked([e.end for e in links])))
            continue
        joints: Sequence[Joint] = elements
        axis2 = None if e0.axis2 is None else stacked([e.axis2 for e in joints])  # type: ignore[misc]
        axis = stacked([e.axis for e in joints])
        out.append(replace(e0, axis=axis, point=stacked([e.point for e in joints]), axis2=axis2))
    return out
