"""Natural frequencies of the FE frame model, against the mass model's (issue 21).

PyNite's own modal analysis cannot represent a rigid platform's 6x6 inertia (its
masses come from loads in one direction and self-weight), and the FE model's
auxiliary members (joint springs, stiff offsets, the platform members) carry no mass.
So the FE stiffness is taken from PyNite (the assembled global matrix of
:func:`ppm_stiffness.validation.fe_model.build_model`, on its free degrees of freedom)
and the mass matrix is assembled here:

- every uniform design link (two frame members, :meth:`FrameBuilder.segment`) gets
  the consistent 12x12 Euler-Bernoulli beam mass of a uniform bar of its mass per
  length ``m / L`` (and the consistent torsional inertia of its ``inertia_axial``
  per length; spin neglected without it, as the mass model's default);
- a link given as a body (its ``mass_centre`` or ``inertia_transverse`` given) is a
  massless beam carrying a rigid body (its mass, and its inertia ``transverse``
  normal to the link and ``axial`` about it) at its centre: on the node where the
  link's two members meet when the centre lies inside the link (the frame puts that
  node there, :func:`ppm_stiffness.validation.fe_model.link_split`), else tied rigidly
  to the node at the nearer end by the offset (``T^T diag(m, m, m, I) T`` on that
  node's motion, :func:`rigid_body_mass`): the rule of the mass model for a centre
  beyond its link's end (:mod:`ppm_stiffness.dynamics.links`), while inside the link
  the frame's beam carries the body at a node of its own where the model's leg FE
  interpolates its elements (the Hermite shape of the element holding the centre);
- a parallelogram's bars (the Delta's) are members of the frame: each carries its
  own mass as a uniform bar (consistent beam mass, no spin), where the mass model
  lumps its halves at the crossbars' centres and has no bending of the bars: the
  Delta's f1, f2 differ by that rule, -3.6 %, and the frame's f4..f6 are the bars'
  bending near 104 Hz (docs/dynamics.md);
- the platform's rigid-body mass sits at its master node P (its spatial inertia at P,
  :mod:`ppm_stiffness.dynamics.inertia`);
- an actuator's carriage mass sits at the node after its joint (the joint's output),
  a rotor's reflected inertia on the relative motion of that node and the node before
  the joint along (about) the joint's axis (a base joint's: the node before it is the
  ground).

The eigenproblem ``K x = omega^2 M x`` of the whole frame is solved as
``M x = mu K x`` (K positive definite, M semi-definite: the massless degrees of
freedom, mu = 0, are condensed statically without forming the condensation), its six
largest mu = 1/omega^2 giving the six lowest frequencies. The frame reduced to P's
six degrees of freedom by static (Guyan) condensation gives ``K_P`` and
``M_P = T^T M T`` (T the static displacement of every node per unit displacement of
P), to compare with this library's K and M (:mod:`ppm_stiffness.dynamics.mass`).

``f_link,1``: the lowest natural frequency of the frame with P held fixed (the legs'
own vibrations: each link in its joints). Where it is at least 10 times the first
frequency f1, the reduced frame and the mass model agree within 1 %, and the full
frame's f1 differs from the model's by about ``(f1 / f_link,1)^2`` (docs/dynamics.md).

Any design, planar or spatial: the FE model builds every chain in space at the full
pose (U and S joints included). Measured (docs/dynamics.md): the shipped 3-PRS agrees
within 5.5e-5 reduced and 2.5e-5 whole (f_link,1 = 48 f1); a hexapod with uniform
struts agrees reduced, but its struts' own bending (f_link,1 = 180 Hz) lies below the
platform's f1 = 198 Hz and the whole frame's f1 is 24 % lower than the condensed
model's; with the legs' own modes (``linked_frequencies``, Craig-Bampton,
:mod:`ppm_stiffness.dynamics.legmodes`) the model has the whole frame's frequencies.
SI throughout.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BALANCE, FloatArray, hat
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.design import Design
from ppm_stiffness.dynamics.mass import mass_matrix_at_pose, platform_mass_matrix
from ppm_stiffness.dynamics.modes import natural_frequencies
from ppm_stiffness.legs.chain import Element, Joint, Link
from ppm_stiffness.legs.joint_kinds import joint_kind
from ppm_stiffness.model import actuator_stiffness_vector, solve_legs, stiffness_at_pose
from ppm_stiffness.poses import full_pose
from ppm_stiffness.validation.fe_model import END_MARGIN, FESettings, body_station, build_model
from ppm_stiffness.validation.frame import FrameBuilder, compliance_at_node

#: PyNite's degrees of freedom of a node, in order, and their places in the library's
#: twist order (phi_x, phi_y, phi_z, x, y, z).
_FE_TO_TWIST = np.array([3, 4, 5, 0, 1, 2])
_SAME_POINT = 1e-9


@dataclass(frozen=True)
class ModalComparison:
    """The FE frame's vibrations against the mass model's at one pose.

    Attributes
    ----------
    model_frequencies : ndarray (6,) [Hz]
        This library's, from K and M at P (the static condensation).
    linked_frequencies : ndarray (6,) [Hz]
        This library's with ``link_modes`` fixed-interface modes per leg
        (:func:`ppm_stiffness.dynamics.legmodes.reduced_frequencies`).
    link_modes : int
        The fixed-interface modes per leg of ``linked_frequencies``.
    reduced_frequencies : ndarray (6,) [Hz]
        The FE frame reduced to P (Guyan), from ``fe_stiffness`` and ``fe_mass``.
    full_frequencies : ndarray (6,) [Hz]
        The six lowest of the whole FE frame with its distributed masses.
    link_frequency : float [Hz]
        f_link,1: the lowest frequency of the frame with P held fixed.
    fe_stiffness, fe_mass : ndarray (6, 6)
        K_P and M_P of the reduced frame, at P, library order (SI).
    model_stiffness, model_mass : ndarray (6, 6)
        This library's K and M at P.
    mass_difference : float
        ``max |M_FE - M| / max |M|`` (length-balanced, L = 0.1 m).
    n_dofs : int
        Free degrees of freedom of the FE frame.
    """

    model_frequencies: FloatArray
    linked_frequencies: FloatArray
    link_modes: int
    reduced_frequencies: FloatArray
    full_frequencies: FloatArray
    link_frequency: float
    fe_stiffness: FloatArray
    fe_mass: FloatArray
    model_stiffness: FloatArray
    model_mass: FloatArray
    mass_difference: float
    n_dofs: int


def beam_mass(mass: float, length: float, axial: float = 0.0) -> FloatArray:
    """Consistent mass (12, 12) of a uniform Euler-Bernoulli bar in its local axes,
    PyNite's order (Dx, Dy, Dz, Rx, Ry, Rz at i, then at j), no rotary inertia of the
    section; its torsional inertia on the twist, linear along it.

    Parameters
    ----------
    mass : float [kg]
    length : float [m]
    axial : float [kg·m^2]
        The bar's inertia about its axis (0: spin neglected).
    """
    m, ell = mass, length
    out = np.zeros((12, 12))
    out[0, 0] = out[6, 6] = m / 3.0
    out[0, 6] = out[6, 0] = m / 6.0
    out[3, 3] = out[9, 9] = axial / 3.0
    out[3, 9] = out[9, 3] = axial / 6.0
    # bending in the local x-y plane: v (1, 7) and theta_z (5, 11), dv/dx = theta_z
    # bending in the local x-z plane: w (2, 8) and theta_y (4, 10), dw/dx = -theta_y
    for v1, r1, v2, r2, s in ((1, 5, 7, 11, 1.0), (2, 4, 8, 10, -1.0)):
        block = (
            m
            / 420.0
            * np.array(
                [
                    [156.0, s * 22.0 * ell, 54.0, -s * 13.0 * ell],
                    [s * 22.0 * ell, 4.0 * ell**2, s * 13.0 * ell, -3.0 * ell**2],
                    [54.0, s * 13.0 * ell, 156.0, -s * 22.0 * ell],
                    [-s * 13.0 * ell, -3.0 * ell**2, -s * 22.0 * ell, 4.0 * ell**2],
                ]
            )
        )
        idx = [v1, r1, v2, r2]
        out[np.ix_(idx, idx)] += block
    return out


def _node_position(fb: FrameBuilder, name: str) -> FloatArray:
    return fb.position(name)


def _link_groups(fb: FrameBuilder) -> list[tuple[FloatArray, FloatArray, list[object]]]:
    """The design links of the frame: (start, end) [m] and their two members."""
    groups: dict[str, list[object]] = {}
    for member in fb.model.members.values():
        if str(member.material.name).startswith("link"):
            groups.setdefault(str(member.material.name), []).append(member)
    out = []
    for members in groups.values():
        ends = [_node_position(fb, m.i_node.name) for m in members]  # type: ignore[attr-defined]
        out.append((ends[0], ends[1], members))
    return out


def _design_links(design: Design, pose: FloatArray) -> list[Link]:
    links = []
    for leg, lp in zip(design.legs, solve_legs(design, pose), strict=True):
        links += [e for e in leg.chain(lp) if isinstance(e, Link)]
    return links


def _bar_links(design: Design, pose: FloatArray) -> list[Link]:
    """The parallelograms' bars as the frame builds them, with their own masses
    (:meth:`~ppm_stiffness.legs.base.LegModel.drawn_members`)."""
    links = []
    for leg, lp in zip(design.legs, solve_legs(design, pose), strict=True):
        links += [e for e in leg.drawn_members(lp)[0] if e.mass is not None]
    return links


def lumps_bar_masses(design: Design, pose: ArrayLike | None = None) -> bool:
    """Whether the mass model lumps a parallelogram's bar masses (a link's
    ``end_mass``): there, its rule (halves at the crossbars, no bending of the bars)
    differs from the frame's continuous bars by physics (docs/dynamics.md, the Delta)."""
    return any(link.end_mass > 0.0 for link in _design_links(design, full_pose(design, pose)))


