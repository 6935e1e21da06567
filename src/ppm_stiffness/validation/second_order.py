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

P-Delta is not a check of the moving-geometry solution itself: it keeps the geometry
of the unloaded pose, so it lacks the second-order kinematics (displacements of order
``u^2 / L``), which are of the same order as the P-Delta correction (docs/statics.md
gives the figures). The FE model's zero-length springs hold their auxiliary nodes to the
ground, exact in linear analysis only, so it cannot be iterated on a moving geometry
either (a corotational FE model would need other joints).

Planar designs only for now (the FE model's joints: docs/validation.md). Twists and
wrenches at P, axes of F_b, SI.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BALANCE, FloatArray
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.core.inputs import validate_wrench
from ppm_stiffness.design import Design
from ppm_stiffness.model import validate_pose
from ppm_stiffness.statics.equilibrium import equilibrium
from ppm_stiffness.statics.moving import moving_equilibrium, relative_size
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
    def moving_correction_difference(self) -> float:
        """The same with the moving-geometry correction in place of the second-order
        one: the part of the moving solution that P-Delta does not model."""
        return self._relative(self.fe_pdelta - self.fe_linear, self.vjm_moving - self.vjm_linear)


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
        A full pose of a planar design (z = rx = ry = 0).
    """
    if not design.planar or np.any(pose[2:5] != 0):
        raise DesignError("the P-Delta comparison takes a planar design at a planar pose")
    fb, p_node = build_model(design, pose[[0, 1, 5]], actuator_stiffness, settings)
    model = fb.model
    twist_scale, wrench_scale = unit_scales(fb.unit)
    for case, value in zip(LOAD_CASES, wrench / wrench_scale, strict=True):
        if value != 0:
            model.add_node_load(p_node, case, float(value), case="load")
    model.add_load_combo("loaded", {"load": 1.0})
    if pdelta:
        model.analyze_PDelta(check_stability=fb.settings.check_stability)
    else:
        model.analyze_linear(check_stability=fb.settings.check_stability)
    fb.check_topology()
    return np.asarray(twist_scale * node_vector(model.nodes[p_node], DISPLACEMENTS, "loaded"))


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
    DesignError
        A design that is not planar.
    MissingExtraError
        Without PyNite (the ``validate`` extra).
    """
    w = validate_wrench(wrench)
    p = validate_pose(design, pose)
    frozen = equilibrium(design, w, p)
    k2, k1 = reference_tangent(design, w, p)
    moving = moving_equilibrium(design, w, p)
    k_act = frozen.actuator_stiffness
    return SecondOrderComparison(
        wrench=w,
        fe_linear=fe_deflection(design, p, w, k_act, False, settings),
        fe_pdelta=fe_deflection(design, p, w, k_act, True, settings),
        vjm_linear=np.asarray(np.linalg.solve(k1, w), dtype=float),
        vjm_second_order=np.asarray(np.linalg.solve(k2, w), dtype=float),
        vjm_moving=moving.twist,
        geometric_fraction=relative_size(k2 - k1, k1),
    )
