"""A second-order check of the geometric stiffness with the FE frame model (P-Delta).

PyNite's P-Delta analysis (``FEModel3D.analyze_PDelta``) solves the frame once linearly,
takes every member's axial force from that solution and solves again with the members'
geometric stiffness added: ``u = (K + K_g(N)) ^-1 f`` on the undeformed geometry. The
virtual-joint analogue is the loaded tangent at the unloaded geometry with the frozen
model's leg wrenches (:func:`ppm_stiffness.statics.moving_tangents.reference_tangent`),
``u = K_2^-1 f``. The two are the same approximation built independently (the frame's
members and lumped springs against the chains' screws and Lie brackets), so their
second-order corrections ``u_2 - u_1`` should agree to the models' difference;
:func:`compare_second_order` gives both with the first-order ones and the full
moving-geometry solution (:mod:`ppm_stiffness.statics.moving`).

What PyNite's P-Delta leaves out. Its geometric stiffness of a member comes from the
member's **axial force only**. The FE platform is a star of stiff members from the legs'
platform points to P (:func:`~ppm_stiffness.validation.fe_model.build_model`), which
carry the legs' forces as shear too; for a rigid body the shear's geometric terms do
not vanish when the platform turns about an axis with a component along a member
(rotations about x and y of a planar platform: spatial designs), so the FE's tangent
differs from the rigid platform's by :func:`platform_shear_term` (derived in its doc).
:func:`compare_second_order` gives the virtual-joint correction with that term added
(``vjm_axial_only``: the same structure as the FE model's), and without. For a planar
design under an in-plane load the term does not act (the platform turns about z,
normal to every member).

P-Delta is not a check of the moving-geometry solution itself: it keeps the geometry
of the unloaded pose, so it lacks the second-order kinematics (displacements of order
``u^2 / L``), which are of the same order as the P-Delta correction (docs/statics.md
gives the figures). The FE model's zero-length springs hold their auxiliary nodes to the
ground, exact in linear analysis only, so it cannot be iterated on a moving geometry
either (a corotational FE model would need other joints).

Any design, planar or spatial (the FE model builds any chain at the full pose). Twists
and wrenches at P, axes of F_b, SI.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BALANCE, FloatArray
from ppm_stiffness.core.inputs import validate_wrench
from ppm_stiffness.design import Design
from ppm_stiffness.model import validate_pose
from ppm_stiffness.statics.equilibrium import equilibrium
from ppm_stiffness.statics.moving import moving_loaded_state, relative_size
from ppm_stiffness.statics.moving_tangents import reference_tangent
from ppm_stiffness.validation.fe_model import FESettings, build_model
from ppm_stiffness.validation.frame import DISPLACEMENTS, LOAD_CASES, node_vector, unit_scales


@dataclass(frozen=True)
class SecondOrderComparison:
    """Deflections of P under one wrench (each a twist (6,) [rad, m] at P, axes of F_b).

    Attributes
    ----------
    wrench : ndarray (6,)
    fe_linear, fe_pdelta : ndarray (6,)
        The FE frame model, linear and P-Delta.
    vjm_linear, vjm_second_order : ndarray (6,)
        The frozen model, and the loaded tangent at the unloaded geometry.
    vjm_moving : ndarray (6,)
        The moving-geometry equilibrium (the rotation vector and P's displacement).
    vjm_axial_only : ndarray (6,)
        The second-order tangent with :func:`platform_shear_term` added: what an
        axial-force-only P-Delta of the FE's star platform gives.
    geometric_fraction : float
        ``||K_2 - K_1|| / ||K_1||`` (length-balanced Frobenius norms): how large the
        geometric term is against the frozen K.
    """

    wrench: FloatArray
    fe_linear: FloatArray
    fe_pdelta: FloatArray
    vjm_linear: FloatArray
    vjm_second_order: FloatArray
    vjm_moving: FloatArray
    geometric_fraction: float
    vjm_axial_only: FloatArray

    @staticmethod
    def _relative(a: FloatArray, b: FloatArray) -> float:
        """``|a - b| / |b|`` of length-balanced twists (rotations times L)."""
        return float(np.linalg.norm((a - b) / BALANCE) / np.linalg.norm(b / BALANCE))

    @property
    def correction_difference(self) -> float:
        """The second-order corrections ``u_2 - u_1`` of the two models, relative
        difference (FE P-Delta against the virtual-joint second-order tangent)."""
        return self._relative(
            self.fe_pdelta - self.fe_linear, self.vjm_second_order - self.vjm_linear
        )

    @property
    def axial_only_difference(self) -> float:
        """:attr:`correction_difference` against ``vjm_axial_only``: both models then
        leave out the shear of the FE platform's members."""
        return self._relative(
            self.fe_pdelta - self.fe_linear, self.vjm_axial_only - self.vjm_linear
        )

    @property
    def moving_correction_difference(self) -> float:
        """The same with the moving-geometry correction in place of the second-order
        one: the part of the moving solution that P-Delta does not model."""
        return self._relative(self.fe_pdelta - self.fe_linear, self.vjm_moving - self.vjm_linear)


#: Member3D.Releases indices of the end translations (DX, DY, DZ at the i and j ends).
_TRANSLATION_RELEASES = (0, 1, 2, 6, 7, 8)


@contextmanager
def _released_members_carry_no_axial_force() -> Iterator[None]:
    """While active, PyNite's geometric stiffness of a member whose end translations are
    released is that of a zero axial force.

    PyNite (``FEModel3D.Kg``) takes a member's axial force from the relative axial
    displacement of its ends, ``E A / L (d_j - d_i)``, also for a member whose end forces
    are released, which carries none: the joints' moment-only members
    (:mod:`ppm_stiffness.validation.joints`), whose released end sits on an auxiliary
    node. Their made-up axial force entered their geometric stiffness, scaled with
    ``1 / connector_length``: on the 3-RPS under a force along x (carried in bending,
    real axial forces of 1e-6 N) P-Delta's correction was rz -2.0e-2, -2.4e-2 and
    -1.0e-1 rad for connectors of 2, 5 and 10 mm, and is below 1e-9 rad with this
    (the hexapod's and the planar examples' corrections are unchanged to 5 digits).
    """
    from Pynite.Member3D import Member3D

    original = Member3D.Kg

    def kg(self: Any, P: float = 0.0) -> Any:  # noqa: N803 - PyNite's name
        if any(self.Releases[i] for i in _TRANSLATION_RELEASES):
            P = 0.0  # noqa: N806
        return original(self, P)

    Member3D.Kg = kg
    try:
        yield
    finally:
        Member3D.Kg = original


def fe_deflection(
    design: Design,
    pose: FloatArray,
    wrench: FloatArray,
    actuator_stiffness: ArrayLike,
    pdelta: bool,
    settings: FESettings | None = None,
) -> FloatArray:
    """Deflection of P (6,) of the FE frame model under ``wrench`` at P: PyNite's linear
    or P-Delta analysis (module doc).

    Parameters
    ----------
    pose : ndarray (6,)
        A full pose (any design: the FE model builds any chain).
    """
    fb, p_node = build_model(design, pose, actuator_stiffness, settings)
    model = fb.model
    twist_scale, wrench_scale = unit_scales(fb.unit)
    for case, value in zip(LOAD_CASES, wrench / wrench_scale, strict=True):
        if value != 0:
            model.add_node_load(p_node, case, float(value), case="load")
    model.add_load_combo("loaded", {"load": 1.0})
    if pdelta:
        with _released_members_carry_no_axial_force():
            model.analyze_PDelta(check_stability=fb.settings.check_stability)
    else:
        model.analyze_linear(check_stability=fb.settings.check_stability)
    fb.check_topology()
    return np.asarray(twist_scale * node_vector(model.nodes[p_node], DISPLACEMENTS, "loaded"))


def platform_shear_term(design: Design, pose: FloatArray, leg_wrenches: FloatArray) -> FloatArray:
    """The geometric stiffness (6, 6) at P that the FE's P-Delta gives its platform on top
    of the rigid platform's, under the legs' wrenches ``leg_wrenches`` (n_legs, 6) about P
    (each leg's load, as :class:`~ppm_stiffness.statics.equilibrium.EquilibriumBatch`
    ``leg_wrenches``; the platform receives their opposite), at the full pose (6,).

    The FE platform is a tree of stiff members: from each distinct platform point (the
    legs' last joints) to P, or to a platform point on its way to P
    (:func:`~ppm_stiffness.validation.fe_model.build_model`). Turned rigidly by a small
    rotation theta, member j (vector d_j from its parent end to its child end, carrying
    the force F_j that the legs apply beyond its child end) moves its ends apart by
    theta x d_j. The rigid body's second-order energy of the fixed-direction forces F_j
    is ``1/2 sum_j [|theta|^2 F_j.d_j - (theta.F_j)(theta.d_j)]``; the members' axial-only
    geometric stiffness ``N_j / |d_j|`` with ``N_j = F_j.e_j`` gives ``1/2 sum_j N_j
    |theta x d_j|^2 / |d_j|``. Their difference is ``1/2 theta^T S theta`` with
    ``S = sum_j sym(d_j F_perp_j^T)``, F_perp_j the part of F_j normal to the member: 0 for
    a planar platform turning about z. Returned as the rotation block of a 6x6 matrix
    (twist (phi, v) at P). A leg's moment about its platform point is left out (the FE's
    members carry it as end moments, which P-Delta leaves out as well).
    """
    from ppm_stiffness.model import solve_legs
    from ppm_stiffness.validation.fe_model import _end_point, _leg_hinges, _platform_parents
    from ppm_stiffness.validation.joints import SAME_POINT

    leg_poses = solve_legs(design, pose)
    points: list[FloatArray] = []
    forces: list[FloatArray] = []
    segments = FESettings().hinge_segments  # the FE's platform points (a notch's far end)
    for i, leg in enumerate(design.legs):
        chain = leg.chain(leg_poses[i])
        q = _end_point(chain, _leg_hinges(design, i, chain, segments))
        f = -np.asarray(leg_wrenches[i, 3:], dtype=float)  # on the platform
        if np.linalg.norm(q) <= SAME_POINT:
            continue  # a leg at P: no member
        found = next((j for j, r in enumerate(points) if np.linalg.norm(q - r) <= SAME_POINT), None)
        if found is None:
            points.append(q)
            forces.append(f)
        else:
            forces[found] = forces[found] + f
    parents = _platform_parents(points)
    carried = [f.copy() for f in forces]  # the force beyond each member's child end
    order = sorted(range(len(points)), key=lambda j: -float(np.linalg.norm(points[j])))
    for j in order:  # outer points first: a parent lies nearer to P than its children
        if parents[j] >= 0:
            carried[parents[j]] = carried[parents[j]] + carried[j]
    s = np.zeros((3, 3))
    for j, q in enumerate(points):
        d = q - (points[parents[j]] if parents[j] >= 0 else np.zeros(3))
        e = d / np.linalg.norm(d)
        f_perp = carried[j] - (carried[j] @ e) * e
        s += 0.5 * (np.outer(d, f_perp) + np.outer(f_perp, d))
    out = np.zeros((6, 6))
    out[:3, :3] = s
    return out


def compare_second_order(
    design: Design,
    wrench: ArrayLike,
    pose: ArrayLike | None = None,
    settings: FESettings | None = None,
) -> SecondOrderComparison:
    """FE linear and P-Delta, frozen, second-order and moving virtual-joint deflections
    of P under ``wrench`` (6,) at P (module doc). The FE actuators get the frozen
    model's tangent stiffness under the load.

    Raises
    ------
    MissingExtraError
        Without PyNite (the ``validate`` extra).
    """
    w = validate_wrench(wrench)
    p = validate_pose(design, pose)
    frozen = equilibrium(design, w, p)
    k2, k1 = reference_tangent(design, w, p)
    moving = moving_loaded_state(design, w, p)
    k_act = frozen.actuator_stiffness
    k_axial = k2 + platform_shear_term(design, p, frozen.leg_wrenches)
    return SecondOrderComparison(
        wrench=w,
        fe_linear=fe_deflection(design, p, w, k_act, False, settings),
        fe_pdelta=fe_deflection(design, p, w, k_act, True, settings),
        vjm_linear=np.asarray(np.linalg.solve(k1, w), dtype=float),
        vjm_second_order=np.asarray(np.linalg.solve(k2, w), dtype=float),
        vjm_moving=moving.twist,
        geometric_fraction=relative_size(k2 - k1, k1),
        vjm_axial_only=np.asarray(np.linalg.solve(k_axial, w), dtype=float),
    )
