"""The manipulator at a pose as a 3D frame model in PyNite, and its stiffness at P.

Why PyNite (``pynitefea``): its frame members are Euler-Bernoulli, the beam theory of
the paper's eq. (3c), so the two models share their beam theory and differ only in
how they are built and solved; member-end releases give the passive revolute
exactly; two-node axial springs and released members give exact lumped springs.
pyfe3d (Timoshenko beams, 6-component springs) would add shear deformation the
virtual-joint model does not have, and its passive joints would be penalty springs.

Model (coordinates: F_b axes, origin at P; PyNite's global X, Y, Z are our x, y, z)
----------------------------------------------------------------------------------
Per leg, nodes B (carriage), Cp (proximal tip at C), Cr (rod root at C), D:

* guide + actuator: six springs from B to the ground in the axes (u, y_B, z) at B:
  translations (actuator along u, lateral along y_B, vertical along z) are PyNite
  ``Spring3D`` elements from a grounded node on the spring's line to B; rotations
  (roll about u, pitch about y_B, yaw about z) are *torsion-only* members (every end
  force and bending moment released at B, so they transmit a pure torque about
  their axis, stiffness ``G J / L``) from a grounded node on the axis to B;
* proximal link: a frame member between Cp and B with the design's proximal section;
* bearing: four zero-length springs between Cp and Cr in the axes (w, y_D, z) at C
  (tilts about y_D and z, radial along y_D and z). A frame model has no zero-length
  element, so each is two elements of twice the stiffness in series through an
  auxiliary node on the spring's line or axis; the auxiliary node's other degrees of
  freedom are held by the ground (supports or perpendicular springs that touch
  nothing else). Nothing connects Cp and Cr along or about w: that is the passive
  cylindrical joint (rod sliding and turning in the bearing);
* rod: a frame member Cr -> D with the design's distal section;
* platform: a stiff member P -> D with the moment about z released at D: the
  passive revolute. This is the only approximation: the platform is rigid in the
  virtual-joint model and ``rigid_stiffness`` times stiffer than 1 N/m here.

All spring realisations are exact in linear analysis (a two-node axial spring and a
released member add stiffness only along their own line or axis). The stiffness at
P comes from six unit-load cases at P (moments, then forces, along the base axes):
the displacements are the compliance columns, ``K = inv(C)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import Z_AXIS, FloatArray, length_balanced_compliance
from ppm_stiffness.core.errors import DesignError, SingularConfigurationError
from ppm_stiffness.design import Design
from ppm_stiffness.model import locked_actuator_stiffness, solve_legs
from ppm_stiffness.validation.frame import (
    DISPLACEMENTS,
    REACTIONS,
    FESettings,
    FrameBuilder,
    compliance_at_node,
    fe_cantilever_compliance,
    node_vector,
    require_pynite,
    unit_scales,
    unit_vector,
)

__all__ = [
    "FEResult",
    "FESettings",
    "build_model",
    "fe_cantilever_compliance",
    "fe_leg_stiffness",
    "fe_stiffness_at_pose",
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
        ``max|C - C^T|`` relative to ``max|C|`` after balancing rotations and
        translations over 0.1 m (Maxwell-Betti reciprocity check of the solution).
    n_nodes, n_members, n_springs : int
        Size of the PyNite model.
    """

    stiffness: FloatArray
    compliance: FloatArray
    asymmetry: float
    n_nodes: int
    n_members: int
    n_springs: int


def _away_from(axis: FloatArray, other: FloatArray) -> FloatArray:
    """``axis`` or ``-axis``, whichever does not point towards ``other``."""
    return axis if float(axis @ other) <= 0.0 else -axis


def _leg_points(design: Design, pose: FloatArray) -> list[dict[str, FloatArray]]:
    """B, C, D, u, w of every leg relative to P (F_b axes); raises if unreachable."""
    out = []
    for leg, lp in zip(design.legs, solve_legs(design, pose), strict=True):
        u, w = leg.directions()
        pts = lp.points
        out.append({"b": pts["B"], "c": pts["C"], "d": pts["D"],
                    "u": unit_vector(u), "w": unit_vector(w)})
    return out


