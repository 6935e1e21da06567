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

A drive in parallel with a flexure (its actuated joint's elastic stiffness ``k_h``,
a piezo stack on the lever of a notch hinge; the flexure rests at the unloaded pose):
the joint carries ``a_i . w_i = G_i + k_h,i delta_i(G_i)``, G_i the drive's force, so
the same equations hold in the drives' forces with ``M + diag(k_h)`` in place of M
(never determinate: the flexure shares each joint's load with its drive); the
tangent stiffness of the actuated freedom is ``K_act(G) + k_h``, which the legs' terms
add (:func:`ppm_stiffness.legs.chain.parallel_stiffness`).

At the solution the module reports the forces, the displacements ``delta(G)``, the
tangent stiffness ``K_act(G)`` (eq. 21), the secant stiffness ``G/delta(G)``, the
platform twist t and the tangent Cartesian stiffness
``sum_i bordered(S_i + a_i a_i^T / K_act,i, J_i)`` (the matrix the paper reports under
load, eq. 33). Poses are full poses (x, y, z, rx, ry, rz) [m, rad] (given as the
design's task coordinates or in full, :mod:`ppm_stiffness.poses`; (x, y, phi) for a
planar design); twists and wrenches at P, axes of F_b.

One implementation for one pose and for many: :func:`loaded_states` solves these
equations at k poses at once (the legs' linear parts from
:mod:`ppm_stiffness.statics.structures`; Newton's method on every pose together) and
gives each pose a refusal code (:class:`ppm_stiffness.core.refusals.Refusal`), in this
order: unreachable, singular with the actuators rigid (the transmission index of
:mod:`ppm_stiffness.core.singularity`, or ``K^S`` not finite), no equilibrium, an
actuator beyond its whole stroke, a platform rotation beyond :data:`MAX_ROTATION`, a
loaded K that is not positive definite. :func:`equilibrium` is the batch of one pose
that raises the code's error; the maps and :func:`ppm_stiffness.maps.loaded.loaded_poses`
mask the poses with a nonzero code. So the maps mask exactly where the single-pose
API raises, by construction.

Newton's method stops when every |F_i| is at most :data:`FORCE_TOLERANCE` times the
size of the terms F is computed from: ``max(|g0|, |G|, |M| (|delta| + |G| / K_act),
1 N)`` (N·m for a rotary actuator). Round-off in F is a few ulps of that size: where
the actuators are driven far (``|M| delta`` of 10^5 N and more) a scale of ``|g0|``
alone asked for less than round-off allows, and whether Newton "converged" depended on
the order of the floating-point sums.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
from ppm_stiffness.core.errors import (
    EquilibriumError,
    SingularConfigurationError,
    UnreachablePoseError,
)
from ppm_stiffness.core.inputs import validate_wrench
from ppm_stiffness.core.refusals import Refusal, RefusalArray, first_refusal
from ppm_stiffness.design import Design
from ppm_stiffness.model import (
    locked_actuator_stiffness,
    parallel_stiffnesses,
    pose_label,
    singular_message,
    solve_legs,
    validate_pose,
)
from ppm_stiffness.poses import full_poses
from ppm_stiffness.statics import actuator as act
from ppm_stiffness.statics.limits import (
    MAX_ROTATION,
    check_actuator_travel,
    check_small_rotation,
    positive_definite,
    small_rotation,
    within_stroke,
)
from ppm_stiffness.statics.structures import LegStructures, LegTerms, reachable_terms

__all__ = [
    "FORCE_TOLERANCE",
    "MAX_ITERATIONS",
    "MAX_ROTATION",
    "Equilibrium",
    "EquilibriumBatch",
    "LegStructures",
    "check_actuator_travel",
    "check_small_rotation",
    "displacements",
    "equilibrium",
    "loaded_states",
    "positive_definite",
    "raise_refusal",
    "small_rotation",
    "solve_forces",
    "solve_loaded",
    "tangent_stiffnesses",
    "within_stroke",
]

#: Newton stops when every |F_i| is below this fraction of the size of F's terms
#: (module doc), and fails after ``MAX_ITERATIONS``.
FORCE_TOLERANCE = 1e-12
MAX_ITERATIONS = 100


def displacements(design: Design, forces: ArrayLike) -> FloatArray:
    """``delta_i(G_i)`` of every leg's law (..., n) [m or rad]."""
    g = np.asarray(forces, dtype=float)
    return np.stack(
        [act.leg_displacement(leg, g[..., i]) for i, leg in enumerate(design.legs)],
        axis=-1,
    )


def tangent_stiffnesses(design: Design, forces: ArrayLike) -> FloatArray:
    """Tangent actuator stiffness (eq. 21) of every leg (..., n) [N/m or N·m/rad]."""
    g = np.asarray(forces, dtype=float)
    return np.stack(
        [act.leg_tangent_stiffness(leg, g[..., i]) for i, leg in enumerate(design.legs)],
        axis=-1,
    )


def solve_forces(
    design: Design, g0: FloatArray, m: FloatArray, leg_scale: FloatArray
) -> tuple[FloatArray, BoolArray, np.ndarray, FloatArray]:
    """Actuator forces (k, n) at equilibrium, ``G - g0 + M delta(G) = 0``, for k poses.

    Newton's method with a backtracking line search (module doc), all poses at once.
    Where ``max|M| <= 1e-9 max(a_i . b_i)`` (``leg_scale``) the forces are statically
    determinate: ``G = g0``, 0 iterations.

    Parameters
    ----------
    g0 : ndarray (k, n) [N or N·m]
    m : ndarray (k, n, n) [N/m or N·m/rad]
    leg_scale : ndarray (k,)
        ``max_i a_i . b_i``, the legs' stiffness along their actuators.

    Returns
    -------
    forces : ndarray (k, n)
        The last iterate where Newton's method did not converge.
    converged : ndarray of bool (k,)
    iterations : ndarray of int (k,)
        -1 where it did not converge.
    residual : ndarray (k,)
        Largest |F_i| at the returned forces.
    """
    k, n = g0.shape
    g = g0.copy()
    iterations = np.zeros(k, dtype=int)
    residual = np.zeros(k)
    determinate = np.max(np.abs(m), axis=(1, 2), initial=0.0) <= 1e-9 * np.maximum(
        leg_scale, 1e-300
    )
    converged = determinate.copy()
    active = np.flatnonzero(~determinate)
    if active.size == 0:
        return g, converged, iterations, residual
    base = np.maximum(np.max(np.abs(g0), axis=1), 1.0)

    def residual_of(gs: FloatArray, rows: np.ndarray) -> FloatArray:
        return np.asarray(
            gs - g0[rows] + np.einsum("kij,kj->ki", m[rows], displacements(design, gs))
        )

    ga = g[active]
    f = residual_of(ga, active)
    eye = np.eye(n)
    for iteration in range(1, MAX_ITERATIONS + 1):
        k_tan = tangent_stiffnesses(design, ga)
        terms = np.abs(displacements(design, ga)) + np.abs(ga) / k_tan
        scale = np.maximum(
            np.maximum(base[active], np.max(np.abs(ga), axis=1)),
            np.max(np.einsum("kij,kj->ki", np.abs(m[active]), terms), axis=1),
        )
        done = np.max(np.abs(f), axis=1) <= FORCE_TOLERANCE * scale
        if np.any(done):
            rows = active[done]
            g[rows] = ga[done]
            converged[rows] = True
            iterations[rows] = iteration - 1
            residual[rows] = np.max(np.abs(f[done]), axis=1)
            keep = ~done
            active, ga, f, k_tan = active[keep], ga[keep], f[keep], k_tan[keep]
        if active.size == 0:
            break
        jac = eye + m[active] / k_tan[:, None, :]
        step = np.linalg.solve(jac, -f[..., None])[..., 0]
        norm0 = np.linalg.norm(f, axis=1)
        alpha = np.ones(active.size)
        trial = ga + step
        f_trial = residual_of(trial, active)
        while True:
            ok = (np.linalg.norm(f_trial, axis=1) < (1 - 1e-4 * alpha) * norm0) | (alpha < 1e-6)
            if np.all(ok):
                break
            redo = np.flatnonzero(~ok)
            alpha[redo] *= 0.5
            trial[redo] = ga[redo] + alpha[redo, None] * step[redo]
            f_trial[redo] = residual_of(trial[redo], active[redo])
        ga, f = trial, f_trial
    g[active] = ga  # not converged: the last iterate
    iterations[active] = -1
    residual[active] = np.max(np.abs(f), axis=1)
    return g, converged, iterations, residual


@dataclass(frozen=True)
class LoadedState:
    """The equilibrium under a wrench, geometry frozen at the unloaded pose (SI; twists
    and wrenches at P, axes of F_b): what :func:`ppm_stiffness.statics.loading
    .loaded_state` returns (``Equilibrium`` until 0.2).

    Attributes
    ----------
    pose : ndarray (6,)
        The full pose (x, y, z [m], rx, ry, rz [rad]) of P in F_b.
    wrench : ndarray (6,)
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at P, axes of F_b.
    actuator_forces : ndarray (n,) [N or N·m]
        Signed, ``G_i = a_i . w_i`` (the drive's share, ``a_i . w_i - k_h delta_i``,
        where a flexure acts in parallel with it: module doc).
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


#: The name of 0.2 (public as ``ppm_stiffness.LoadedState``; ``statics.loading`` names
#: it so).
Equilibrium = LoadedState


@dataclass(frozen=True)
class EquilibriumBatch:
    """The loaded state at k poses (SI; at P, axes of F_b).

    Attributes
    ----------
    poses : ndarray (k, 6)
        Full poses (x, y, z, rx, ry, rz) [m, rad] of P in F_b.
    wrench : ndarray (6,)
    refusal : ndarray of int8 (k,)
        :class:`~ppm_stiffness.core.refusals.Refusal` codes: 0 exactly where
        :func:`equilibrium` returns.
    forces, displacements, actuator_stiffness, secant_stiffness : ndarray (k, n)
        As :class:`Equilibrium`; meaningful where an equilibrium was found (a code of 0
        or above ``NO_EQUILIBRIUM``), zero where the pose is unreachable or singular.
    twist : ndarray (k, 6)
    leg_wrenches : ndarray (k, n, 6)
    stiffness : ndarray (k, 6, 6)
        The loaded tangent K.
    iterations : ndarray of int (k,)
        -1 where no equilibrium was found (or the pose is unreachable or singular).
    residual : ndarray (k,)
        Largest force residual of Newton's method [N or N·m].
    rigid_finite : ndarray of bool (k,)
        ``sum K_i^S`` finite (False: a leg is rigid with its actuator locked).
    projector : ndarray (k, 6, 6)
        The legs' summed projector ``Pi`` (:mod:`ppm_stiffness.core.singularity`).
    """

    poses: FloatArray
    wrench: FloatArray
    refusal: RefusalArray
    forces: FloatArray
    displacements: FloatArray
    actuator_stiffness: FloatArray
    secant_stiffness: FloatArray
    twist: FloatArray
    leg_wrenches: FloatArray
    stiffness: FloatArray
    iterations: np.ndarray
    residual: FloatArray
    rigid_finite: BoolArray
    projector: FloatArray

    @property
    def solved(self) -> BoolArray:
        """An equilibrium was found (it may still be outside the model)."""
        return np.asarray((self.refusal == 0) | (self.refusal > Refusal.NO_EQUILIBRIUM))

    def state(self, i: int) -> LoadedState:
        """Pose ``i`` as a :class:`LoadedState`."""
        return LoadedState(
            pose=self.poses[i],
            wrench=self.wrench,
            actuator_forces=self.forces[i],
            actuator_displacements=self.displacements[i],
            actuator_stiffness=self.actuator_stiffness[i],
            secant_stiffness=self.secant_stiffness[i],
            twist=self.twist[i],
            leg_wrenches=self.leg_wrenches[i],
            stiffness_matrix=self.stiffness[i],
            iterations=int(self.iterations[i]),
        )


def solve_loaded(
    design: Design, terms: LegTerms, wrench: FloatArray, poses: FloatArray
) -> EquilibriumBatch:
    """The equations of the module doc at every pose of ``terms`` (all reachable)."""
    k, n = terms.size, len(design.legs)
    w = np.asarray(wrench, dtype=float)
    ks, a = terms.rigid, terms.actuator
    total = ks.sum(axis=1)
    rigid_finite = np.all(np.isfinite(total), axis=(1, 2))
    good = terms.nonsingular & rigid_finite
    if np.all(good):
        safe, ks_safe = total, ks
    else:  # no singular or non-finite matrix into the algebra (those poses are refused)
        safe = np.where(good[:, None, None], total, np.eye(6))
        ks_safe = np.where(good[:, None, None, None], ks, 0.0)
    c_s = np.linalg.inv(safe)
    c_s = 0.5 * (c_s + np.swapaxes(c_s, 1, 2))
    b = np.einsum("klij,klj->kli", ks_safe, a)
    cb = np.einsum("kij,klj->kli", c_s, b)
    u = c_s @ w
    g0 = np.einsum("kli,ki->kl", b, u)
    ab = np.einsum("kli,kli->kl", a, b)
    m = -np.einsum("kli,kji->klj", b, cb)
    m[:, np.arange(n), np.arange(n)] += ab
    m = 0.5 * (m + np.swapaxes(m, 1, 2))
    m[:, np.arange(n), np.arange(n)] += parallel_stiffnesses(design)  # module doc
    forces = np.zeros((k, n))
    converged = np.zeros(k, dtype=bool)
    iterations = np.full(k, -1)
    residual = np.zeros(k)
    idx = np.flatnonzero(good)
    if idx.size:
        forces[idx], converged[idx], iterations[idx], residual[idx] = solve_forces(
            design, g0[idx], m[idx], np.max(np.abs(ab[idx]), axis=1)
        )
    solved = good & converged
    forces = np.where(solved[:, None], forces, 0.0)
    delta = displacements(design, forces)
    k_tan = tangent_stiffnesses(design, forces)
    locked = locked_actuator_stiffness(design)
    with np.errstate(divide="ignore", invalid="ignore"):
        secant = np.where(delta != 0, forces / np.where(delta != 0, delta, 1.0), locked)
    twist = np.where(solved[:, None], u + np.einsum("kli,kl->ki", cb, delta), 0.0)
    leg_w = np.einsum("klij,klj->kli", ks_safe, twist[:, None, :] - a * delta[..., None])
    stiffness = terms.stiffness(k_tan)
    codes = first_refusal(
        (k,),
        [
            (Refusal.SINGULAR, good),
            (Refusal.NO_EQUILIBRIUM, converged),
            (Refusal.BEYOND_STROKE, within_stroke(design, delta)),
            (Refusal.LARGE_ROTATION, small_rotation(twist)),
            (Refusal.LOADED_NOT_POSITIVE_DEFINITE, positive_definite(stiffness)),
        ],
    )
    return EquilibriumBatch(
        poses=poses,
        wrench=w,
        refusal=codes,
        forces=forces,
        displacements=delta,
        actuator_stiffness=k_tan,
        secant_stiffness=secant,
        twist=twist,
        leg_wrenches=leg_w,
        stiffness=stiffness,
        iterations=np.where(solved, iterations, -1),
        residual=residual,
        rigid_finite=rigid_finite,
        projector=terms.projector,
    )


def loaded_states(design: Design, poses: ArrayLike, wrench: ArrayLike) -> EquilibriumBatch:
    """The loaded state under ``wrench`` at poses (k, n_task) or (k, 6), each with its
    refusal code
    (module doc): the one implementation of :func:`equilibrium` and of the maps.

    Parameters
    ----------
    design : Design
    poses : array_like (k, n_task) or (k, 6) [m, rad]
        Task coordinates or full poses (:mod:`ppm_stiffness.poses`); a pose whose
        completion fails is unreachable.
    wrench : array_like (6,) [N·m, N]
        At P, axes of F_b.
    """
    p, completed = full_poses(design, np.asarray(poses, dtype=float))
    p, completed = p.reshape(-1, 6), completed.reshape(-1)
    w = np.asarray(wrench, dtype=float)
    k, n = p.shape[0], len(design.legs)
    reach, terms = reachable_terms(design, p, completed)
    out = EquilibriumBatch(
        poses=p,
        wrench=w,
        refusal=np.where(reach, 0, Refusal.UNREACHABLE).astype(np.int8),
        forces=np.zeros((k, n)),
        displacements=np.zeros((k, n)),
        actuator_stiffness=np.tile(locked_actuator_stiffness(design), (k, 1)),
        secant_stiffness=np.tile(locked_actuator_stiffness(design), (k, 1)),
        twist=np.zeros((k, 6)),
        leg_wrenches=np.zeros((k, n, 6)),
        stiffness=np.zeros((k, 6, 6)),
        iterations=np.full(k, -1),
        residual=np.zeros(k),
        rigid_finite=np.ones(k, dtype=bool),
        projector=np.zeros((k, 6, 6)),
    )
    if terms is None:
        return out
    sub = solve_loaded(design, terms, w, p[reach])
    for name in (
        "refusal",
        "forces",
        "displacements",
        "actuator_stiffness",
        "secant_stiffness",
        "twist",
        "leg_wrenches",
        "stiffness",
        "iterations",
        "residual",
        "rigid_finite",
        "projector",
    ):
        getattr(out, name)[reach] = getattr(sub, name)
    return out


def raise_refusal(design: Design, batch: EquilibriumBatch, i: int) -> None:
    """Raise the error of pose ``i``'s refusal code (nothing for 0), with a message
    that says why; the checks that word it test what the code tested."""
    code = Refusal(int(batch.refusal[i]))
    if code == Refusal.NONE:
        return
    where = pose_label(batch.poses[i], design)
    if code == Refusal.UNREACHABLE:
        solve_legs(design, batch.poses[i])  # names the leg and the limit
        raise UnreachablePoseError(f"pose unreachable{where}")
    if code == Refusal.SINGULAR:
        if not batch.rigid_finite[i]:
            raise SingularConfigurationError(f"a leg is rigid with its actuator locked{where}")
        k_rigid = np.zeros((6, 6))  # finite: the message is about the transmission index
        raise SingularConfigurationError(singular_message(k_rigid, batch.projector[i], where))
    if code == Refusal.NO_EQUILIBRIUM:
        raise EquilibriumError(
            f"no equilibrium found after {MAX_ITERATIONS} Newton iterations{where} "
            f"(largest force residual {float(batch.residual[i]):.3g})"
        )
    if code == Refusal.BEYOND_STROKE:
        check_actuator_travel(design, batch.displacements[i])
    elif code == Refusal.LARGE_ROTATION:
        check_small_rotation(batch.twist[i])
    else:
        raise SingularConfigurationError(
            f"the loaded stiffness matrix is not positive definite{where}"
        )
    raise code.error(f"{code.reason}{where}")  # the checks above raise first


def equilibrium(
    design: Design,
    wrench: ArrayLike,
    pose: ArrayLike,
    structures: LegStructures | None = None,
) -> Equilibrium:
    """The loaded state under ``wrench`` (m_x, m_y, m_z, f_x, f_y, f_z at P, F_b).

    The batch of one pose of :func:`loaded_states`, raising where its refusal code is
    not 0.

    Parameters
    ----------
    design : Design
    wrench : array_like (6,) [N·m, N]
    pose : array_like (n_task,) or (6,) [m, rad]
        The design's task coordinates ((x, y, phi) for a planar design; all six for a
        hexapod; (z, rx, ry) for a tripod) or the full pose (x, y, z, rx, ry, rz) of P
        in F_b (:mod:`ppm_stiffness.poses`).
    structures : LegStructures, optional
        Reuse the springs of an earlier call at the same pose.

    Returns
    -------
    Equilibrium

    Raises
    ------
    InputDataError
        If the wrench is not 6 finite numbers or the pose neither the task coordinates
        nor a full pose.
    UnreachablePoseError, SingularConfigurationError, EquilibriumError
    InputDataError
        A load beyond the small-displacement model (an actuator beyond its stroke, a
        rotation beyond :data:`MAX_ROTATION`).
    """
    w = validate_wrench(wrench)
    p = validate_pose(design, pose)
    if structures is None:
        batch = loaded_states(design, p.reshape(1, 6), w)
    else:
        batch = solve_loaded(design, structures.terms, w, structures.pose.reshape(1, 6))
    raise_refusal(design, batch, 0)
    return batch.state(0)
