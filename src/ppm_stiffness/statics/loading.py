"""The loaded manipulator: actuator forces, actuator stiffness and K under a wrench.

An external wrench ``w = (m_x, m_y, m_z, f_x, f_y, f_z)`` [N·m, N] applied at P (axes
of F_b) is shared by the legs in proportion to their stiffness:
``w_i = K_i K^{-1} w`` (so that ``sum_i w_i = w``, equilibrium). All springs of a leg
are in series, so each carries the projection of ``w_i`` on its screw; the actuator
carries ``G_i = u_i . f_i`` [N]. For the 3-PPR each leg transmits a single in-plane
force, so the in-plane split is statically determinate and these forces do not
depend on the stiffness values used for the split.

Sign: ``G_i = u_i . f_i``, the component along ``u_i`` of the force carried by leg i;
the actuator law is odd, so only ``|G_i|`` sets its stiffness.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.design import Design
from ppm_stiffness.model import (
    actuator_screws_at_pose,
    leg_stiffnesses_at_pose,
    stiffness_at_pose,
    workspace_centre,
)
from ppm_stiffness.statics import actuator as act


def validate_wrench(wrench: ArrayLike) -> FloatArray:
    """A wrench as a finite (6,) array (m_x, m_y, m_z, f_x, f_y, f_z), or raise."""
    w = np.asarray(wrench, dtype=float)
    if w.shape != (6,):
        raise InputDataError(
            f"a wrench has 6 components (m_x, m_y, m_z, f_x, f_y, f_z), got shape {w.shape}"
        )
    if not np.all(np.isfinite(w)):
        raise InputDataError("wrench components must be finite")
    return w


def check_actuator_travel(design: Design, displacements: ArrayLike) -> None:
    """Refuse loads under which an actuator would travel beyond its stroke.

    The model is one of small displacements about a fixed geometry; an actuator
    displaced by more than its whole stroke (``stroke[1] - stroke[0]`` of its leg) is
    far outside it, and its stiffness from eq. (21) is meaningless.

    Parameters
    ----------
    displacements : array_like, shape (..., n_legs)
        Actuator displacement magnitudes [m].
    """
    d = np.abs(np.asarray(displacements, dtype=float)).reshape(-1, len(design.legs))
    spans = np.array([leg.stroke[1] - leg.stroke[0] for leg in design.legs])
    worst = np.where(np.isfinite(d), d, 0.0).max(axis=0)
    for i in np.flatnonzero(~(worst <= spans)):
        raise InputDataError(
            f"load too large: actuator {i + 1} would move {worst[i] * 1e3:.4g} mm, more than "
            f"its whole stroke of {spans[i] * 1e3:.4g} mm (the model is for small deflections)"
        )


#: Largest platform rotation [rad] a deflection may reach: the model linearises the
#: geometry about the unloaded pose (small displacements).
MAX_ROTATION = 0.1


def check_small_rotation(twists: ArrayLike) -> None:
    """Refuse deflections whose rotation exceeds :data:`MAX_ROTATION` (5.7 deg).

    Parameters
    ----------
    twists : array_like, shape (..., 6)
        Platform twists (rotation first) [rad, m].
    """
    t = np.asarray(twists, dtype=float).reshape(-1, 6)
    rotation = float(np.max(np.linalg.norm(t[:, :3], axis=1))) if len(t) else 0.0
    if not rotation <= MAX_ROTATION:
        raise InputDataError(
            f"load too large: the platform would rotate {np.degrees(rotation):.3g} deg, "
            f"beyond the {np.degrees(MAX_ROTATION):.2g} deg a small-displacement model covers"
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
    """Axial force [N] in each actuator for an external wrench at a pose.

    ``actuator_stiffness`` only matters for statically indeterminate designs.
    """
    w = validate_wrench(wrench)
    p = workspace_centre(design) if pose is None else np.asarray(pose, dtype=float)
    legs = leg_stiffnesses_at_pose(design, p, actuator_stiffness)
    shares = leg_wrenches(legs, w)
    screws = actuator_screws_at_pose(design, p)
    return np.einsum("ij,ij->i", shares, screws)


@dataclass(frozen=True)
class LoadedState:
    """The manipulator under a wrench (SI).

    Attributes
    ----------
    pose : ndarray (3,)
    wrench : ndarray (6,)
    actuator_forces : ndarray (n_legs,) [N]
    actuator_displacements : ndarray (n_legs,) [m]
        Magnitudes from the bare law, eq. (20): the delta that sets the stiffness in
        eq. (21). The deflection module's actuator displacement, the integral of
        1/K_act along the force path, exceeds it by G_th/K_locked - delta_th (20.9 um
        for the paper's law) above the threshold (docs/actuation.md).
    actuator_stiffness : ndarray (n_legs,) [N/m], eq. (21)
    stiffness_matrix : ndarray (6, 6)
    """

    pose: FloatArray
    wrench: FloatArray
    actuator_forces: FloatArray
    actuator_displacements: FloatArray
    actuator_stiffness: FloatArray
    stiffness_matrix: FloatArray


def loaded_state(design: Design, wrench: ArrayLike, pose: ArrayLike | None = None) -> LoadedState:
    """Actuator forces, displacements, stiffnesses and K under ``wrench`` at ``pose``.

    The forces come from the statics of the unloaded (locked) manipulator; the
    structure is linear and the 3-PPR's in-plane split is determinate, so no
    iteration is needed. Geometry changes under load are neglected (small
    displacements), as in the paper.
    """
    w = validate_wrench(wrench)
    p = workspace_centre(design) if pose is None else np.asarray(pose, dtype=float)
    forces = actuator_forces(design, w, p)
    delta = act.displacement_from_force(design.actuator, forces)
    check_actuator_travel(design, delta)
    k_act = act.stiffness_from_displacement(design.actuator, delta)
    k = stiffness_at_pose(design, p, k_act)
    return LoadedState(p, w, forces, delta, k_act, k)
