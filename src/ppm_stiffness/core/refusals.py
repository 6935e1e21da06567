"""Why a pose is refused: one code per pose, shared by the single-pose API and the maps.

The single-pose functions (:func:`ppm_stiffness.model.stiffness_at_pose`,
:func:`ppm_stiffness.statics.loading.loaded_state`) raise at a pose exactly where the
batched ones give it a nonzero code (:func:`ppm_stiffness.maps.loaded.loaded_poses`,
:attr:`ppm_stiffness.maps.workspace.StiffnessMap.refusal`; ``evaluate_poses`` masks the
same poses), and the code names the error: the checks run in the order of
:class:`Refusal`, and the first that fails decides (:func:`first_refusal`).
"""

from __future__ import annotations

from collections.abc import Sequence
from enum import IntEnum

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ppm_stiffness.core.errors import (
    EquilibriumError,
    InputDataError,
    PPMStiffnessError,
    SingularConfigurationError,
    UnreachablePoseError,
)

#: Codes per pose: an int8 array, 0 where the pose is accepted.
RefusalArray = NDArray[np.int8]


class Refusal(IntEnum):
    """Why a pose is refused, in the order the checks run."""

    NONE = 0
    #: a leg's inverse kinematics has no solution or a joint coordinate is out of limits
    UNREACHABLE = 1
    #: K not finite, or the transmission index at or below its tolerance
    #: (:mod:`ppm_stiffness.core.singularity`; under a load: with the actuators rigid)
    SINGULAR = 2
    #: Newton's method found no equilibrium of the actuator forces
    NO_EQUILIBRIUM = 3
    #: an actuator would move by more than its whole stroke (small-displacement model)
    BEYOND_STROKE = 4
    #: the platform would rotate by more than the small-displacement model covers
    LARGE_ROTATION = 5
    #: the loaded tangent K is not positive definite
    LOADED_NOT_POSITIVE_DEFINITE = 6
    #: with moving geometry: the load path passes the first instability (a limit or
    #: bifurcation point, :mod:`ppm_stiffness.statics.margin`) before the full load
    UNSTABLE = 7

    @property
    def reason(self) -> str:
        """A short description, for counts ("12 outside the joint limits")."""
        return _REASONS[self]

    @property
    def error(self) -> type[PPMStiffnessError]:
        """The error the single-pose API raises for this code."""
        return _ERRORS[self]


_REASONS = {
    Refusal.NONE: "accepted",
    Refusal.UNREACHABLE: "outside the joint limits",
    Refusal.SINGULAR: "singular",
    Refusal.NO_EQUILIBRIUM: "no equilibrium found",
    Refusal.BEYOND_STROKE: "load too large: an actuator beyond its stroke",
    Refusal.LARGE_ROTATION: "load too large: platform rotation beyond the small-displacement model",
    Refusal.LOADED_NOT_POSITIVE_DEFINITE: "loaded stiffness not positive definite",
    Refusal.UNSTABLE: "load beyond the first instability (moving geometry)",
}
_ERRORS: dict[Refusal, type[PPMStiffnessError]] = {
    Refusal.NONE: PPMStiffnessError,
    Refusal.UNREACHABLE: UnreachablePoseError,
    Refusal.SINGULAR: SingularConfigurationError,
    Refusal.NO_EQUILIBRIUM: EquilibriumError,
    Refusal.BEYOND_STROKE: InputDataError,
    Refusal.LARGE_ROTATION: InputDataError,
    Refusal.LOADED_NOT_POSITIVE_DEFINITE: SingularConfigurationError,
    Refusal.UNSTABLE: EquilibriumError,
}


def first_refusal(
    shape: tuple[int, ...], checks: Sequence[tuple[Refusal, ArrayLike]]
) -> RefusalArray:
    """Codes (shape) from checks in order: ``(code, passed)`` with ``passed`` a boolean
    array broadcastable to ``shape``; a pose gets the code of the first check it fails,
    0 if it passes them all."""
    codes = np.zeros(shape, dtype=np.int8)
    for code, passed in checks:
        ok = np.broadcast_to(np.asarray(passed, dtype=bool), shape)
        codes = np.where((codes == 0) & ~ok, np.int8(code), codes).astype(np.int8)
    return codes


def refusal_counts(codes: ArrayLike) -> dict[str, int]:
    """Refused poses by reason (:attr:`Refusal.reason` -> count), in check order; only
    the reasons that occur."""
    c = np.asarray(codes)
    return {r.reason: int(np.count_nonzero(c == r)) for r in Refusal if r and np.any(c == r)}
