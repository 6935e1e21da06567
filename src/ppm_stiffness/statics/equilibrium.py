"""Equilibrium of the loaded manipulator with nonlinear actuator springs, any number of legs.

Model (small displacements about a fixed geometry, as in the paper). In leg i every
spring is in series; the actuator is one of them, with the nonlinear law
``delta_i(G_i)`` (:func:`ppm_stiffness.statics.actuator.actuator_displacement`, the
integral of the tangent compliance of eq. 21). Write the leg's compliance at P without
its actuator as ``S_i``, its passive-joint twists ``J_i`` and its actuator's unit twist
``a_i``; ``K_i^S`` (the bordered inverse of ``S_i``, eq. 1) is the leg's stiffness with
a rigid actuator. Under the platform twist t the leg carries

    w_i = K_i^S (t - a_i delta_i(G_i)),     G_i = a_i . w_i,

and equilibrium is ``sum_i w_i = w``. Eliminating t,

    t = C^S (w + sum_j b_j delta_j(G_j)),   b_j = K_j^S a_j,  C^S = (sum_j K_j^S)^-1,

leaves n equations in the n actuator forces,

    F(G) = G - g0 + M delta(G) = 0,   g0 = B^T C^S w,   M = diag(a_i . b_i) - B^T C^S B,

solved by Newton's method with a backtracking line search (Jacobian
``I + M diag(1 / K_act(G))``). For a design whose actuator forces are statically
determinate (a 3-leg planar design) ``M = 0`` and ``G = g0`` whatever the law: the
secant stiffness ``G/delta(G)`` only shares the load between legs when there is more
than one way to share it (redundant designs).

At the solution the module reports the forces, the displacements ``delta(G)``, the
tangent stiffness ``K_act(G)`` (eq. 21), the secant stiffness ``G/delta(G)``, the
platform twist t and the tangent Cartesian stiffness
``sum_i bordered(S_i + a_i a_i^T / K_act,i, J_i)`` (the matrix the paper reports under
load, eq. 33). Poses are (x, y, phi) [m, m, rad]; twists and wrenches at P, axes of F_b.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, length_balanced
from ppm_stiffness.core.errors import (
    EquilibriumError,
    InputDataError,
    SingularConfigurationError,
)
from ppm_stiffness.core.singularity import leg_projector, nonsingular, transmission_index
from ppm_stiffness.core.solver import bordered_stiffness, leg_compliance_at_platform
from ppm_stiffness.design import Design
from ppm_stiffness.legs.base import LegModel
from ppm_stiffness.model import (
    actuator_stiffness_vector,
    check_transmission,
    leg_springs_at_pose,
    pose_label,
)
from ppm_stiffness.statics import actuator as act

#: Newton stops when every |F_i| is below this fraction of the force scale
#: max(|g0|, 1 N) (or 1 N·m), and fails after ``MAX_ITERATIONS``.
FORCE_TOLERANCE = 1e-12
MAX_ITERATIONS = 100


def check_actuator_travel(design: Design, displacements: ArrayLike) -> None:
    """Refuse loads under which an actuator would travel beyond its stroke.

    The model is one of small displacements about a fixed geometry; an actuator
    displaced by more than its whole stroke (the span of its leg's actuated coordinate) is
    far outside it, and its stiffness from eq. (21) is meaningless.

    Parameters
    ----------
    displacements : array_like, shape (..., n_legs)
        Actuator displacement magnitudes [m, or rad for a rotary actuator].
    """
    d = np.abs(np.asarray(displacements, dtype=float)).reshape(-1, len(design.legs))
    spans = np.array([_stroke_span(leg) for leg in design.legs])
    worst = np.where(np.isfinite(d), d, 0.0).max(axis=0)
    for i in np.flatnonzero(~(worst <= spans)):
        leg = design.legs[i]
        rotary = leg.COORDINATES[leg.ACTUATED_COORDINATE].unit == "rad"
        scale, unit = (180 / np.pi, "deg") if rotary else (1e3, "mm")
        raise InputDataError(
            f"load too large: actuator {i + 1} would move {worst[i] * scale:.4g} {unit}, "
            f"more than its whole stroke of {spans[i] * scale:.4g} {unit} (the model is "
            "for small deflections)"
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


def _stroke_span(leg: LegModel) -> float:
    """The whole travel of a leg's actuated coordinate (its limits' span) [m or rad]."""
    lo, hi = leg.limits()[leg.ACTUATED_COORDINATE]
    return float(hi - lo)


class LegStructures:
    """The linear parts of every leg at one pose (springs built once).

    Attributes
    ----------
    structure : ndarray (n, 6, 6)
        ``S_i``: the leg's compliance at P without its actuator.
    passive : ndarray (n, 6, p)
        Passive-joint twists (legs must have the same number p; otherwise stored as a
        list).
    actuator : ndarray (n, 6)
        ``a_i``, the actuated joint's unit twist.
    rigid_actuator_stiffness : ndarray (n, 6, 6)
        ``K_i^S``.
    """

    def __init__(self, design: Design, pose: ArrayLike) -> None:
        self.design = design
        self.pose = np.asarray(pose, dtype=float)
        k0 = actuator_stiffness_vector(design, None)
        legs = leg_springs_at_pose(design, self.pose, k0)
        self.passive = [leg.passive for leg in legs]
        self.actuator = np.stack([leg.screws[:, leg.actuator_index] for leg in legs])
        c6 = np.stack([leg_compliance_at_platform(leg.screws, leg.compliance) for leg in legs])
        outer = np.einsum("li,lj->lij", self.actuator, self.actuator)
        self.structure = c6 - outer / k0[:, None, None]
        self.rigid_actuator_stiffness = np.stack(
            [bordered_stiffness(s, q) for s, q in zip(self.structure, self.passive, strict=True)]
        )

    @property
    def n_legs(self) -> int:
        return int(self.actuator.shape[0])

    def leg_stiffnesses(self, actuator_stiffness: ArrayLike) -> FloatArray:
        """Each leg's tangent stiffness (n, 6, 6) with the given actuator stiffnesses."""
        k = np.asarray(actuator_stiffness, dtype=float)
        outer = np.einsum("li,lj->lij", self.actuator, self.actuator)
        c6 = self.structure + outer / k[:, None, None]
        return np.stack([bordered_stiffness(c, q) for c, q in zip(c6, self.passive, strict=True)])

    def stiffness(self, actuator_stiffness: ArrayLike) -> FloatArray:
        """Cartesian stiffness (6, 6) at P with the given actuator stiffnesses."""
        return np.asarray(self.leg_stiffnesses(actuator_stiffness).sum(axis=0))

    def reduced(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``B`` (6, n), ``C^S`` (6, 6) and ``M`` (n, n) of the module doc."""
        k_s = self.rigid_actuator_stiffness
        total = k_s.sum(axis=0)
        if not np.all(np.isfinite(total)):
            raise SingularConfigurationError(
                f"a leg is rigid with its actuator locked{pose_label(self.pose)}"
            )
        pi = np.sum([leg_projector(q) for q in self.passive], axis=0)
        check_transmission(
            bool(nonsingular(transmission_index(pi))), total, pi, pose_label(self.pose)
        )
        b = np.einsum("lij,lj->il", k_s, self.actuator)
        c_s = np.linalg.inv(total)
        c_s = 0.5 * (c_s + c_s.T)
        m = np.diag(np.einsum("li,il->l", self.actuator, b)) - b.T @ c_s @ b
        return b, c_s, 0.5 * (m + m.T)


def displacements(design: Design, forces: ArrayLike) -> FloatArray:
    """``delta_i(G_i)`` of every leg's law (..., n) [m or rad]."""
    g = np.asarray(forces, dtype=float)
    return np.stack(
        [act.actuator_displacement(leg.actuator, g[..., i]) for i, leg in enumerate(design.legs)],
        axis=-1,
    )


def tangent_stiffnesses(design: Design, forces: ArrayLike) -> FloatArray:
    """Tangent actuator stiffness (eq. 21) of every leg (..., n) [N/m or N·m/rad]."""
    g = np.asarray(forces, dtype=float)
    return np.stack(
        [act.stiffness_from_force(leg.actuator, g[..., i]) for i, leg in enumerate(design.legs)],
        axis=-1,
    )


@dataclass(frozen=True)
class Equilibrium:
    """The equilibrium under a wrench (SI; twists and wrenches at P, axes of F_b).

    Attributes
    ----------
    pose : ndarray (3,)
    wrench : ndarray (6,)
    actuator_forces : ndarray (n,) [N or N·m]
        Signed, ``G_i = a_i . w_i``.
    actuator_displacements : ndarray (n,) [m or rad]
        ``delta_i(G_i)`` (integral of 1/K_act).
    actuator_stiffness : ndarray (n,)
        Tangent stiffness (eq. 21) at G_i.
    secant_stiffness : ndarray (n,)
        ``G_i / delta_i(G_i)`` (the locked stiffness where G_i = 0).
    twist : ndarray (6,) [rad, m]
        Platform deflection.
    leg_wrenches : ndarray (n, 6)
        Wrench carried by each leg (they sum to ``wrench``).
    stiffness_matrix : ndarray (6, 6)
        Tangent Cartesian stiffness at the loaded state.
    iterations : int
        Newton iterations used (0 when the forces are statically determinate).
    """

    pose: FloatArray
    wrench: FloatArray
    actuator_forces: FloatArray
    actuator_displacements: FloatArray
    actuator_stiffness: FloatArray
    secant_stiffness: FloatArray
    twist: FloatArray
    leg_wrenches: FloatArray
    stiffness_matrix: FloatArray
    iterations: int


def solve_forces(
    design: Design, structures: LegStructures, wrench: ArrayLike
) -> tuple[FloatArray, int]:
    """Actuator forces (n,) at equilibrium under ``wrench`` and the Newton iterations.

    Raises
    ------
    EquilibriumError
        If Newton's method does not converge.
    """
    w = np.asarray(wrench, dtype=float)
    b, c_s, m = structures.reduced()
    g0 = b.T @ c_s @ w
    scale = max(float(np.max(np.abs(g0))), 1.0)
    # M is a difference of terms of the size of a_i . K_i^S a_i (the leg's stiffness
    # along its actuator): relative to that, M vanishes for determinate forces
    leg_scale = float(np.max(np.abs(np.einsum("li,il->l", structures.actuator, b))))
    if float(np.max(np.abs(m))) <= 1e-9 * max(leg_scale, 1e-300):
        return g0, 0  # statically determinate actuator forces

    def residual(g: FloatArray) -> FloatArray:
        return np.asarray(g - g0 + m @ displacements(design, g))

    g = g0.copy()
    f = residual(g)
    for iteration in range(1, MAX_ITERATIONS + 1):
        if np.max(np.abs(f)) <= FORCE_TOLERANCE * scale:
            return g, iteration - 1
        jac = np.eye(len(g)) + m / tangent_stiffnesses(design, g)[None, :]
        step = np.linalg.solve(jac, -f)
        norm0 = float(np.linalg.norm(f))
        alpha = 1.0
        while True:
            trial = g + alpha * step
            f_trial = residual(trial)
            if float(np.linalg.norm(f_trial)) < (1 - 1e-4 * alpha) * norm0 or alpha < 1e-6:
                break
            alpha *= 0.5
        g, f = trial, f_trial
    raise EquilibriumError(
        f"no equilibrium found after {MAX_ITERATIONS} Newton iterations"
        f"{pose_label(structures.pose)} (largest force residual "
        f"{float(np.max(np.abs(f))):.3g})"
    )


def equilibrium(
    design: Design,
    wrench: ArrayLike,
    pose: ArrayLike,
    structures: LegStructures | None = None,
) -> Equilibrium:
    """The loaded state under ``wrench`` (m_x, m_y, m_z, f_x, f_y, f_z at P, F_b).

    Parameters
    ----------
    design : Design
    wrench : array_like (6,) [N·m, N]
    pose : array_like (3,) [m, m, rad]
    structures : LegStructures, optional
        Reuse the springs of an earlier call at the same pose.

    Returns
    -------
    Equilibrium

    Raises
    ------
    UnreachablePoseError, SingularConfigurationError, EquilibriumError
    """
    w = np.asarray(wrench, dtype=float)
    st = LegStructures(design, pose) if structures is None else structures
    g, iterations = solve_forces(design, st, w)
    delta = displacements(design, g)
    k_tan = tangent_stiffnesses(design, g)
    locked = np.array([leg.actuator.locked_stiffness for leg in design.legs])
    with np.errstate(divide="ignore", invalid="ignore"):
        secant = np.where(delta != 0, g / np.where(delta != 0, delta, 1.0), locked)
    check_actuator_travel(design, delta)
    b, c_s, _ = st.reduced()
    twist = c_s @ (w + b @ delta)
    check_small_rotation(twist)
    leg_w = np.einsum(
        "lij,lj->li", st.rigid_actuator_stiffness, twist[None, :] - st.actuator * delta[:, None]
    )
    k = st.stiffness(k_tan)
    # Soft powered actuators can make the loaded K ill-conditioned without any
    # kinematic singularity (that was checked with the actuators locked): only a K
    # that is not finite and positive definite is refused here.
    if not np.all(np.isfinite(k)) or np.linalg.eigvalsh(length_balanced(k))[0] <= 0:
        raise SingularConfigurationError(
            f"the loaded stiffness matrix is not positive definite{pose_label(st.pose)}"
        )
    return Equilibrium(
        pose=st.pose,
        wrench=w,
        actuator_forces=g,
        actuator_displacements=delta,
        actuator_stiffness=k_tan,
        secant_stiffness=secant,
        twist=twist,
        leg_wrenches=leg_w,
        stiffness_matrix=k,
        iterations=iterations,
    )
