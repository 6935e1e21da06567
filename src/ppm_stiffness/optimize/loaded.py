"""The loaded state over many poses, for the region summary.

:func:`loaded_region` is the only place the region summary asks for loaded states: the
batched equilibrium :func:`ppm_stiffness.maps.loaded.loaded_poses`, which equals
:func:`ppm_stiffness.statics.loading.loaded_state` pose by pose (tests/test_loaded_batch.py)
and is valid exactly where that returns. The wrench acts at the design's tool point;
the equilibrium takes it at P, where it depends on the tool point's offset R t: the
poses are solved in groups of one offset (one group per orientation of a planar
region; one pose per group for a tripod, whose parasitic rotation differs at every
pose, when its tool point is not P).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray, hat, rotation_z
from ppm_stiffness.core.errors import (
    EquilibriumError,
    InputDataError,
    SingularConfigurationError,
    UnreachablePoseError,
)
from ppm_stiffness.design import Design

#: The errors that make a pose's loaded state unavailable (not a bug): unreachable or
#: singular, no equilibrium, or a load beyond the small-displacement model.
LOADED_STATE_ERRORS = (
    EquilibriumError,
    InputDataError,
    SingularConfigurationError,
    UnreachablePoseError,
)


@dataclass(frozen=True)
class LoadedRegion:
    """The loaded state at n poses under one wrench at the tool point (SI).

    Attributes
    ----------
    twists : ndarray (n, 6)
        Platform twist (omega [rad], v [m]) of P, axes of F_b; NaN where not ``solved``.
    solved : ndarray of bool (n,)
        False where the loaded state cannot be computed (:data:`LOADED_STATE_ERRORS`).
    offsets : ndarray (n, 3)
        The tool point's offset T - P [m, F_b] at each unloaded pose.
    stiffness : ndarray (n, 6, 6) or None
        The loaded tangent K at P (zero where not solved), when asked for.
    actuator_stiffness : ndarray (n, n_legs) or None
        The tangent actuator stiffnesses the loaded K was built with, when asked for.
    poses : ndarray (n, 6) or None
        The full unloaded poses, when asked for.
    forces : ndarray (n, n_legs) or None
        The actuator forces G_i [N or N·m, each leg's kind] of the loaded state; NaN
        where not solved.
    """

    twists: FloatArray
    solved: BoolArray
    offsets: FloatArray
    stiffness: FloatArray | None = None
    actuator_stiffness: FloatArray | None = None
    poses: FloatArray | None = None
    forces: FloatArray | None = None

    def tool_motion(self) -> tuple[FloatArray, FloatArray]:
        """The tool point's displacement v + omega x (T - P) (n, 3) [m] and the rotation
        omega (n, 3) [rad], axes of F_b; NaN where not solved."""
        v = self.twists[:, 3:] + np.cross(self.twists[:, :3], self.offsets)
        return v, self.twists[:, :3]


def shift(offsets: FloatArray) -> FloatArray:
    """Per pose ``A = [[1, hat(-r)], [0, 1]]`` (n, 6, 6): ``K_T = A K A^T``,
    ``w_P = A^-1 w_T``, for tool offsets ``r = T - P`` (n, 3) [m, F_b]."""
    a = np.tile(np.eye(6), (offsets.shape[0], 1, 1))
    a[:, :3, 3:] = hat(-offsets)
    return a


def tool_offsets(design: Design, poses: FloatArray) -> FloatArray:
    """``T - P`` at each pose (n, 3) [m, F_b] (:func:`ppm_stiffness.model.tool_offset`)
    for poses (n, n_task) in task coordinates: a planar design's by ``rotation_z(phi)``,
    another's at its completed full pose."""
    tool = np.asarray(design.tool_point, dtype=float)
    if design.planar:
        return np.asarray(rotation_z(poses[:, 2]) @ tool)
    from ppm_stiffness.model import tool_offset
    from ppm_stiffness.poses import full_poses

    full, _ = full_poses(design, poses)
    return np.asarray(tool_offset(full, tool)).reshape(-1, 3)


def loaded_region(
    design: Design, poses: ArrayLike, wrench: ArrayLike, *, matrices: bool = False
) -> LoadedRegion:
    """The loaded state under ``wrench`` at the tool point at each pose (module doc).

    Parameters
    ----------
    design : Design
    poses : array_like, shape (n, n_task)
        Task coordinates of P in F_b [m, rad].
    wrench : array_like, shape (6,)
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at the design's tool point, axes of F_b.
    matrices : bool
        Also return the loaded tangent K, the tangent actuator stiffnesses and the full
        poses (for the natural frequencies).

    Returns
    -------
    LoadedRegion
    """
    from ppm_stiffness.maps.loaded import loaded_poses

    p = np.asarray(poses, dtype=float)
    p = p.reshape(-1, p.shape[-1])
    n = p.shape[0]
    w = np.asarray(wrench, dtype=float)
    at_tool = bool(np.any(np.asarray(design.tool_point, dtype=float)))
    offsets = tool_offsets(design, p) if at_tool else np.zeros((n, 3))
    twists = np.full((n, 6), np.nan)
    solved = np.zeros(n, dtype=bool)
    n_legs = len(design.legs)
    forces = np.full((n, n_legs), np.nan)
    mats = np.zeros((n, 6, 6)) if matrices else None
    k_act = np.full((n, n_legs), np.nan) if matrices else None
    full = np.zeros((n, 6)) if matrices else None
    if at_tool:
        keys, groups = np.unique(offsets, axis=0, return_inverse=True)
        groups = np.asarray(groups).reshape(-1)
    else:
        keys, groups = np.zeros((1, 3)), np.zeros(n, dtype=int)
    for g in range(keys.shape[0]):
        rows = np.flatnonzero(groups == g)
        w_p = np.linalg.solve(shift(offsets[rows[:1]])[0], w) if at_tool else w
        result = loaded_poses(design, p[rows], w_p, matrices=matrices, principal=False)
        ok = np.asarray(result.valid, dtype=bool)
        solved[rows] = ok
        twists[rows] = np.where(ok[:, None], np.ma.getdata(result.twist), np.nan)
        forces[rows] = np.where(ok[:, None], np.ma.getdata(result.actuator_forces), np.nan)
        if mats is not None and k_act is not None and full is not None:
            assert result.stiffness is not None
            mats[rows] = result.stiffness
            k_act[rows] = np.where(ok[:, None], np.ma.getdata(result.actuator_stiffness), np.nan)
            full[rows] = result.poses
    return LoadedRegion(twists, solved, offsets, mats, k_act, full, forces)


def loaded_twists(
    design: Design, poses: ArrayLike, wrench: ArrayLike
) -> tuple[FloatArray, BoolArray]:
    """Platform deflection under ``wrench`` at P at each pose (the loaded equilibrium).

    Parameters
    ----------
    design : Design
    poses : array_like, shape (n, n_task)
        Task coordinates of P in F_b ((x [m], y [m], phi [rad]) for a planar design).
    wrench : array_like, shape (6,)
        (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N] at P, axes of F_b.

    Returns
    -------
    twists : ndarray (n, 6)
        (omega [rad], v [m]) of P, axes of F_b; NaN where ``solved`` is False.
    solved : ndarray of bool (n,)
        False where the loaded state cannot be computed (:data:`LOADED_STATE_ERRORS`).
    """
    from ppm_stiffness.maps.loaded import loaded_poses

    p = np.asarray(poses, dtype=float)
    p = p.reshape(-1, p.shape[-1])
    result = loaded_poses(design, p, np.asarray(wrench, dtype=float))
    solved = np.asarray(result.valid, dtype=bool)
    twists = np.where(solved[:, None], np.ma.getdata(result.twist), np.nan)
    return twists, solved


def loaded_state_error(design: Design, pose: ArrayLike, wrench: ArrayLike) -> str:
    """The message of the error that :func:`loaded_region` met at ``pose`` (task
    values; ``wrench`` at the tool point), "" if none."""
    from ppm_stiffness.core.conventions import wrench_b_from_wrench_a
    from ppm_stiffness.statics.loading import loaded_state

    p = np.asarray(pose, dtype=float)
    w = np.asarray(wrench, dtype=float)
    try:
        offset = tool_offsets(design, p[None])[0]
        w_p = wrench_b_from_wrench_a(np.eye(3), offset) @ w
        loaded_state(design, w_p, p)
    except LOADED_STATE_ERRORS as exc:
        return str(exc)
    return ""
