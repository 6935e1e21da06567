"""The Cartesian stiffness of a design at a pose: the single-pose API.

Joins a design's geometry module (today :mod:`ppm_stiffness.legs.ppr`) and the generic
solver. Poses are ``(x, y, phi)`` in F_b [m, m, rad]; matrices are at P with the axes
of F_b (see :mod:`ppm_stiffness.core.conventions`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import DesignError, SingularConfigurationError
from ppm_stiffness.core.solver import LegSprings, cartesian_stiffness, leg_stiffness
from ppm_stiffness.design import Design
from ppm_stiffness.legs import ppr

#: Smallest admissible ratio of the smallest to the largest eigenvalue of the
#: length-balanced stiffness matrix; below it the configuration is called singular.
SINGULARITY_TOLERANCE = 1e-9


def workspace_centre(design: Design) -> FloatArray:
    """The design's workspace centre pose (x, y, phi) [m, m, rad]."""
    ws = design.workspace
    return np.array([ws.centre_x, ws.centre_y, ws.phi])


def actuator_stiffness_vector(design: Design, actuator_stiffness: ArrayLike | None) -> FloatArray:
    """Per-leg actuator stiffness [N/m]; the locked value when None is given."""
    n = len(design.legs)
    if actuator_stiffness is None:
        return np.full(n, design.actuator.locked_stiffness)
    k = np.asarray(actuator_stiffness, dtype=float)
    if k.shape == ():
        k = np.full(n, float(k))
    if k.shape[-1] != n:
        raise DesignError(f"expected {n} actuator stiffnesses, got {k.shape[-1]}")
    if not np.all(np.isfinite(k)) or np.any(k <= 0):
        raise DesignError("actuator stiffness must be finite and > 0 N/m")
    return k


def leg_springs_at_pose(
    design: Design, pose: ArrayLike, actuator_stiffness: ArrayLike | None = None
) -> list[LegSprings]:
    """Virtual springs of every leg at one reachable pose (raises if unreachable)."""
    k_act = actuator_stiffness_vector(design, actuator_stiffness)
    geoms = ppr.check_reachable(design, pose)
    return [
        ppr.leg_springs(design, leg, g, k_act[i])
        for i, (leg, g) in enumerate(zip(design.legs, geoms, strict=True))
    ]


def check_nonsingular(stiffness: FloatArray, where: str = "") -> None:
    """Raise :class:`SingularConfigurationError` if K is not finite or nearly singular."""
    if not np.all(np.isfinite(stiffness)):
        raise SingularConfigurationError(f"stiffness matrix is not finite{where}")
    scale = np.array([10.0, 10.0, 10.0, 1.0, 1.0, 1.0])  # rotations balanced at 0.1 m
    ks = stiffness / scale[:, None] / scale[None, :]
    eig = np.linalg.eigvalsh(ks)
    if eig[-1] <= 0 or eig[0] < -SINGULARITY_TOLERANCE * eig[-1]:
        raise SingularConfigurationError(
            f"stiffness matrix is not positive definite{where}: smallest eigenvalue "
            f"{eig[0]:.3g} (length-balanced units)"
        )
    if eig[0] <= SINGULARITY_TOLERANCE * eig[-1]:
        raise SingularConfigurationError(
            f"singular configuration{where}: stiffness eigenvalue ratio "
            f"{eig[0] / eig[-1]:.2e} below {SINGULARITY_TOLERANCE:.0e}"
        )


def stiffness_at_pose(
    design: Design, pose: ArrayLike | None = None, actuator_stiffness: ArrayLike | None = None
) -> FloatArray:
    """Cartesian stiffness matrix of the platform, shape (6, 6).

    Parameters
    ----------
    design : Design
    pose : array_like, shape (3,), optional
        (x [m], y [m], phi [rad]) of P in F_b; the workspace centre if None.
    actuator_stiffness : array_like, shape (n_legs,) or scalar, optional
        [N/m]; the locked (unloaded) value if None.

    Returns
    -------
    ndarray, shape (6, 6)
        At P, axes of F_b, blocks [[K_rr, K_rt], [K_rt^T, K_tt]] in N·m/rad, N, N/m.

    Raises
    ------
    UnreachablePoseError, SingularConfigurationError
    """
    p = workspace_centre(design) if pose is None else np.asarray(pose, dtype=float)
    legs = leg_springs_at_pose(design, p, actuator_stiffness)
    k = cartesian_stiffness(legs)
    check_nonsingular(k, f" at pose ({p[0] * 1e3:.2f} mm, {p[1] * 1e3:.2f} mm, "
                         f"{np.degrees(p[2]):.2f} deg)")
    return k


def leg_stiffnesses_at_pose(
    design: Design, pose: ArrayLike | None = None, actuator_stiffness: ArrayLike | None = None
) -> list[FloatArray]:
    """Each leg's 6x6 stiffness at P (their sum is :func:`stiffness_at_pose`)."""
    p = workspace_centre(design) if pose is None else np.asarray(pose, dtype=float)
    return [leg_stiffness(leg) for leg in leg_springs_at_pose(design, p, actuator_stiffness)]
