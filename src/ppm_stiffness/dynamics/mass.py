"""The design's 6x6 mass matrix at P, at one pose or many.

``M = M_platform + sum_legs M_leg`` at P, axes of F_b, order (omega, v), in kg·m^2
(rotational block), kg·m (coupling) and kg (translational block): the kinetic energy of
the machine moving with the platform twist t (the legs following statically,
:mod:`ppm_stiffness.dynamics.condensation`) is ``t^T M t / 2``, so that
``K v = omega^2 M v`` is consistent with ``w = K t``. The platform is a rigid body
(:class:`~ppm_stiffness.design.platform.PlatformModel`: its centre of mass and inertia
are given in the platform frame and turn with it, ``c = R c_p``, ``I = R I_p R^T``).
M is symmetric positive definite (the platform's mass and inertia are positive, the
legs add positive semi-definite terms), and transforms between reference points as K
does (:func:`ppm_stiffness.model.stiffness_at_tool_point` applies to both).

The legs' motion depends on their springs, the actuators' among them: the locked
actuator stiffnesses by default, the tangent ones of a loaded state when given.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core import pose as pose6
from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.design import Design
from ppm_stiffness.dynamics.condensation import leg_mass_matrix
from ppm_stiffness.dynamics.inertia import rotated_inertia, spatial_inertia
from ppm_stiffness.legs.chain import stack_chains, structure_groups
from ppm_stiffness.model import actuator_stiffness_vector, solve_legs
from ppm_stiffness.poses import full_pose

#: Poses evaluated together by :func:`mass_matrix`: their temporaries (about 10 kB per
#: pose and leg) stay in the processor's caches; 2048 is 25 % faster than 10^4 at once
#: on the hexapod (benchmarks/bench_modes.py).
MASS_CHUNK = 2048


def require_mass_model(design: Design) -> None:
    """Raise :class:`DesignError` if the design has no mass model."""
    if design.platform is None:
        raise DesignError(
            f"{design.name!r} has no mass model: add a [platform] table (mass [kg] and "
            "inertia [kg·m^2], or a shape) and, optionally, the masses of the legs' parts "
            "(docs/dynamics.md)"
        )


def platform_mass_matrix(design: Design, poses: ArrayLike) -> FloatArray:
    """The platform's spatial inertia (..., 6, 6) at P at full poses (..., 6).

    Raises
    ------
    DesignError
        If the design has no mass model.
    """
    require_mass_model(design)
    assert design.platform is not None
    q = np.asarray(poses, dtype=float)
    body = design.platform
    centre = pose6.platform_offset(q, body.centre())
    inertia = rotated_inertia(body.inertia_tensor(), pose6.rotation(q))
    return spatial_inertia(body.mass, centre, inertia)


def mass_matrix(
    design: Design, poses: ArrayLike, actuator_stiffness: ArrayLike | None = None
) -> FloatArray:
    """M (..., 6, 6) at P at full poses (..., 6), batched (module doc).

    Parameters
    ----------
    design : Design
        With a mass model.
    poses : array_like (..., 6)
        Full poses [m, rad] (:func:`ppm_stiffness.poses.full_poses`).
    actuator_stiffness : array_like (..., n_legs) or (n_legs,), optional
        [N/m or N·m/rad]; the locked values if None.

    Returns
    -------
    ndarray (..., 6, 6)
        Symmetric; NaN at poses a leg cannot reach (no inverse-kinematics solution or a
        joint coordinate beyond its limits: the single-pose
        :func:`mass_matrix_at_pose` raises there) and where a leg's passive joints are
        dependent.

    Raises
    ------
    DesignError
        If the design has no mass model.
    """
    q = np.asarray(poses, dtype=float)
    n_legs = len(design.legs)
    k = actuator_stiffness
    if k is None:
        k = actuator_stiffness_vector(design, None)
    k_act = np.broadcast_to(np.asarray(k, dtype=float), q.shape[:-1] + (n_legs,))
    if q.ndim == 1:
        return _mass_matrices(design, q, k_act)
    flat, k_flat = q.reshape(-1, 6), k_act.reshape(-1, n_legs)
    out = np.empty((flat.shape[0], 6, 6))
    for lo in range(0, flat.shape[0], MASS_CHUNK):
        hi = lo + MASS_CHUNK
        out[lo:hi] = _mass_matrices(design, flat[lo:hi], k_flat[lo:hi])
    return out.reshape(q.shape[:-1] + (6, 6))


def _mass_matrices(design: Design, q: FloatArray, k_act: FloatArray) -> FloatArray:
    """M (..., 6, 6) at full poses (..., 6) with actuator stiffnesses (..., n_legs)."""
    total = platform_mass_matrix(design, q)
    reachable = np.ones(q.shape[:-1], dtype=bool)
    for i, leg in enumerate(design.legs):
        leg_pose = leg.solve(q)
        reachable = reachable & leg.reachable(leg_pose)
        total = total + leg_mass_matrix(leg.chain(leg_pose), k_act[..., i])
    total = np.where(reachable[..., None, None], total, np.nan)
    return np.asarray(0.5 * (total + np.swapaxes(total, -1, -2)))


def leg_mass_matrices(
    design: Design, pose: ArrayLike | None = None, actuator_stiffness: ArrayLike | None = None
) -> list[FloatArray]:
    """Each leg's mass matrix (6, 6) at P at one pose (their sum plus the platform's is
    :func:`mass_matrix_at_pose`).

    Raises
    ------
    DesignError, InputDataError, UnreachablePoseError
    """
    require_mass_model(design)
    p = full_pose(design, pose)
    k_act = actuator_stiffness_vector(design, actuator_stiffness)
    chains = [leg.chain(lp) for leg, lp in zip(design.legs, solve_legs(design, p), strict=True)]
    k = np.asarray(k_act, dtype=float)
    out: list[FloatArray] = [np.zeros((6, 6))] * len(chains)
    for group in structure_groups(chains):  # the legs of one structure in one batched call
        stacked = stack_chains([chains[i] for i in group])
        assert stacked is not None
        for i, m in zip(group, leg_mass_matrix(stacked, k[group]), strict=True):
            out[i] = m
    return out


def mass_matrix_at_pose(
    design: Design, pose: ArrayLike | None = None, actuator_stiffness: ArrayLike | None = None
) -> FloatArray:
    """M (6, 6) at P at one pose (the home pose if None), checked reachable.

    Parameters
    ----------
    design : Design
        With a mass model.
    pose : array_like (n_task,) or (6,), optional
        Task coordinates or a full pose [m, rad] (:mod:`ppm_stiffness.poses`).
    actuator_stiffness : array_like (n_legs,) or scalar, optional
        [N/m or N·m/rad]; the locked values if None.

    Returns
    -------
    ndarray (6, 6)
        [[M_rr, M_rt], [M_rt^T, M_tt]] in kg·m^2, kg·m, kg; at P, axes of F_b.

    Raises
    ------
    DesignError
        No mass model.
    InputDataError, UnreachablePoseError, SingularConfigurationError
        A bad pose, an unreachable one, or one where M is not finite.
    """
    require_mass_model(design)
    p = full_pose(design, pose)
    legs = leg_mass_matrices(design, p, actuator_stiffness)
    m = platform_mass_matrix(design, p) + np.sum(legs, axis=0)
    m = 0.5 * (m + m.T)
    if not np.all(np.isfinite(m)):
        from ppm_stiffness.core.errors import SingularConfigurationError
        from ppm_stiffness.model import pose_label

        raise SingularConfigurationError(
            f"mass matrix not finite{pose_label(p)}: a leg's passive joints are dependent"
        )
    return m


def moving_mass(design: Design) -> dict[str, float]:
    """The physical masses of the mass model [kg]: ``platform``, ``links`` (every
    link's, a parallelogram's two bars: :meth:`LegModel.link_mass`), ``carriages``
    (every actuator's carriage), and ``total``."""
    require_mass_model(design)
    assert design.platform is not None
    links = sum(leg.link_mass() for leg in design.legs)
    carriages = sum((leg.actuator and leg.actuator.carriage_mass) or 0.0 for leg in design.legs)
    platform = design.platform.mass
    return {
        "platform": platform,
        "links": links,
        "carriages": carriages,
        "total": platform + links + carriages,
    }