def _add_leg(
    fb: FrameBuilder, leg: Any, pts: dict[str, FloatArray], k_act: float,
    platform_node: str | None, tag: str,
) -> str:
    """Add one leg; returns the name of its node D (rod tip)."""
    s = fb.s
    b, c, d, u, w = pts["b"], pts["c"], pts["d"], pts["u"], pts["w"]
    z = Z_AXIS
    if np.linalg.norm(c - b) < 10 * s or np.linalg.norm(d - c) <= 0.0:
        raise DesignError(f"FE model, {tag}: proximal link or rod too short for the model")
    # guide + actuator at B, grounded springs on the side away from the proximal link
    nb = fb.node(b, f"B{tag}_")
    u_out = _away_from(u, c - b)
    y_out = _away_from(unit_vector(np.cross(z, u)), c - b)
    g = leg.guide
    fb.grounded_rotation(nb, b, u_out, g.roll, s)
    fb.grounded_rotation(nb, b, y_out, g.pitch, s)
    fb.grounded_rotation(nb, b, -z, g.yaw, s)
    fb.grounded_translation(nb, b, u_out, k_act, 2 * s)
    fb.grounded_translation(nb, b, y_out, g.lateral, 2 * s)
    fb.grounded_translation(nb, b, -z, g.vertical, 2 * s)
    # proximal link B -C, built from C (see link_rotation on why members start at C)
    ncp = fb.node(c, f"Cp{tag}_")
    fb.beam(ncp, nb, leg.proximal)
    # bearing at C: Cp -> Cr, axes (w, y_D, z); nothing along/about w (cylindrical)
    ncr = fb.node(c, f"Cr{tag}_")
    lat = _away_from(unit_vector(np.cross(z, w)), b - c)
    br = leg.bearing
    fb.link_rotation(ncp, ncr, c, lat, br.tilt_lateral, s, (w, z))
    fb.link_rotation(ncp, ncr, c, z, br.tilt_vertical, s, (w, -lat))
    fb.link_translation(ncp, ncr, c, lat, br.radial_lateral, 2 * s, (w, z))
    fb.link_translation(ncp, ncr, c, z, br.radial_vertical, 2 * s, (w, -lat))
    # rod C -> D
    nd = fb.node(d, f"D{tag}_")
    fb.beam(ncr, nd, leg.distal)
    if platform_node is not None:
        _platform_member(fb, platform_node, nd, float(np.linalg.norm(d)))
    return nd


def _platform_member(fb: FrameBuilder, p_node: str, d_node: str, length: float) -> None:
    """Stiff member P -> D, moment about z released at D (the passive revolute)."""
    k = fb.settings.rigid_stiffness * fb.unit  # N/m -> N/unit
    ell = length / fb.unit
    name = fb._name("rigid")
    fb.model.add_section(name, k * ell, k * ell**3 / 3, k * ell**3 / 3, k * ell**3)
    fb.member(p_node, d_node, "unit", name, Rzj=True)


def _actuator_stiffness(design: Design, actuator_stiffness: ArrayLike | None) -> FloatArray:
    n = len(design.legs)
    if actuator_stiffness is None:
        return locked_actuator_stiffness(design)
    k = np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), (n,))
    if not np.all(np.isfinite(k)) or np.any(k <= 0):
        raise DesignError("actuator stiffness must be finite and > 0 N/m")
    return np.asarray(k, dtype=float)


def build_model(
    design: Design, pose: ArrayLike, actuator_stiffness: ArrayLike | None = None,
    settings: FESettings | None = None, legs: tuple[int, ...] | None = None,
) -> tuple[FrameBuilder, str]:
    """The FE model of the manipulator (or of some legs) at ``pose``.

    Parameters
    ----------
    design : Design
    pose : array_like, shape (3,)
        (x [m], y [m], phi [rad]); the model is built with its origin at P.
    actuator_stiffness : array_like, optional
        Per-leg actuator stiffness [N/m]; the locked value when None.
    settings : FESettings, optional
    legs : tuple of int, optional
        Indices (from 0) of the legs to include; all when None.

    Returns
    -------
    (FrameBuilder, str)
        The builder (its ``model`` is the PyNite model) and the name of node P.
    """
    st = settings or FESettings()
    p = np.asarray(pose, dtype=float)
    k_act = _actuator_stiffness(design, actuator_stiffness)
    fb = FrameBuilder(st)
    p_node = fb.node(np.zeros(3), "P")
    points = _leg_points(design, p)
    chosen = range(len(design.legs)) if legs is None else legs
    for i in chosen:
        _add_leg(fb, design.legs[i], points[i], float(k_act[i]), p_node, f"{i + 1}")
    return fb, p_node


def _balanced_asymmetry(c: FloatArray) -> float:
    cb = length_balanced_compliance(c)
    return float(np.max(np.abs(cb - cb.T)) / np.max(np.abs(cb)))


def fe_stiffness_at_pose(
    design: Design, pose: ArrayLike, actuator_stiffness: ArrayLike | None = None,
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
        stiffness=0.5 * (k + k.T), compliance=c, asymmetry=_balanced_asymmetry(c),
        n_nodes=len(m.nodes), n_members=len(m.members), n_springs=len(m.springs),
    )


def fe_leg_stiffness(
    design: Design, leg: int, pose: ArrayLike, actuator_stiffness: ArrayLike | None = None,
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
        model.analyze_linear(check_stability=fb.settings.check_stability)
        combo = next(iter(model.load_combos))
        cols.append(node_vector(model.nodes[p_node], REACTIONS, combo))
    fb.check_topology()
    t, w = unit_scales(fb.unit)
    k = w[:, None] * np.stack(cols, axis=1) / t[None, :]
    return np.asarray(0.5 * (k + k.T))
