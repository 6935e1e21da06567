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
_END_FORCES_AND_BENDING = ("Dx", "Dy", "Dz", "Ry", "Rz")


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
    """

    connector_length: float = 5e-3
    rigid_stiffness: float = 1e12
    length_unit: float = 0.1
    check_stability: bool = True


def require_pynite() -> Any:
    """The ``Pynite`` package, or :class:`MissingExtraError` with the install hint."""
    try:
        return importlib.import_module("Pynite")
    except ImportError as exc:  # pragma: no cover - exercised only without the extra
        raise MissingExtraError(
            "the FE validation needs PyNite: pip install 'ppm-stiffness[validate]' "
            "(package pynitefea)"
        ) from exc


def unit_vector(v: ArrayLike) -> FloatArray:
    a = np.asarray(v, dtype=float)
    return np.asarray(a / np.linalg.norm(a))


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

    def material(self, section: SectionModel) -> str:
        """Material and section of a design link; returns the common name."""
        name = self._name("link")
        l2, l4 = self.unit**2, self.unit**4
        self.model.add_material(
            name, section.young_modulus * l2, section.shear_modulus * l2, 0.3, 0.0
        )
        self.model.add_section(
            name, section.area / l2, section.inertia_y / l4, section.inertia_z / l4,
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

    def beam(self, i_node: str, j_node: str, section: SectionModel, **releases: bool) -> str:
        """An Euler-Bernoulli link with the design's section (local z = global z)."""
        mat = self.material(section)
        return self.member(i_node, j_node, mat, mat, **releases)

    def torsion_spring(self, i_node: str, j_node: str, stiffness: float, free_end: str) -> str:
        """A member that transmits only the torque about its own axis.

        Every end force and both bending moments are released at ``free_end``
        ('i' or 'j'), so the condensed element is ``GJ/L`` on the two end rotations
        about the axis and nothing else. With G = 1, J = stiffness * L (model units).

        Parameters
        ----------
        stiffness : float
            [N·m/rad].
        """
        xi = np.array([self.model.nodes[i_node].X, self.model.nodes[i_node].Y,
                       self.model.nodes[i_node].Z])
        xj = np.array([self.model.nodes[j_node].X, self.model.nodes[j_node].Y,
                       self.model.nodes[j_node].Z])
        length = float(np.linalg.norm(xj - xi))
        section = self._name("tor")
        # A, I only condition the condensation (EA/L = 1 N/m, 12EI/L^3 = 1 N/m).
        k_model = stiffness / self.unit  # N·m/rad -> N·unit/rad
        self.model.add_section(section, length, length**3 / 12, length**3 / 12,
                               k_model * length)
        releases = {f"{dof}{free_end}": True for dof in _END_FORCES_AND_BENDING}
        return self.member(i_node, j_node, "unit", section, **releases)

    def axial_spring(self, i_node: str, j_node: str, stiffness: float) -> str:
        """A two-node spring acting along the line between its nodes [N/m]."""
        k_model = stiffness * self.unit  # N/m -> N/unit
        return str(self.model.add_spring(self._name("S"), i_node, j_node, k_model))

    # --- lumped springs at a point ------------------------------------------------

    def grounded_translation(
        self, node: str, point: FloatArray, axis: FloatArray, stiffness: float, offset: float
    ) -> None:
        """Spring ``stiffness`` [N/m] along ``axis`` between ground and ``node`` (at
        ``point``); the grounded end sits at ``point + offset * axis``."""
        self.axial_spring(self.ground(point + offset * axis), node, stiffness)

    def grounded_rotation(
        self, node: str, point: FloatArray, axis: FloatArray, stiffness: float, offset: float
    ) -> None:
        """Rotational spring ``stiffness`` [N·m/rad] about ``axis`` between ground and
        ``node``; the grounded end sits at ``point + offset * axis``."""
        self.torsion_spring(self.ground(point + offset * axis), node, stiffness, "j")

    def link_translation(
        self, n1: str, n2: str, point: FloatArray, axis: FloatArray, stiffness: float,
        offset: float, others: tuple[FloatArray, FloatArray],
    ) -> None:
        """Zero-length spring along ``axis`` between coincident nodes ``n1``, ``n2``.

        Two axial springs of ``2 * stiffness`` in series through an auxiliary node on
        the spring's line (at ``point + offset * axis``); that node's rotations are
        supported and its translations along ``others`` (both perpendicular to
        ``axis``) held by grounded springs that act on nothing else.
        """
        pos = point + offset * axis
        aux = self.node(pos, "A")
        self.model.def_support(aux, False, False, False, True, True, True)
        self.axial_spring(n1, aux, 2.0 * stiffness)
        self.axial_spring(aux, n2, 2.0 * stiffness)
        for e in others:
            self.axial_spring(self.ground(pos - self.s * e), aux, stiffness)

    def link_rotation(
        self, n1: str, n2: str, point: FloatArray, axis: FloatArray, stiffness: float,
        offset: float, others: tuple[FloatArray, FloatArray],
    ) -> None:
        """Zero-length rotational spring about ``axis`` between ``n1`` and ``n2``.

        Two torsion-only members of ``2 * stiffness`` in series through an auxiliary
        node at ``point + offset * axis``; its translations are supported and its
        rotations about ``others`` held by grounded torsion springs.
        """
        pos = point + offset * axis
        aux = self.node(pos, "X")
        self.model.def_support(aux, True, True, True, False, False, False)
        # both members start at the coincident nodes: PyNite splits a member at any
        # node it finds strictly inside (0 < t < L), and t = 0 is exact at the i-end
        self.torsion_spring(n1, aux, 2.0 * stiffness, "j")
        self.torsion_spring(n2, aux, 2.0 * stiffness, "j")
        for e in others:
            self.torsion_spring(self.ground(pos - self.s * e), aux, stiffness, "j")

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
    model.analyze_linear(check_stability=fb.settings.check_stability)
    fb.check_topology()
    n = model.nodes[node]
    c_model = np.stack([node_vector(n, DISPLACEMENTS, case) for case in LOAD_CASES], axis=1)
    t, w = unit_scales(fb.unit)
    return np.asarray(t[:, None] * c_model / w[None, :])


def fe_cantilever_compliance(
    section: SectionModel, root: ArrayLike, tip: ArrayLike, settings: FESettings | None = None
) -> FloatArray:
    """Tip compliance of a single clamped link, one PyNite member, in the tip frame.

    The tip frame has x along the link (root to tip), y = z x x and z = F_b's z; the
    link must lie in the plane z = const (as the manipulator's links do).

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
    y = np.cross(Z_AXIS, x)
    rot = np.zeros((6, 6))
    rot[:3, :3] = rot[3:, 3:] = np.stack([x, y, Z_AXIS])
    return np.asarray(rot @ c_global @ rot.T)