def _joint_nodes(fb: FrameBuilder, chains: Sequence[Sequence[Element]]) -> dict[int, str]:
    """The node after each joint (id of the Joint element -> node name): each joint adds
    one ``J`` node at its point, in chain order."""
    js = [
        (int(name[1:]), name)
        for name in fb.model.nodes
        if name.startswith("J") and name[1:].isdigit()
    ]
    js.sort()
    used: set[str] = set()
    out: dict[int, str] = {}
    for chain in chains:
        for element in chain:
            if not isinstance(element, Joint):
                continue
            point = np.asarray(element.point, dtype=float).reshape(3)
            for _, name in js:
                if name not in used and np.linalg.norm(fb.position(name) - point) <= 1e-7:
                    used.add(name)
                    out[id(element)] = name
                    break
    return out


def _dof(fb: FrameBuilder, node: str) -> int:
    return int(fb.model.nodes[node].ID) * 6


def rigid_body_mass(mass: float, inertia: ArrayLike, offset: ArrayLike) -> FloatArray:
    """The mass (6, 6) on a node's motion (PyNite's order: displacement, then rotation)
    of a rigid body tied to the node, its centre at ``offset`` from it: ``T^T diag(m,
    m, m, I) T`` with T the body's (velocity of its centre, angular velocity) from the
    node's, ``v_c = d - hat(r) theta``.

    Parameters
    ----------
    mass : float [kg]
    inertia : array_like (3, 3) [kg·m^2]
        About the body's centre, global axes.
    offset : array_like (3,) [m]
        The centre from the node, global axes.
    """
    t = np.eye(6)
    t[:3, 3:] = -hat(np.asarray(offset, dtype=float))
    w = np.zeros((6, 6))
    w[:3, :3] = mass * np.eye(3)
    w[3:, 3:] = np.asarray(inertia, dtype=float)
    out = t.T @ w @ t
    return np.asarray(0.5 * (out + out.T))


