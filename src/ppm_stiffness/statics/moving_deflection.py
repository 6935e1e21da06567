"""Deflection along a growing load with moving geometry, beside the frozen curve.

The frozen curve (:mod:`ppm_stiffness.statics.deflection`) keeps the geometry of the
unloaded pose. Here every load of the same curve is solved with the equilibrium with
moving geometry (:func:`ppm_stiffness.statics.moving.moving_load_states`: row i is what
:func:`~ppm_stiffness.statics.moving.moving_loaded_state` gives under load i), so that
both curves share their loads, their load direction and their tool point.

The moving curve stops at the first load whose equilibrium is refused: the load path
passes the first instability (``UNSTABLE``), no equilibrium is found on it
(``NO_EQUILIBRIUM``: a limit point) or an actuator runs beyond its whole stroke. It then
names the reason and, for the first two, the load at which the path loses stability
(the load margin of :mod:`ppm_stiffness.statics.margin` times the refused load) with the
buckling mode: no point beyond is drawn or printed, and none before is dropped.

The twists are finite displacements of the tool point (the platform's rotation vector
[rad], R' = exp(hat(phi)) R, and the tool point's displacement [m], axes of F_b), which
tend to the frozen curve's small twists as the load tends to 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, wrench_b_from_wrench_a
from ppm_stiffness.core.errors import EquilibriumError, InputDataError
from ppm_stiffness.core.inputs import validate_wrench
from ppm_stiffness.core.refusals import Refusal
from ppm_stiffness.design import Design
from ppm_stiffness.model import tool_offset, validate_pose
from ppm_stiffness.statics.deflection import DeflectionCurve, deflection_path
from ppm_stiffness.statics.equilibrium import loaded_states
from ppm_stiffness.statics.margin import LoadMargin, MarginKind, load_margin
from ppm_stiffness.statics.moving import (
    moving_load_states,
    raise_moving_refusal,
    relative_difference,
)

#: The method label of a moving-geometry curve (:attr:`DeflectionCurve.method`).
MOVING_METHOD = "moving geometry"
#: The statics models a curve may use.
GEOMETRIES = ("frozen", "moving")


@dataclass(frozen=True)
class CurveStop:
    """Where and why a curve stops before its last load.

    Attributes
    ----------
    load : float
        The first load the curve lacks [the curve's load unit].
    reason : str
        Why (a :class:`~ppm_stiffness.core.refusals.Refusal` reason).
    instability_load : float or None
        Moving geometry: the load at which the path loses stability (the load margin
        of ``load`` times it), where found.
    margin : LoadMargin or None
        That load margin, with its buckling mode.
    """

    load: float
    reason: str
    instability_load: float | None = None
    margin: LoadMargin | None = None

    def describe(self, geometry: str, unit: str) -> str:
        """One line: "the moving-geometry curve stops before the load 3.5 N: ..."."""
        unit = "times the wrench" if unit == "1" else unit
        text = f"the {geometry}-geometry curve stops before the load {self.load:g} {unit}: "
        text += self.reason
        if self.instability_load is not None and self.margin is not None:
            kind = self.margin.kind
            what = "bifurcation" if kind == MarginKind.BIFURCATION else "limit point"
            text += (
                f"; the path loses stability at {self.instability_load:.6g} {unit} ({what}; "
                f"mode: {self.margin.mode_name})"
            )
        return text


@dataclass(frozen=True)
class MovingDeflection:
    """The frozen and the moving-geometry curves of one load path (SI, axes of F_b).

    Attributes
    ----------
    frozen : DeflectionCurve
        The frozen model's curve (:func:`~ppm_stiffness.statics.deflection
        .deflection_path`), over the loads it accepts (``frozen_stop``).
    moving : DeflectionCurve
        The moving-geometry curve over the loads solved (up to the first refused one):
        the tool point's finite twists (n, 6) [rad, m] and the actuators' forces,
        tangent stiffnesses and displacements; ``method`` is :data:`MOVING_METHOD`.
    displaced_poses : ndarray (n, 6)
        The loaded pose (x, y, z, rx, ry, rz) [m, rad] of P under each load of ``moving``.
    stiffness_difference : ndarray (n,)
        ``||K_F - K|| / ||K||`` at each load of ``moving`` (length-balanced Frobenius
        norms; K the frozen model's loaded tangent under the same load, both at the
        tool point).
    frozen_stop, moving_stop : CurveStop or None
        Where each curve stops before the last load (None: it does not).
    leg_wrenches : ndarray (n, n_legs, 6) or None
        Each leg's wrench about the displaced load point under each load of ``moving``
        [N·m, N] (:class:`~ppm_stiffness.statics.moving.MovingBatch`).
    coordinates : tuple of ndarray (n, n_i) or None
        Each leg's chain coordinates at each load of ``moving`` [m or rad].
    """

    frozen: DeflectionCurve
    moving: DeflectionCurve
    displaced_poses: FloatArray
    stiffness_difference: FloatArray
    frozen_stop: CurveStop | None
    moving_stop: CurveStop | None
    leg_wrenches: FloatArray | None = None
    coordinates: tuple[FloatArray, ...] | None = None

    def stops(self) -> list[str]:
        """A line for each curve that stops early."""
        unit = self.frozen.load_unit
        return [
            stop.describe(name, unit)
            for name, stop in (("frozen", self.frozen_stop), ("moving", self.moving_stop))
            if stop is not None
        ]


def _frozen_prefix(
    design: Design, unit_wrench: FloatArray, loads: FloatArray, pose: FloatArray, tool: FloatArray
) -> tuple[int, str | None]:
    """How many loads (from the first) the frozen model accepts, and the first refused
    one's reason (:func:`~ppm_stiffness.statics.equilibrium.loaded_states`' codes)."""
    offset = tool_offset(pose, tool)
    to_p = wrench_b_from_wrench_a(np.eye(3), offset)
    for i, load in enumerate(loads):
        code = int(
            loaded_states(design, pose.reshape(1, 6), to_p @ (load * unit_wrench)).refusal[0]
        )
        if code:
            return i, Refusal(code).reason
    return loads.size, None


def moving_deflection(
    design: Design,
    unit_wrench: ArrayLike,
    loads: ArrayLike,
    pose: ArrayLike | None = None,
    method: str = "integrate",
    mode: str = "wrench",
    alpha: float = math.nan,
    tool_point: ArrayLike | None = None,
) -> MovingDeflection:
    """The frozen and the moving-geometry curves under ``L * unit_wrench`` as L grows
    through ``loads`` (module doc; the parameters of
    :func:`~ppm_stiffness.statics.deflection.deflection_path`).

    Each curve covers the loads its model accepts, from the first: the frozen one up to
    the first load :func:`~ppm_stiffness.statics.deflection.deflection_path` refuses
    (an actuator beyond its stroke, a rotation beyond the small-displacement model), the
    moving one up to the first load whose equilibrium is refused.

    Returns
    -------
    MovingDeflection

    Raises
    ------
    InputDataError
        Bad loads, direction, method or mode; ``method="linear"`` (the unloaded K for
        every load), which the moving curve, solved with the actuator law, cannot follow.
    UnreachablePoseError, SingularConfigurationError
        At the unloaded pose.
    """
    if method == "linear":
        raise InputDataError(
            "method 'linear' (the unloaded K for every load) cannot be combined with "
            "moving geometry: the moving curve solves the equilibrium with the actuator "
            "law; use 'integrate' or 'closed-form' (or the frozen curve alone)"
        )
    p = validate_pose(design, pose)
    tool = np.asarray(design.tool_point if tool_point is None else tool_point, dtype=float)
    try:
        frozen = deflection_path(design, unit_wrench, loads, p, method, mode, alpha, tool)
        frozen_stop = None
    except (InputDataError, EquilibriumError):
        w = validate_wrench(unit_wrench)
        x = np.asarray(loads, dtype=float)
        m, why = _frozen_prefix(design, w, x, p, tool)
        if why is None or m == 0:
            raise  # not a load the frozen model refuses: the caller's input
        frozen = deflection_path(design, w, x[:m], p, method, mode, alpha, tool)
        frozen_stop = CurveStop(float(x[m]), why)
    x = np.asarray(loads, dtype=float)
    wrenches = x[:, None] * frozen.unit_wrench[None, :]
    batch = moving_load_states(design, wrenches, p, tool)
    refused = np.flatnonzero(batch.refusal != 0)
    n = int(refused[0]) if refused.size else x.size
    moving_stop = None
    if n < x.size:
        code = Refusal(int(batch.refusal[n]))
        if code in (Refusal.UNREACHABLE, Refusal.SINGULAR):
            raise_moving_refusal(design, batch, n)  # the unloaded pose: raises
        instability = margin = None
        if code in (Refusal.UNSTABLE, Refusal.NO_EQUILIBRIUM):
            margin = load_margin(design, wrenches[n], p, tool)
            if margin.factor is not None:
                instability = margin.factor * float(x[n])
        moving_stop = CurveStop(float(x[n]), code.reason, instability, margin)
    diff = np.array(
        [relative_difference(batch.stiffness[i], batch.frozen_stiffness[i]) for i in range(n)]
    )
    moving = replace(
        frozen,
        loads=x[:n].copy(),
        wrenches=wrenches[:n].copy(),
        twists=batch.twist[:n].copy(),
        actuator_forces=batch.actuator_forces[:n].copy(),
        actuator_stiffness=batch.actuator_stiffness[:n].copy(),
        actuator_displacements=batch.actuator_displacements[:n].copy(),
        method=MOVING_METHOD,
    )
    return MovingDeflection(
        frozen=frozen,
        moving=moving,
        displaced_poses=batch.displaced_poses[:n].copy(),
        stiffness_difference=diff,
        frozen_stop=frozen_stop,
        moving_stop=moving_stop,
        leg_wrenches=batch.leg_wrenches[:n].copy(),
        coordinates=tuple(c[:n].copy() for c in batch.coordinates),
    )


__all__ = ["GEOMETRIES", "MOVING_METHOD", "CurveStop", "MovingDeflection", "moving_deflection"]
