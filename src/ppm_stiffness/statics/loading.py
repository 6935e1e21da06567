"""The loaded manipulator: actuator forces, actuator stiffness and K under a wrench.

An external wrench ``w = (m_x, m_y, m_z, f_x, f_y, f_z)`` [N·m, N] applied at P (axes
of F_b). :func:`loaded_state` solves the equilibrium with the nonlinear actuator law
(:mod:`ppm_stiffness.statics.equilibrium`). :func:`actuator_forces` is the *linear*
split at given actuator stiffnesses, ``w_i = K_i K^{-1} w``: exact for a 3-leg planar
design (its actuator forces are statically determinate, independent of the
stiffnesses), an approximation for a redundant one.

Sign: ``G_i = a_i . w_i`` with ``a_i`` the actuated joint's unit twist
(for a linear actuator along u_i, ``G_i = u_i . f_i``); the actuator law is odd, so
only ``|G_i|`` sets its stiffness. Where a flexure of stiffness ``k_h`` acts in
parallel with the drive (its actuated joint is elastic) G_i is the drive's share,
``a_i . w_i k_act / (k_act + k_h)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.inputs import validate_wrench
from ppm_stiffness.design import Design
from ppm_stiffness.model import (
    actuator_screws_at_pose,
    actuator_stiffness_vector,
    leg_stiffnesses_at_pose,
    parallel_stiffnesses,
    validate_pose,
)
from ppm_stiffness.statics.equilibrium import (
    MAX_ROTATION,
    LoadedState,
    check_actuator_travel,
    check_small_rotation,
    equilibrium,
)


def leg_wrenches(leg_stiffnesses: list[FloatArray], wrench: ArrayLike) -> FloatArray:
    """Share of ``wrench`` carried by each leg, shape (n_legs, 6): ``K_i K^{-1} w``."""
    total = np.sum(leg_stiffnesses, axis=0)
    twist = np.linalg.solve(total, np.asarray(wrench, dtype=float))
    return np.array([k @ twist for k in leg_stiffnesses])


def actuator_forces(
    design: Design,
    wrench: ArrayLike,
    pose: ArrayLike | None = None,
    actuator_stiffness: ArrayLike | None = None,
) -> FloatArray:
    """Actuator forces [N or N·m] by the linear split at given actuator stiffnesses.

    Exact for statically determinate designs, whatever ``actuator_stiffness``; for a
    redundant design it is the split of a linear model with those stiffnesses (the
    locked ones by default), *not* the loaded equilibrium: use :func:`loaded_state`.
    """
    w = validate_wrench(wrench)
    p = validate_pose(design, pose)
    legs = leg_stiffnesses_at_pose(design, p, actuator_stiffness)
    shares = leg_wrenches(legs, w)
    screws = actuator_screws_at_pose(design, p)
    joint = np.einsum("ij,ij->i", shares, screws)  # the actuated joints' forces
    k_h = parallel_stiffnesses(design)
    if not np.any(k_h):
        return joint
    k_act = actuator_stiffness_vector(design, actuator_stiffness)
    with np.errstate(invalid="ignore"):  # a passive leg's inf: no flexure, share 1
        return np.asarray(joint * np.where(k_h > 0, k_act / (k_act + k_h), 1.0))


def loaded_state(design: Design, wrench: ArrayLike, pose: ArrayLike | None = None) -> LoadedState:
    """Actuator forces, displacements, stiffnesses and K under ``wrench`` at ``pose``.

    The equilibrium of the nonlinear actuator springs is solved exactly
    (:func:`ppm_stiffness.statics.equilibrium.equilibrium`, any design, planar or
    spatial): where the actuator forces are statically determinate (``M = 0`` in
    :mod:`ppm_stiffness.statics.equilibrium`, e.g. a 3-leg planar design) they do not
    depend on the actuator law; for a redundant design the secant actuator stiffnesses
    share the load. Geometry changes under load are neglected (small displacements,
    the geometry of the unloaded pose), as in the paper:
    :func:`ppm_stiffness.statics.moving.moving_loaded_state` lets the geometry move.

    Parameters
    ----------
    design : Design
    wrench : array_like (6,)
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] applied at P (the platform point, not a
        tool point), components in the axes of F_b.
    pose : array_like (n_task,) or (6,), optional
        The unloaded pose: the design's task coordinates (``design.task_coordinates``;
        (x [m], y [m], phi [rad]) for a planar design) or a full pose (x, y, z [m], rx,
        ry, rz [rad]) of P in F_b; the home pose if None.

    Returns
    -------
    LoadedState
        At P, axes of F_b: the full pose (6,), the wrench, the actuator forces G_i
        [N or N·m], displacements delta(G_i) [m or rad], tangent (eq. 21) and secant
        actuator stiffnesses, the platform twist (phi_x, phi_y, phi_z, x, y, z) [rad,
        m], each leg's wrench (n_legs, 6) and the tangent Cartesian stiffness (6, 6)
        [N·m/rad, N, N/m] of the loaded state.

    Raises
    ------
    InputDataError
        If an actuator would travel beyond its whole stroke or the platform would turn
        by more than :data:`~ppm_stiffness.statics.equilibrium.MAX_ROTATION`.
    UnreachablePoseError, SingularConfigurationError, EquilibriumError
    """
    w = validate_wrench(wrench)
    p = validate_pose(design, pose)
    return equilibrium(design, w, p)


__all__ = [
    "MAX_ROTATION",
    "LoadedState",
    "actuator_forces",
    "check_actuator_travel",
    "check_small_rotation",
    "leg_wrenches",
    "loaded_state",
    "validate_wrench",
]