def _link_members(
    groups: list[tuple[FloatArray, FloatArray, list[object]]], link: Link
) -> list[object]:
    """The frame's two members of a design link (each from one of its ends)."""
    start = np.asarray(link.start, dtype=float).reshape(3)
    end = np.asarray(link.end, dtype=float).reshape(3)
    match = [
        g
        for g in groups
        if {tuple(np.round(g[0] / _SAME_POINT)), tuple(np.round(g[1] / _SAME_POINT))}
        == {tuple(np.round(start / _SAME_POINT)), tuple(np.round(end / _SAME_POINT))}
    ]
    if len(match) != 1:
        raise DesignError(f"FE modal check: link {link.name} not found in the frame")
    return match[0][2]


def _add_uniform_link(out: FloatArray, fb: FrameBuilder, link: Link, members: list[object]) -> None:
    """The consistent mass of a uniform link's two members (module doc) into ``out``."""
    assert link.mass is not None
    body = link.mass
    length = float(np.linalg.norm(np.asarray(link.end) - np.asarray(link.start)))
    for member in members:
        sub = next(iter(member.sub_members.values()))  # type: ignore[attr-defined]
        part = float(sub.L()) * fb.unit
        local = beam_mass(body.mass * part / length, part, body.axial * part / length)
        t = np.asarray(sub.T(), dtype=float)
        glob = t.T @ local @ t
        dofs = np.r_[
            _dof(fb, sub.i_node.name) + np.arange(6), _dof(fb, sub.j_node.name) + np.arange(6)
        ]
        out[np.ix_(dofs, dofs)] += glob


