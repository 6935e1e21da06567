"""Frame-model building blocks on PyNite: exact lumped springs, unit-load compliance.

PyNite (``pynitefea``) models frames with Euler-Bernoulli members, two-node axial
springs, supports and member-end releases; it has no zero-length spring and no rigid
link. :class:`FrameBuilder` adds what the manipulator model needs on top of that API,
each exact in linear analysis:

* a translational spring between ground and a node: an axial ``Spring3D`` from a
  grounded node on the spring's line;
* a rotational spring: a *torsion-only* member (end forces and bending moments
  released at one end), which after PyNite's static condensation is ``G J / L``
  about its own axis and nothing else;
* a zero-length spring between two coincident nodes: two such elements of twice the
  stiffness in series through an auxiliary node on the spring's line or axis, whose
  other degrees of freedom are held by supports or by grounded springs that act on
  nothing else.

A link's section is turned about its axis so that its ``inertia_y`` and
``inertia_z`` act about the link frame's y and z (:func:`link_y_axis`, the convention
of :mod:`ppm_stiffness.legs.chain`), in any direction in space.

The model can be solved in a length unit other than the metre (forces stay in N)
to balance rotational and translational stiffness entries; inputs and outputs of
this module are SI.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.beam import BeamSection
from ppm_stiffness.core.conventions import Z_AXIS, FloatArray
from ppm_stiffness.core.errors import SingularConfigurationError
from ppm_stiffness.design import SectionModel
from ppm_stiffness.validation import MissingExtraError

#: Load case names at P, in the library's wrench order (m_x, m_y, m_z, f_x, f_y, f_z).
LOAD_CASES = ("MX", "MY", "MZ", "FX", "FY", "FZ")
#: Displacement attributes of a PyNite node, in the library's twist order.
DISPLACEMENTS = ("RX", "RY", "RZ", "DX", "DY", "DZ")
#: Reaction attributes of a PyNite node, in the library's wrench order.
REACTIONS = ("RxnMX", "RxnMY", "RxnMZ", "RxnFX", "RxnFY", "RxnFZ")


@dataclass(frozen=True)
class FESettings:
    """Modelling constants of the FE model (none is a physical parameter).

    Attributes
    ----------
    connector_length : float
        Length s [m] of the auxiliary spring elements; any s > 0 gives the same
        result (the elements are exact), it only sets where auxiliary nodes sit.
    rigid_stiffness : float
        Stiffness scale [N/m] of the platform members (axial EA/L and lateral 3EI/L^3;
        torsion GJ/L = rigid_stiffness * L^2). The platform is rigid in the
        virtual-joint model; the FE difference from that scales as 1/rigid_stiffness.
    length_unit : float
        The model's length unit [m] (forces stay in N). A unit near the links' size
        balances rotational and translational stiffness entries; it changes the
        conditioning of the solve, not the model.
    check_stability : bool
        Let PyNite check the stiffness matrix for unstable degrees of freedom.
    hinge_segments : int
        A notch hinge (a chain leg's R with a ``hinge`` table) is built as this many
        beam members along its profile (:mod:`ppm_stiffness.validation.hinge_chain`);
        0 builds it as the elastic R of the virtual-joint model.
    """

    connector_length: float = 5e-3
    rigid_stiffness: float = 1e11
    length_unit: float = 0.1
    check_stability: bool = True
    hinge_segments: int = 32


def require_pynite() -> Any:
    """The ``Pynite`` package, or :class:`MissingExtraError` with the install hint."""
    try:
        return importlib.import_module("Pynite")
    except ImportError as exc:  # pragma: no cover - exercised only without the extra
        raise MissingExtraError(
            "the FE validation needs PyNite: pip install 'ppm-stiffness[validate]' "
            "(package pynitefea)"
        ) from exc


#: PyNite's messages (it raises a bare ``Exception``) when its solve finds the stiffness
#: matrix singular: a node with no stiffness in some direction, or a solution that
#: does not satisfy equilibrium to a relative 1e-6.
_PYNITE_SINGULAR = ("stiffness matrix is singular", "Unstable node")


def analyze_linear(model: Any, check_stability: bool) -> None:
    """``model.analyze_linear``, PyNite's failure of a singular stiffness matrix turned
    into :class:`SingularConfigurationError` (any other error passes through).

    The virtual-joint model has found the pose non-singular before the FE model is
    built, so a singular FE matrix means a solve that double precision cannot carry
    out: parts many orders of magnitude stiffer than the others (a Young's modulus
    such as 1e20 Pa, near-rigid joints) make the frame's stiffness matrix too
    ill-conditioned for PyNite's equilibrium check.
    """
    try:
        model.analyze_linear(check_stability=check_stability)
    except Exception as exc:
        if type(exc) is not Exception or not any(m in str(exc) for m in _PYNITE_SINGULAR):
            raise
        raise SingularConfigurationError(
            "FE model: PyNite finds the frame's stiffness matrix singular (no "
            "equilibrium to 1e-6); the FE solve is ill-conditioned when some parts are "
            "many orders of magnitude stiffer than others (a Young's modulus such as "
            "1e20 Pa, near-rigid joints): give them realistic values to validate"
        ) from None


def unit_vector(v: ArrayLike) -> FloatArray:
    a = np.asarray(v, dtype=float)
    return np.asarray(a / np.linalg.norm(a))


def link_y_axis(direction: ArrayLike) -> FloatArray:
    """Local y of a link along ``direction`` (3,): ``unit(z x x)``, or ``unit(x x e_x)``
    when the link is along z (the link frame of :mod:`ppm_stiffness.legs.chain`, in
    which a section's ``inertia_y`` and ``inertia_z`` are given)."""
    x = unit_vector(direction)
    y = np.cross(Z_AXIS, x)
    if np.linalg.norm(y) < 1e-12:
        y = np.cross(x, np.array([1.0, 0.0, 0.0]))
    return unit_vector(y)


class FrameBuilder:
    """Adds nodes, members and exact lumped springs to a PyNite ``FEModel3D``.

    Parameters
    ----------
    settings : FESettings
    """

    def __init__(self, settings: FESettings) -> None:
        pynite = require_pynite()
        self.model = pynite.FEModel3D()
        self.settings = settings
        self.s = settings.connector_length
        self.unit = settings.length_unit
        self._count = 0
        # G = E = 1 Pa: spring members get their stiffness from the section numbers.
        self.model.add_material("unit", 1.0, 1.0, 0.0, 0.0)

    def _name(self, prefix: str) -> str:
        self._count += 1
        return f"{prefix}{self._count}"

    def node(self, point: ArrayLike, prefix: str = "N") -> str:
        """A free node at ``point`` [m]."""
        x, y, z = (float(c) for c in np.asarray(point, dtype=float) / self.unit)
        return str(self.model.add_node(self._name(prefix), x, y, z))

    def ground(self, point: ArrayLike) -> str:
        """A node at ``point`` held in all six degrees of freedom."""
        name = self.node(point, "G")
        self.model.def_support(name, True, True, True, True, True, True)
        return name

    def material(self, section: BeamSection | SectionModel, prefix: str = "link") -> str:
        """Material and section of a design link (or of another beam: a notch hinge's
        member, ``prefix = "notch"``); returns the common name."""
        name = self._name(prefix)
        l2, l4 = self.unit**2, self.unit**4
        self.model.add_material(
            name, section.young_modulus * l2, section.shear_modulus * l2, 0.3, 0.0
        )
        self.model.add_section(
            name,
            section.area / l2,
            section.inertia_y / l4,
            section.inertia_z / l4,
            section.torsion_constant / l4,
        )
        return name

    def member(
        self, i_node: str, j_node: str, material: str, section: str, **releases: bool
    ) -> str:
        """A frame member from ``i_node`` to ``j_node``; ``releases`` as PyNite's."""
        name = str(self.model.add_member(self._name("M"), i_node, j_node, material, section))
        if releases:
            self.model.def_releases(name, **releases)
        return name

    def beam(
        self, i_node: str, j_node: str, section: BeamSection | SectionModel, **releases: bool
    ) -> str:
        """An Euler-Bernoulli link with the design's section, one member, its local y
        along :func:`link_y_axis`."""
        mat = self.material(section)
        name = self.member(i_node, j_node, mat, mat, **releases)
        self.orient(name, link_y_axis(self.position(j_node) - self.position(i_node)))
        return name

    def orient(self, member: str, y_axis: ArrayLike) -> None:
        """Turn ``member`` about its axis until its local y is ``y_axis`` (unit, normal
        to the member; PyNite's ``rotation``).

        Raises
        ------
        SingularConfigurationError
            If PyNite's local axes do not follow (a change of PyNite).
        """
        y = np.asarray(y_axis, dtype=float)
        m = self.model.members[member]
        m.rotation = 0.0
        rot = m.T()[:3, :3]
        m.rotation = float(np.degrees(np.arctan2(float(y @ rot[2]), float(y @ rot[1]))))
        rot = m.T()[:3, :3]
        if abs(float(rot[1] @ y)) < 1.0 - 1e-9:
            raise SingularConfigurationError(  # pragma: no cover - a PyNite change
                f"FE model: cannot align the local axes of member {member}"
            )

    # --- zero-length joints between coincident nodes ------------------------------

    def support(self, node: str, dofs: str) -> None:
        """Hold ``node`` in the global degrees of freedom named in ``dofs`` (a subset
        of ``"DX DY DZ RX RY RZ"``)."""
        names = ("DX", "DY", "DZ", "RX", "RY", "RZ")
        self.model.def_support(node, *(n in dofs.split() for n in names))

    def position(self, node: str) -> FloatArray:
        """Position of ``node`` [m]."""
        n = self.model.nodes[node]
        return np.array([n.X, n.Y, n.Z]) * self.unit

    def segment(
        self,
        a: str,
        b: str,
        section: str,
        material: str,
        y_axis: ArrayLike | None = None,
        at: float = 0.5,
    ) -> str:
        """A straight member a-b as two members from each end to a new node at the
        fraction ``at`` of its length from a (the midpoint by default; a link's body
        sits on it, :func:`ppm_stiffness.validation.fe_model.link_split`) (local y along
        ``y_axis`` if given, else PyNite's default).

        PyNite splits a member at any node it finds strictly inside it; a node
        coincident with the member's j-end may land at ``t < L`` after round-off, but
        at the i-end ``t = 0`` exactly. Joints put twin nodes at both ends of a link,
        so both halves start at an end. Two Euler-Bernoulli members with the same
        section in series are the same beam (no load between them). Returns the
        node between them.
        """
        mid = self.node((1.0 - at) * self.position(a) + at * self.position(b), "H")
        for end in (a, b):
            name = self.member(end, mid, material, section)
            if y_axis is not None:
                self.orient(name, y_axis)
        return mid

    def link(self, a: str, b: str, section: BeamSection | SectionModel, at: float = 0.5) -> str:
        """An Euler-Bernoulli link a-b with the design's section (:meth:`segment`, its
        two members meeting at the fraction ``at`` from a), its section axes those of
        the link frame (:func:`link_y_axis`)."""
        mat = self.material(section)
        y_axis = link_y_axis(self.position(b) - self.position(a))
        return self.segment(a, b, mat, mat, y_axis, at)

    def rigid(self, a: str, b: str) -> str:
        """A stiff member a-b standing in for a rigid body (:meth:`segment`).

        Axial EA/L and lateral 3EI/L^3 are ``settings.rigid_stiffness`` [N/m] and the
        torsion GJ/L is ``rigid_stiffness * L^2`` [N·m/rad] over the whole length L.
        """
        k = self.settings.rigid_stiffness * self.unit  # N/m -> N/unit
        ell = float(np.linalg.norm(self.position(b) - self.position(a))) / self.unit
        name = self._name("rigid")
        self.model.add_section(name, k * ell, k * ell**3 / 3, k * ell**3 / 3, k * ell**3)
        return self.segment(a, b, name, "unit")

    def moment_member(
        self,
        i_node: str,
        j_node: str,
        axes: tuple[FloatArray, FloatArray],
        stiffness: FloatArray,
        free: tuple[bool, bool, bool],
    ) -> str:
        """A member that transmits only a moment: rotational springs in its own axes.

        Every end force is released at ``j_node``, so the shear is zero and the
        moment constant along the member: after PyNite's static condensation the
        element is ``diag(GJ, EI_y, EI_z) / L`` on the relative rotation of its ends
        about its local (x, y, z) axes and nothing else (exact, Euler-Bernoulli).

        Parameters
        ----------
        axes : (ndarray (3,), ndarray (3,))
            Unit local x (along i -> j) and the wanted local y; the member is turned
            about x until PyNite's local y is this axis.
        stiffness : ndarray (3,)
            About local x, y, z [N·m/rad], each > 0.
        free : tuple of 3 bool
            Moments about local x, y, z also released at ``j_node`` (no stiffness).
        """
        x_axis, y_axis = axes
        k = np.asarray(stiffness, dtype=float) / self.unit  # N·m/rad -> N·unit/rad
        ell = float(np.linalg.norm(self.position(j_node) - self.position(i_node))) / self.unit
        section = self._name("mom")
        # G = E = 1: J = k_x L, I = k L; A only conditions the condensation (EA/L = 1).
        self.model.add_section(section, ell, k[1] * ell, k[2] * ell, k[0] * ell)
        name = self.member(i_node, j_node, "unit", section)
        if abs(float(self.model.members[name].T()[0, :3] @ x_axis)) < 1.0 - 1e-9:
            raise SingularConfigurationError(  # pragma: no cover - a caller's mistake
                f"FE model: member {name} does not lie along its x axis"
            )
        self.orient(name, y_axis)
        releases = {"Dxj": True, "Dyj": True, "Dzj": True}
        for dof, f in zip(("Rxj", "Ryj", "Rzj"), free, strict=True):
            if f:
                releases[dof] = True
        self.model.def_releases(name, **releases)
        return name

    def axial_spring(self, i_node: str, j_node: str, stiffness: float) -> str:
        """A two-node spring acting along the line between its nodes [N/m]."""
        k_model = stiffness * self.unit  # N/m -> N/unit
        return str(self.model.add_spring(self._name("S"), i_node, j_node, k_model))

    def check_topology(self) -> None:
        """Raise if PyNite split a member at a node lying on it (unintended joint)."""
        for member in self.model.members.values():
            if len(member.sub_members) != 1:
                raise SingularConfigurationError(
                    f"FE model: a node lies on member {member.name}; "
                    "change FESettings.connector_length"
                )


def node_vector(node: Any, attrs: tuple[str, ...], combo: str) -> FloatArray:
    return np.array([getattr(node, a)[combo] for a in attrs], dtype=float)


def unit_scales(unit: float) -> tuple[FloatArray, FloatArray]:
    """Model-to-SI factors: twist_SI = t * twist_model, wrench_SI = w * wrench_model."""
    t = np.array([1.0, 1.0, 1.0, unit, unit, unit])
    w = np.array([unit, unit, unit, 1.0, 1.0, 1.0])
    return t, w


def compliance_at_node(fb: FrameBuilder, node: str) -> FloatArray:
    """Solve six unit-load cases at ``node``; the 6x6 compliance (library order, SI)."""
    model = fb.model
    for case in LOAD_CASES:
        model.add_node_load(node, case, 1.0, case=case)
        model.add_load_combo(case, {case: 1.0})
    analyze_linear(model, fb.settings.check_stability)
    fb.check_topology()
    n = model.nodes[node]
    c_model = np.stack([node_vector(n, DISPLACEMENTS, case) for case in LOAD_CASES], axis=1)
    t, w = unit_scales(fb.unit)
    return np.asarray(t[:, None] * c_model / w[None, :])


def fe_cantilever_compliance(
    section: SectionModel, root: ArrayLike, tip: ArrayLike, settings: FESettings | None = None
) -> FloatArray:
    """Tip compliance of a single clamped link, one PyNite member, in the tip frame.

    The tip frame is the link frame: x along the link (root to tip), y =
    :func:`link_y_axis` (``unit(z x x)``; ``unit(x x e_x)`` along z), z = x x y; the
    link may point in any direction.

    Returns
    -------
    ndarray, shape (6, 6)
        Maps the tip wrench (m, f) to the tip twist (rotation, displacement), local axes.
    """
    r0 = np.asarray(root, dtype=float)
    r1 = np.asarray(tip, dtype=float)
    fb = FrameBuilder(settings or FESettings())
    n0 = fb.ground(r0)
    n1 = fb.node(r1)
    fb.beam(n0, n1, section)
    c_global = compliance_at_node(fb, n1)
    x = unit_vector(r1 - r0)
    y = link_y_axis(x)
    rot = np.zeros((6, 6))
    rot[:3, :3] = rot[3:, 3:] = np.stack([x, y, np.cross(x, y)])
    return np.asarray(rot @ c_global @ rot.T)
