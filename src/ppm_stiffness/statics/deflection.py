"""Deflection of the loaded platform along a growing load, actuators' law in the loop.

A load grows from zero along a fixed direction, ``w(L) = L * w_hat`` (``L`` in N or
N·m, ``w_hat`` the wrench of a unit load), geometry fixed at the unloaded pose (small
displacements, as in the paper), for any design (planar or spatial; poses are full
6-D poses, :mod:`ppm_stiffness.poses`). The direction is one of the paper's Fig. 9
modes (:data:`MODES`), any wrench direction (mode ``"direction"``,
:func:`direction_wrench`: normalised so that the load is the force's magnitude [N], or
a pure moment's [N·m]), or multiples of a given wrench (mode ``"wrench"``, a
dimensionless scale). Three ways to compute the platform twist t(L):

``"closed-form"``
    the exact equilibrium at each load (:mod:`ppm_stiffness.statics.equilibrium`):
    actuator displacements ``delta(G) = int dG / K_act`` (eq. 20-21) in closed form,
    the actuator forces by Newton's method (directly, for 3-leg designs whose forces
    are statically determinate).
``"integrate"``
    an independent route: the tangent model integrated along the load path,
    ``dt/dL = K(L)^-1 w_hat`` and ``dG_i/dL = a_i . K_i(L) K(L)^-1 w_hat`` (each leg's
    share of the load increment, by its tangent stiffness K_i), with every actuator at
    its tangent stiffness (eq. 21) under its current force. The right-hand side jumps
    where an actuator leaves its locked branch; the integration stops there (an
    event) and restarts, each piece with an adaptive 8th-order Runge-Kutta scheme
    (``scipy.integrate.solve_ivp``, DOP853). It uses neither ``delta(G)`` in closed
    form nor the equilibrium solver, and agrees with them (tests).
``"linear"``
    one linearisation at zero load, every actuator locked (the paper's matrix 22).

The actuator displacement is the integral of the tangent compliance 1/K_act
(:func:`ppm_stiffness.statics.actuator.actuator_displacement`); above the threshold it
exceeds the bare law ``(G/k_a)^(1/q)`` by ``G_th/K_locked - delta_th`` (20.9 µm for
the paper's values). See docs/actuation.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray, twist_b_from_twist_a, wrench_b_from_wrench_a
from ppm_stiffness.core.errors import EquilibriumError, InputDataError
from ppm_stiffness.core.pose import displaced_pose
from ppm_stiffness.design import Design
from ppm_stiffness.model import parallel_stiffnesses, tool_offset, validate_pose
from ppm_stiffness.statics.actuator import (
    actuator_displacement,
    leg_displacement,
    leg_powered_stiffness,
    leg_threshold_force,
    threshold_force,
)
from ppm_stiffness.statics.equilibrium import (
    LegStructures,
    equilibrium,
    tangent_stiffnesses,
)
from ppm_stiffness.statics.loading import (
    check_actuator_travel,
    check_small_rotation,
    validate_wrench,
)
from ppm_stiffness.statics.modes import CURVE_MODES, DIRECTION, METHODS, MODES

__all__ = [
    "CURVE_MODES",
    "DIRECTION",
    "LOAD_UNITS",
    "METHODS",
    "MODES",
    "DeflectionCurve",
    "actuator_displacement",
    "closed_form_twist",
    "deflection_curve",
    "deflection_path",
    "direction_load_unit",
    "direction_wrench",
    "mode_wrench",
    "threshold_force",
]

#: Unit of the load for each mode ("wrench": a dimensionless scale of a given wrench;
#: "direction": N, or N·m for a pure moment, :func:`direction_load_unit`).
LOAD_UNITS = {
    "planar-force": "N",
    "moment": "N·m",
    "vertical-force": "N",
    DIRECTION: "N",
    "wrench": "1",
}

#: Relative tolerance of the path integration (DOP853).
INTEGRATION_RTOL = 1e-10


def direction_wrench(direction: ArrayLike) -> FloatArray:
    """The wrench of a unit load along a direction (6,) (m_x, m_y, m_z, f_x, f_y, f_z).

    Normalised so that the load is the magnitude of the force [N]: ``w / |f|``, the
    moment following in proportion (a force along f with the moment m / |f| per
    newton: e.g. a force applied away from the tool point); a pure moment (f = 0) is
    normalised by its own magnitude, the load then in N·m
    (:func:`direction_load_unit`).

    Raises
    ------
    InputDataError
        Not 6 finite components, or all zero.
    """
    w = validate_wrench(direction)
    force, moment = float(np.linalg.norm(w[3:])), float(np.linalg.norm(w[:3]))
    if force > 0:
        return np.asarray(w / force)
    if moment > 0:
        return np.asarray(w / moment)
    raise InputDataError("a load direction must not be zero (6 components, not all 0)")


def direction_load_unit(unit_wrench: ArrayLike) -> str:
    """Unit of the load along a normalised direction: "N" when it has a force, "N·m"
    for a pure moment (:func:`direction_wrench`)."""
    return "N" if np.any(np.asarray(unit_wrench, dtype=float)[3:] != 0) else "N·m"


def mode_wrench(
    mode: str, alpha: float = math.pi / 4, direction: ArrayLike | None = None
) -> FloatArray:
    """Wrench of a unit load of a mode, (m_x, m_y, m_z, f_x, f_y, f_z).

    Parameters
    ----------
    mode : {"planar-force", "moment", "vertical-force", "direction"}
        planar force ``f_xy (cos alpha, sin alpha)``; pure moment ``m_z``; vertical
        force ``f_z``; or the normalised ``direction`` (:func:`direction_wrench`). The
        axes are those of F_b, for any design.
    alpha : float
        Direction of the planar force in the xy plane of F_b [rad].
    direction : array_like (6,), optional
        (m_x, m_y, m_z, f_x, f_y, f_z), with mode "direction" only.

    Returns
    -------
    ndarray, shape (6,) [N·m per unit load, N per unit load]

    Raises
    ------
    InputDataError
        An unknown mode, a direction with another mode or none with "direction".
    """
    if mode == DIRECTION:
        if direction is None:
            raise InputDataError("mode 'direction' needs a direction (6 wrench components)")
        return direction_wrench(direction)
    if direction is not None:
        raise InputDataError(f"a direction goes with mode {DIRECTION!r}, not {mode!r}")
    w = np.zeros(6)
    if mode == "planar-force":
        if not math.isfinite(alpha):
            raise InputDataError("alpha must be finite")
        w[3], w[4] = math.cos(alpha), math.sin(alpha)
    elif mode == "moment":
        w[2] = 1.0
    elif mode == "vertical-force":
        w[5] = 1.0
    else:
        raise InputDataError(
            f"unknown loading mode {mode!r}; expected one of {MODES + (DIRECTION,)}"
        )
    return w


@dataclass(frozen=True)
class DeflectionCurve:
    """Platform deflection along a growing load (SI).

    Attributes
    ----------
    mode : str
        One of :data:`CURVE_MODES`.
    loads : ndarray, shape (n,)
        Load values [N, N·m, or a scale for "wrench": :attr:`load_unit`], increasing,
        >= 0.
    wrenches : ndarray, shape (n, 6)
        Applied wrench at each load, (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N].
    twists : ndarray, shape (n, 6)
        Platform twist (phi_x, phi_y, phi_z, x, y, z) [rad, m] at the tool point (P by
        default), axes of F_b.
    actuator_forces : ndarray, shape (n, n_legs)
        Axial actuator forces G_i [N].
    actuator_stiffness : ndarray, shape (n, n_legs)
        Tangent actuator stiffness (eq. 21) [N/m].
    actuator_displacements : ndarray, shape (n, n_legs)
        Signed actuator displacements [m] (:func:`actuator_displacement`).
    unit_wrench : ndarray, shape (6,)
        Wrench per unit load (the load direction), applied at the tool point.
    pose : ndarray, shape (6,)
        The unloaded full pose (x, y, z, rx, ry, rz) [m, rad] of P.
    alpha : float
        Direction of the planar force [rad] (NaN for other modes).
    method : str
        One of :data:`METHODS`.
    tool_point : ndarray, shape (3,)
        Where the load acts and the twist is given, platform frame [m].
    planar : bool
        The design is planar (``Design.planar``): its pictures keep the components of
        the paper's modes; a spatial design's show all six.
    task_coordinates : tuple of str
        The design's task coordinates (``Design.task_coordinates``).
    """

    mode: str
    loads: FloatArray
    wrenches: FloatArray
    twists: FloatArray
    actuator_forces: FloatArray
    actuator_stiffness: FloatArray
    actuator_displacements: FloatArray
    unit_wrench: FloatArray
    pose: FloatArray
    alpha: float
    method: str
    tool_point: FloatArray = field(default_factory=lambda: np.zeros(3))
    planar: bool = True
    task_coordinates: tuple[str, ...] = ("x", "y", "rz")

    @property
    def load_unit(self) -> str:
        if self.mode == DIRECTION:
            return direction_load_unit(self.unit_wrench)
        return LOAD_UNITS.get(self.mode, "1")

    def conjugate_displacement(self) -> FloatArray:
        """Displacement work-conjugate to the load, ``w_hat . t`` (n,) [m or rad]."""
        return np.asarray(self.twists @ self.unit_wrench)

    def twists_at_p(self) -> FloatArray:
        """The twists (n, 6) [rad, m] of P (the curve's are the tool point's)."""
        offset = tool_offset(self.pose, self.tool_point)  # tool point - P, axes of F_b
        return np.asarray(self.twists @ twist_b_from_twist_a(np.eye(3), offset).T)

    def loaded_poses(self) -> FloatArray:
        """The pose (n, 6) (x, y, z, rx, ry, rz) [m, rad] of P under each load: the
        unloaded pose moved by the twist of P, ``R' = exp(hat(phi)) R``, ``p' = p + v``
        (:func:`ppm_stiffness.core.pose.displaced_pose`)."""
        return displaced_pose(np.broadcast_to(self.pose, self.twists.shape), self.twists_at_p())


def _validate_loads(loads: ArrayLike) -> FloatArray:
    x = np.asarray(loads, dtype=float)
    if x.ndim != 1 or x.size == 0:
        raise InputDataError(f"loads must be a non-empty 1-D array, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise InputDataError("loads must be finite")
    if np.any(x < 0) or np.any(np.diff(x) <= 0):
        raise InputDataError(
            "loads must be >= 0 and strictly increasing (the load grows from zero; "
            "reverse a direction with alpha or a negative wrench instead)"
        )
    return x


def closed_form_twist(
    design: Design, wrench: ArrayLike, pose: ArrayLike | None = None
) -> FloatArray:
    """Twist (6,) [rad, m] under ``wrench`` applied from zero: the exact equilibrium.

    Path independent (the actuator springs are elastic), so any loading history that
    ends at ``wrench`` gives this twist.
    """
    w = validate_wrench(wrench)
    p = validate_pose(design, pose)
    return equilibrium(design, w, p).twist


def _integrate(
    design: Design,
    structures: LegStructures,
    unit_wrench: FloatArray,
    loads: FloatArray,
    rtol: float,
) -> tuple[FloatArray, FloatArray]:
    """t(L) (n_loads, 6) and G(L) (n_loads, n_legs) by integrating the tangent model."""
    n = structures.n_legs
    g_th = np.array([leg_threshold_force(leg) for leg in design.legs])
    k_h = parallel_stiffnesses(design)

    def rates(state: FloatArray, branch: FloatArray) -> FloatArray:
        g = state[6:]
        # the branch (locked or powered) is fixed within a piece, so the right-hand
        # side is smooth there; it is chosen at the start of each piece
        k = np.array(
            [
                leg_powered_stiffness(leg, g[i]) if branch[i] else leg.locked_stiffness()
                for i, leg in enumerate(design.legs)
            ]
        )
        legs_k = structures.leg_stiffnesses(k)
        dt = np.linalg.solve(legs_k.sum(axis=0), unit_wrench)
        # the joint's load increment, of which a drive takes k / (k + k_h)
        dg = np.einsum("li,lij,j->l", structures.actuator, legs_k, dt) * _share(k, k_h)
        return np.concatenate([dt, dg])

    def crossing(i: int, powered: bool) -> object:
        """Event: actuator i's force leaves its branch (|G| falls below the threshold
        when powered, rises above it when locked). The direction makes an event that
        starts at zero, an actuator just switched, fire only on its next crossing."""

        def event(_load: float, state: FloatArray, *_args: object) -> float:
            return float(abs(state[6 + i]) - g_th[i])

        event.terminal = True  # type: ignore[attr-defined]
        event.direction = -1.0 if powered else 1.0  # type: ignore[attr-defined]
        return event

    top = float(loads[-1])
    out_t = np.zeros((loads.size, 6))
    out_g = np.zeros((loads.size, n))
    state = np.zeros(6 + n)
    start = 0.0
    for _ in range(4 * n + 4):
        # an actuator with no locked range (threshold 0) is powered once loaded
        powered = (np.abs(state[6:]) > g_th * (1 + 1e-12)) | (g_th == 0)
        # an actuator sitting at its threshold: powered if its force is growing
        at_edge = np.isclose(np.abs(state[6:]), g_th, rtol=1e-9, atol=0.0) & (g_th > 0)
        if np.any(at_edge):
            grow = rates(state, powered)[6:] * np.sign(state[6:])
            powered = powered | (at_edge & (grow > 0))
        events = [crossing(i, bool(powered[i])) for i in range(n) if g_th[i] > 0]
        from scipy.integrate import solve_ivp  # lazily: scipy is heavy to import

        sol = solve_ivp(
            lambda _load, y, branch: rates(y, branch),
            (start, top),
            state,
            method="DOP853",
            args=(powered,),
            rtol=rtol,
            atol=1e-16,
            events=events or None,
            dense_output=True,
        )
        if not sol.success:  # pragma: no cover - DOP853 on a smooth bounded RHS
            raise InputDataError(f"deflection integration failed: {sol.message}")
        end = float(sol.t[-1])
        inside = (loads > start) & (loads <= end)
        if np.any(inside):
            values = sol.sol(loads[inside])
            out_t[inside] = values[:6].T
            out_g[inside] = values[6:].T
        state = sol.y[:, -1]
        start = end
        if end >= top:
            return out_t, out_g
    raise InputDataError("deflection integration: too many actuator branch changes")


def _share(k_act: FloatArray, k_h: FloatArray) -> FloatArray:
    """A drive's share ``k_act / (k_act + k_h)`` of its joint's load increment (1
    without a flexure in parallel, a passive leg's ``inf`` included)."""
    with np.errstate(invalid="ignore"):
        return np.asarray(np.where(k_h > 0, k_act / (k_act + k_h), 1.0))


def deflection_path(
    design: Design,
    unit_wrench: ArrayLike,
    loads: ArrayLike,
    pose: ArrayLike | None = None,
    method: str = "integrate",
    mode: str = "wrench",
    alpha: float = math.nan,
    tool_point: ArrayLike | None = None,
) -> DeflectionCurve:
    """Deflection under the load ``L * unit_wrench`` as L grows through ``loads``.

    Parameters
    ----------
    design : Design
    unit_wrench : array_like, shape (6,)
        (m_x, m_y, m_z, f_x, f_y, f_z) per unit load, axes of F_b, acting at the tool
        point (P by default).
    loads : array_like, shape (n,)
        Increasing load values >= 0 (the path always starts at zero load).
    pose : array_like, shape (n_task,) or (6,), optional
        The design's task coordinates or a full pose [m, rad]
        (:mod:`ppm_stiffness.poses`); the home pose if None.
    method : {"integrate", "closed-form", "linear"}
        See :data:`METHODS` and the module docstring.
    mode, alpha
        Labels stored in the result (``mode`` one of :data:`CURVE_MODES`).
    tool_point : array_like, shape (3,), optional
        Platform frame [m]: the load acts there and the twists are given there;
        ``design.tool_point`` if None.

    Returns
    -------
    DeflectionCurve

    Raises
    ------
    InputDataError, UnreachablePoseError, SingularConfigurationError
    """
    w_hat = validate_wrench(unit_wrench)
    x = _validate_loads(loads)
    if method not in METHODS:
        raise InputDataError(f"unknown method {method!r}; expected one of {METHODS}")
    if mode not in CURVE_MODES:
        raise InputDataError(f"unknown loading mode {mode!r}; expected one of {CURVE_MODES}")
    p = validate_pose(design, pose)
    tool = np.asarray(design.tool_point if tool_point is None else tool_point, dtype=float)
    offset = tool_offset(p, tool)
    w_tool = w_hat
    w_hat = wrench_b_from_wrench_a(np.eye(3), offset) @ w_tool  # the same load, at P
    to_tool = twist_b_from_twist_a(np.eye(3), -offset)
    structures = LegStructures(design, p)
    locked = np.array([leg.locked_stiffness() for leg in design.legs])
    if method == "linear":
        legs_k = structures.leg_stiffnesses(locked)
        c0 = np.linalg.inv(legs_k.sum(axis=0))
        t_unit = c0 @ w_hat
        g_unit = np.einsum("li,lij,j->l", structures.actuator, legs_k, t_unit)
        g_unit = g_unit * _share(locked, parallel_stiffnesses(design))  # the drives' shares
        twists = x[:, None] * t_unit[None, :]
        forces = x[:, None] * g_unit[None, :]
        k_act = np.broadcast_to(locked, forces.shape).copy()
        disp = forces / k_act
    else:
        # the top load first: refuse a load beyond the strokes before integrating
        top = equilibrium(design, x[-1] * w_hat, p, structures)
        check_actuator_travel(design, top.actuator_displacements)
        check_small_rotation(top.twist)
        if method == "integrate":
            twists, forces = _integrate(design, structures, w_hat, x, INTEGRATION_RTOL)
            # the path must end at the equilibrium of the top load (an independent
            # solution): a branch missed along the way would show here
            off = np.max(np.abs(twists[-1] - top.twist))
            if not off <= 1e-6 * max(float(np.max(np.abs(top.twist))), 1e-300):
                raise EquilibriumError(
                    "deflection integration ended off the equilibrium of the top load "
                    f"(by {off:.3g}); use --method closed-form"
                )
        else:
            states = [equilibrium(design, load * w_hat, p, structures) for load in x]
            twists = np.array([e.twist for e in states])
            forces = np.array([e.actuator_forces for e in states])
        k_act = tangent_stiffnesses(design, forces)
        disp = np.stack(
            [leg_displacement(leg, forces[:, i]) for i, leg in enumerate(design.legs)],
            axis=-1,
        )
    check_actuator_travel(design, disp)
    check_small_rotation(twists)
    return DeflectionCurve(
        mode=mode,
        loads=x,
        wrenches=x[:, None] * w_tool[None, :],
        twists=np.asarray(twists) @ to_tool.T,
        actuator_forces=np.asarray(forces),
        actuator_stiffness=np.asarray(k_act),
        actuator_displacements=np.asarray(disp),
        unit_wrench=w_tool,
        pose=p,
        alpha=alpha,
        method=method,
        tool_point=tool,
        planar=design.planar,
        task_coordinates=tuple(design.task_coordinates),
    )


def deflection_curve(
    design: Design,
    mode: str,
    loads: ArrayLike,
    pose: ArrayLike | None = None,
    alpha: float = math.pi / 4,
    method: str = "integrate",
    tool_point: ArrayLike | None = None,
    direction: ArrayLike | None = None,
) -> DeflectionCurve:
    """Deflection along one of the Fig. 9 loading modes, or along a direction.

    Parameters
    ----------
    design : Design
        Any design; the modes' wrenches are in the axes of F_b at the tool point.
    mode : {"planar-force", "moment", "vertical-force", "direction"}
    loads : array_like, shape (n,)
        Increasing loads >= 0 [N, or N·m for "moment" and a pure-moment direction].
    pose : array_like, shape (n_task,) or (6,), optional
        Task coordinates or a full pose [m, rad]; the home pose if None.
    alpha : float
        Direction of the planar force [rad] (default 45 deg, Fig. 10a).
    method : {"integrate", "closed-form", "linear"}
    tool_point : array_like (3,), optional
        Platform frame [m]; ``design.tool_point`` if None.
    direction : array_like (6,), optional
        With mode "direction": (m_x, m_y, m_z, f_x, f_y, f_z) in any scale, normalised
        by :func:`direction_wrench`.

    Returns
    -------
    DeflectionCurve

    Raises
    ------
    InputDataError
        An unknown mode, a direction that is zero or does not go with the mode, bad
        loads (:func:`deflection_path`).
    """
    w_hat = mode_wrench(mode, alpha, direction)
    return deflection_path(
        design,
        w_hat,
        loads,
        pose,
        method,
        mode,
        alpha if mode == "planar-force" else math.nan,
        tool_point,
    )