def _add_link_body(
    out: FloatArray, fb: FrameBuilder, link: Link, members: list[object], station: float
) -> None:
    """A link given as a body (module doc) into ``out``: a rigid body at its centre,
    ``station`` [m] from the link's start, on the node where the link's members meet
    (the centre inside the link) or tied to the nearer end's node."""
    assert link.mass is not None
    body = link.mass
    start = np.asarray(link.start, dtype=float).reshape(3)
    end = np.asarray(link.end, dtype=float).reshape(3)
    length = float(np.linalg.norm(end - start))
    axis = (end - start) / length
    centre = start + station * axis
    xi = station / length
    if END_MARGIN < xi < 1.0 - END_MARGIN:  # on the node between the members (link_split)
        node = str(members[0].j_node.name)  # type: ignore[attr-defined]
    else:
        near = start if xi < 0.5 else end
        node = next(
            str(m.i_node.name)  # type: ignore[attr-defined]
            for m in members
            if np.linalg.norm(fb.position(m.i_node.name) - near) <= _SAME_POINT  # type: ignore[attr-defined]
        )
    transverse = body.mass * length**2 / 12.0 if body.transverse is None else body.transverse
    inertia = transverse * (np.eye(3) - np.outer(axis, axis)) + body.axial * np.outer(axis, axis)
    d = _dof(fb, node)
    out[d : d + 6, d : d + 6] += rigid_body_mass(body.mass, inertia, centre - fb.position(node))


def fe_mass_matrix(design: Design, pose: FloatArray, fb: FrameBuilder, p_node: str) -> FloatArray:
    """The frame's mass matrix over all its degrees of freedom (PyNite's numbering, SI:
    m and rad) from the design's mass model (module doc).

    A parallelogram's bars (the Delta's) are members of the frame: each carries its own
    mass as a uniform bar (consistent beam mass, no spin), where the mass model lumps
    each bar's halves at its crossbars' centres (the arm link's ``end_mass`` and the
    equivalent U joint's mass, :mod:`ppm_stiffness.legs.types._parallelogram`): the
    frame takes neither of those.

    Raises
    ------
    DesignError
        A rotor on a joint away from the element before it, a link the frame lacks,
        or a joint with a mass the frame does not build at its point.
    """
    n = 6 * len(fb.model.nodes)
    out = np.zeros((n, n))
    groups = _link_groups(fb)
    for link in _design_links(design, pose) + _bar_links(design, pose):
        if link.mass is None:  # a link's end_mass: its parallelogram's bars, below
            continue
        members = _link_members(groups, link)
        station = body_station(link)
        if station is None:
            _add_uniform_link(out, fb, link, members)
        else:
            _add_link_body(out, fb, link, members, station)
    p = full_pose(design, pose)
    m_platform = platform_mass_matrix(design, p)[np.ix_(_FE_TO_TWIST, _FE_TO_TWIST)]
    dp = _dof(fb, p_node) + np.arange(6)
    out[np.ix_(dp, dp)] += m_platform
    chains = [leg.chain(lp) for leg, lp in zip(design.legs, solve_legs(design, p), strict=True)]
    after = _joint_nodes(fb, chains)
    for chain in chains:
        for k, element in enumerate(chain):
            if not isinstance(element, Joint) or element.mass is None or element.equivalent:
                continue  # an equivalent joint's mass: its parallelogram's bars
            if id(element) not in after:
                raise DesignError(
                    f"FE modal check, joint {element.name}: the frame has no node at its "
                    "point for its mass"
                )
            d = _dof(fb, after[id(element)])
            out[d : d + 3, d : d + 3] += element.mass.mass * np.eye(3)
            if element.mass.rotor > 0.0:
                before = None if k == 0 else _node_before(fb, chain, k, groups, after)
                _add_rotor(out, fb, element, after[id(element)], before)
    return 0.5 * (out + out.T)


