"""The loaded state over many poses: one function, the seam a batched version replaces.

:func:`loaded_twists` is the only place the region summary asks for loaded states;
today it loops over :func:`ppm_stiffness.statics.loading.loaded_state` (about 3-7 ms
per pose), so a batched implementation in :mod:`ppm_stiffness.maps` can take its place
without touching anything else.
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
    from ppm_stiffness.statics.loading import loaded_state

    p = np.asarray(poses, dtype=float).reshape(-1, 3)
    w = np.asarray(wrench, dtype=float)
    twists = np.full((p.shape[0], 6), np.nan)
    solved = np.zeros(p.shape[0], dtype=bool)
    for n, pose in enumerate(p):
        try:
            twists[n] = loaded_state(design, w, pose).twist
        except LOADED_STATE_ERRORS:
            continue
        solved[n] = True
    return twists, solved


def loaded_state_error(design: Design, pose: ArrayLike, wrench: ArrayLike) -> str:
    """The message of the error that :func:`loaded_twists` met at ``pose`` ("" if none)."""
    from ppm_stiffness.statics.loading import loaded_state

    try:
        loaded_state(design, np.asarray(wrench, dtype=float), np.asarray(pose, dtype=float))
    except LOADED_STATE_ERRORS as exc:
        return str(exc)
    return ""
