"""The loaded state over many poses, for the region summary.

:func:`loaded_twists` is the only place the region summary asks for loaded states: the
batched equilibrium :func:`ppm_stiffness.maps.loaded.loaded_poses`, which equals
:func:`ppm_stiffness.statics.loading.loaded_state` pose by pose (tests/test_loaded_batch.py)
and is valid exactly where that returns.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import BoolArray, FloatArray
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


def loaded_twists(
    design: Design, poses: ArrayLike, wrench: ArrayLike
) -> tuple[FloatArray, BoolArray]:
    """Platform deflection under ``wrench`` at each pose (the loaded equilibrium).

    Parameters
    ----------
    design : Design
    poses : array_like, shape (n, 3)
        (x [m], y [m], phi [rad]) of P in F_b.
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

    p = np.asarray(poses, dtype=float).reshape(-1, 3)
    result = loaded_poses(design, p, np.asarray(wrench, dtype=float))
    solved = np.asarray(result.valid, dtype=bool)
    twists = np.where(solved[:, None], np.ma.getdata(result.twist), np.nan)
    return twists, solved


def loaded_state_error(design: Design, pose: ArrayLike, wrench: ArrayLike) -> str:
    """The message of the error that :func:`loaded_twists` met at ``pose`` ("" if none)."""
    from ppm_stiffness.statics.loading import loaded_state

    try:
        loaded_state(design, np.asarray(wrench, dtype=float), np.asarray(pose, dtype=float))
    except LOADED_STATE_ERRORS as exc:
        return str(exc)
    return ""