def _node_before(
    fb: FrameBuilder,
    chain: Sequence[Element],
    k: int,
    groups: list[tuple[FloatArray, FloatArray, list[object]]],
    after: dict[int, str],
) -> str:
    """The node before joint ``chain[k]`` (k > 0): the end node of the link before it,
    or the node after the joint before it, at the joint's point.

    Raises
    ------
    DesignError
        Neither is at the joint's point (a rigid offset between them).
    """
    point = np.asarray(chain[k].point, dtype=float).reshape(3)  # type: ignore[union-attr]
    previous = chain[k - 1]
    if isinstance(previous, Joint):
        node = after[id(previous)]
        if np.linalg.norm(fb.position(node) - point) <= _SAME_POINT:
            return node
    else:
        for member in _link_members(groups, previous):
            node = str(member.i_node.name)  # type: ignore[attr-defined]
            if np.linalg.norm(fb.position(node) - point) <= _SAME_POINT:
                return node
    raise DesignError(
        "FE modal check: a rotor on a joint away from the end of the element before it"
    )


def _add_rotor(
    out: FloatArray, fb: FrameBuilder, joint: Joint, node: str, before: str | None
) -> None:
    """A rotor's reflected inertia (:class:`~ppm_stiffness.legs.chain.JointMass`) on
    the relative motion of the joint's node ``node`` and the node ``before`` it (the
    ground when None) along (about) the joint's axis, into ``out``."""
    assert joint.mass is not None
    axis = np.asarray(joint.axis, dtype=float).reshape(3)
    axis = axis / np.linalg.norm(axis)
    shift = 3 if joint_kind(joint.kind).first_rotates else 0
    rows = [(_dof(fb, node) + shift, 1.0)]
    if before is not None:
        rows.append((_dof(fb, before) + shift, -1.0))
    for di, si in rows:
        for dj, sj in rows:
            out[di : di + 3, dj : dj + 3] += si * sj * joint.mass.rotor * np.outer(axis, axis)


def _free_dofs(fb: FrameBuilder) -> FloatArray:
    free = []
    for node in fb.model.nodes.values():
        supports = (
            node.support_DX,
            node.support_DY,
            node.support_DZ,
            node.support_RX,
            node.support_RY,
            node.support_RZ,
        )
        free += [node.ID * 6 + i for i, held in enumerate(supports) if not held]
    return np.array(free, dtype=int)


def _lowest(k: FloatArray, m: FloatArray, count: int) -> FloatArray:
    """The ``count`` lowest frequencies [Hz] of ``K x = omega^2 M x`` (K positive
    definite, M semi-definite) from the largest mu of ``M x = mu K x``."""
    from scipy.linalg import eigh

    n = k.shape[0]
    mu = eigh(m, k, eigvals_only=True, subset_by_index=[n - count, n - 1])
    with np.errstate(divide="ignore"):  # mu = 0: no mass there, an infinite frequency
        return np.sort(1.0 / np.sqrt(mu[::-1])) / (2.0 * math.pi)


def frame_stiffness(fb: FrameBuilder, node: str) -> FloatArray:
    """The frame's stiffness matrix over all its degrees of freedom (PyNite's
    numbering, SI: N/m, N, N·m/rad), assembled by PyNite after six unit-load solves at
    ``node`` (which number the model and split its members)."""
    compliance_at_node(fb, node)  # prepares the model (numbering, sub-members)
    model = fb.model
    combo = next(iter(model.load_combos))
    k_all = np.asarray(model.Ke(combo, sparse=False, check_stability=False), dtype=float)
    # model units -> SI: lengths in units of fb.unit, forces in N, so energies in
    # N·unit: K_SI = unit D K D with D = 1 / unit on translations, 1 on rotations
    scale = np.tile(np.r_[np.full(3, 1.0 / fb.unit), np.ones(3)], len(model.nodes))
    return np.asarray(fb.unit * scale[:, None] * k_all * scale[None, :])


def lowest_frequencies(
    k_all: FloatArray, m_all: FloatArray, fb: FrameBuilder, count: int
) -> FloatArray:
    """The ``count`` lowest frequencies [Hz] of the frame (its free degrees of
    freedom) from its stiffness and mass over all degrees of freedom (SI)."""
    free = _free_dofs(fb)
    k_ff = k_all[np.ix_(free, free)]
    return _lowest(0.5 * (k_ff + k_ff.T), m_all[np.ix_(free, free)], count)


def _linked_frequencies(
    design: Design, pose: FloatArray, k_model: FloatArray, m_model: FloatArray, count: int
) -> FloatArray:
    """The model's six lowest frequencies [Hz] with ``count`` fixed-interface modes
    per leg (:mod:`ppm_stiffness.dynamics.legmodes`), locked actuators."""
    if count == 0:
        return natural_frequencies(k_model, m_model)
    from ppm_stiffness.dynamics.legmodes import (
        design_leg_modes,
        reduced_frequencies,
        reduced_matrices,
        stack_leg_modes,
    )

    k_act = actuator_stiffness_vector(design, None)
    legs = design_leg_modes(design, pose, k_act, count)
    return np.asarray(
        reduced_frequencies(*reduced_matrices(k_model, m_model, *stack_leg_modes(legs)))[0]
    )


def modal_comparison(
    design: Design,
    pose: ArrayLike | None = None,
    settings: FESettings | None = None,
    link_modes: int | None = None,
) -> ModalComparison:
    """The FE frame's frequencies and reduced M and K against the mass model's at one
    pose, locked actuators (module doc).

    Parameters
    ----------
    design : Design
        A design with a mass model (planar or spatial; links uniform or given as
        bodies).
    pose : array_like (n_task,) or (6,), optional
        The pose (the home pose if None).
    settings : FESettings, optional
    link_modes : int, optional
        Fixed-interface modes per leg of the model's ``linked_frequencies`` (the
        default :data:`~ppm_stiffness.dynamics.legmodes.DEFAULT_LINK_MODES` if None).

    Raises
    ------
    DesignError, InputDataError, MissingExtraError, UnreachablePoseError,
    SingularConfigurationError
    """
    from ppm_stiffness.dynamics.legmodes import resolve_link_modes

    count = resolve_link_modes(link_modes)
    p = full_pose(design, pose)
    st = settings or FESettings()
    k_act = actuator_stiffness_vector(design, None)
    fb, p_node = build_model(design, p, k_act, st)
    k_all = frame_stiffness(fb, p_node)
    m_all = fe_mass_matrix(design, p, fb, p_node)
    free = _free_dofs(fb)
    k_ff = k_all[np.ix_(free, free)]
    m_ff = m_all[np.ix_(free, free)]
    k_ff = 0.5 * (k_ff + k_ff.T)
    full = _lowest(k_ff, m_ff, 6)
    # Guyan reduction to P
    master = np.searchsorted(free, _dof(fb, p_node) + np.arange(6))
    slave = np.setdiff1d(np.arange(free.size), master)
    k_ss = k_ff[np.ix_(slave, slave)]
    follow = -np.linalg.solve(k_ss, k_ff[np.ix_(slave, master)])
    t = np.zeros((free.size, 6))
    t[master] = np.eye(6)
    t[slave] = follow
    k_red = t.T @ k_ff @ t
    m_red = t.T @ m_ff @ t
    order = np.argsort(_FE_TO_TWIST)  # FE (D, R) -> library (R, D)
    k_p = 0.5 * (k_red + k_red.T)[np.ix_(order, order)]
    m_p = 0.5 * (m_red + m_red.T)[np.ix_(order, order)]
    # the legs' own vibrations: P held
    link = float(_lowest(k_ss, m_ff[np.ix_(slave, slave)], 1)[0])
    k_model = stiffness_at_pose(design, p)
    m_model = mass_matrix_at_pose(design, p)
    balance = BALANCE  # M_rr / L^2, M_rt / L
    mb = balance[:, None] * m_model * balance[None, :]
    fb_ = balance[:, None] * m_p * balance[None, :]
    return ModalComparison(
        model_frequencies=natural_frequencies(k_model, m_model),
        linked_frequencies=_linked_frequencies(design, p, k_model, m_model, count),
        link_modes=count,
        reduced_frequencies=natural_frequencies(k_p, m_p),
        full_frequencies=full,
        link_frequency=link,
        fe_stiffness=k_p,
        fe_mass=m_p,
        model_stiffness=k_model,
        model_mass=m_model,
        mass_difference=float(np.max(np.abs(fb_ - mb)) / np.max(np.abs(mb))),
        n_dofs=int(free.size),
    )
