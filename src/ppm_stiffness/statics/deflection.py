"""Deflection of the loaded platform along a growing load, actuators' law in the loop.

A load grows from zero along a fixed direction, ``w(L) = L * w_hat`` (``L`` in N or
N·m, ``w_hat`` the wrench of a unit load). The platform twist follows from

    dt/dL = K(k_act(L))^{-1} w_hat,        t(0) = 0,

where ``K`` is the model's stiffness (:mod:`ppm_stiffness.model`, geometry fixed at the
unloaded pose) with each actuator at its tangent stiffness (eq. 21) under its current
force ``G_i(L) = L * (B w_hat)_i`` (:func:`ppm_stiffness.statics.loading.actuator_forces`; the
3-PPR's in-plane statics are determinate, so ``B`` does not depend on the stiffnesses).
The right-hand side jumps where an actuator leaves its locked branch; the load axis is
cut there and each piece is integrated with an adaptive 8th-order Runge-Kutta scheme
(``scipy.integrate.solve_ivp``, DOP853).

Closed form. With the geometry fixed and determinate forces, the compliance is affine
in the actuator compliances, ``C(k) = C_s + B^T diag(1/k) B`` (``C_s``: actuators rigid;
``B^T`` column i: the platform twist per unit actuator displacement, by reciprocity),
so the path integrates exactly to

    t(L) = C_s w(L) + B^T delta(B w(L)),

with ``delta(G)`` the actuator displacement :func:`actuator_displacement`, the integral
of the tangent compliance ``1/K_act`` along the force path. Below the locked
threshold this is ``G / K_locked``; above, ``G_th / K_locked + (G/k_a)^(1/q) - delta_th``
(``G_th = k_a delta_th^q`` the force at the threshold). Above the threshold it
exceeds the bare law ``(G/k_a)^(1/q)`` by the constant ``G_th/K_locked - delta_th``
(20.9 µm for the paper's values: 2.99 N on the locked 1.1108e5 N/m is 26.9 µm, while
eq. 20 reaches 2.99 N at 6 µm). Eq. (21)'s locked branch and eq. (20) do not describe
the same displacement; a tangent-stiffness model can only be consistent with the
first. See docs/actuation.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.core.errors import InputDataError
from ppm_stiffness.core.solver import bordered_stiffness, leg_compliance_at_platform
from ppm_stiffness.design import ActuatorModel, Design
from ppm_stiffness.model import (
    actuator_stiffness_vector,
    check_nonsingular,
    leg_springs_at_pose,
    workspace_centre,
)
from ppm_stiffness.statics import actuator as act
from ppm_stiffness.statics.loading import (
    actuator_forces,
    check_actuator_travel,
    check_small_rotation,
    validate_wrench,
)

#: The loading modes of the paper's Fig. 9, plus an arbitrary proportional wrench.
MODES = ("planar-force", "moment", "vertical-force")
#: Unit of the load for each mode ("wrench": a dimensionless scale of a given wrench).
LOAD_UNITS = {"planar-force": "N", "moment": "N·m", "vertical-force": "N", "wrench": "1"}
#: Ways to compute the path: the integral of the tangent compliance, its closed form,
#: or one linearisation at zero load (every actuator locked, the paper's matrix 22).
METHODS = ("integrate", "closed-form", "linear")

#: Relative tolerance of the path integration (DOP853).
INTEGRATION_RTOL = 1e-10


def mode_wrench(mode: str, alpha: float = math.pi / 4) -> FloatArray:
    """Wrench of a unit load of a Fig. 9 mode, (m_x, m_y, m_z, f_x, f_y, f_z).

    Parameters
    ----------
    mode : {"planar-force", "moment", "vertical-force"}
        planar force ``f_xy (cos alpha, sin alpha)`` at P; pure moment ``m_z``;
        vertical force ``f_z`` at P.
    alpha : float
        Direction of the planar force in the xy plane of F_b [rad].

    Returns
    -------
    ndarray, shape (6,) [N·m per unit load, N per unit load]
    """
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
        raise InputDataError(f"unknown loading mode {mode!r}; expected one of {MODES}")
    return w


def threshold_force(law: ActuatorModel) -> float:
    """Force [N] at which eq. (21) leaves the locked branch: ``k_a delta_th^q``."""
    return float(law.k_a * law.threshold_displacement**law.q)


def actuator_displacement(law: ActuatorModel, force: ArrayLike) -> FloatArray:
    """Signed actuator displacement [m] under force [N]: ``int_0^G dG' / K_act(G')``.

    ``G / K_locked`` up to the threshold force ``G_th``; above it
    ``G_th / K_locked + (|G|/k_a)^(1/q) - delta_th``, with the sign of ``G``. The
    derivative is the tangent compliance ``1 / K_act`` of eq. (21) everywhere.
    """
    g = np.asarray(force, dtype=float)
    mag = np.abs(g)
    g_th = threshold_force(law)
    locked = mag / law.locked_stiffness
    powered = (
        g_th / law.locked_stiffness
        + act.displacement_from_force(law, mag)
        - law.threshold_displacement
    )
    return np.asarray(np.sign(g) * np.where(mag <= g_th, locked, powered))


@dataclass(frozen=True)
class LinearStructure:
    """The linear parts of the deflection at a pose.

    Attributes
    ----------
    structural_compliance : ndarray, shape (6, 6)
        ``C_s``, the platform compliance with rigid actuators [rad/(N·m), rad/N, m/N].
    force_influence : ndarray, shape (n_legs, 6)
        ``B``: actuator forces [N] per unit wrench, ``G = B w``.
    """

    structural_compliance: FloatArray
    force_influence: FloatArray


class _TangentModel:
    """The model's K at one pose for any actuator stiffness vector (springs built once)."""

    def __init__(self, design: Design, pose: FloatArray) -> None:
        legs = leg_springs_at_pose(design, pose)
        k0 = actuator_stiffness_vector(design, None)
        self._passive = np.stack([leg.passive for leg in legs])
        c6 = np.stack([leg_compliance_at_platform(leg.screws, leg.compliance) for leg in legs])
        self._act = np.stack([leg.screws[:, leg.actuator_index] for leg in legs])
        # J C' J^T of the structure alone: remove the locked actuator's a a^T / k0.
        self._structure = c6 - np.einsum("li,lj->lij", self._act, self._act) / k0[:, None, None]

    def stiffness(self, actuator_stiffness: FloatArray) -> FloatArray:
        c6 = self._structure + (
            np.einsum("li,lj->lij", self._act, self._act) / actuator_stiffness[:, None, None]
        )
        return np.asarray(bordered_stiffness(c6, self._passive).sum(axis=0))


def linear_structure(design: Design, pose: ArrayLike | None = None) -> LinearStructure:
    """``C_s`` and ``B`` at a pose (see the module docstring)."""
    p = workspace_centre(design) if pose is None else np.asarray(pose, dtype=float)
    b = np.array([actuator_forces(design, e, p) for e in np.eye(6)]).T
    k0 = actuator_stiffness_vector(design, None)
    k = _TangentModel(design, p).stiffness(k0)
    check_nonsingular(k)
    c = np.linalg.inv(k)
    c_s = c - b.T @ np.diag(1.0 / k0) @ b
    return LinearStructure(0.5 * (c_s + c_s.T), b)


def closed_form_twist(
    design: Design, wrench: ArrayLike, pose: ArrayLike | None = None
) -> FloatArray:
    """Twist (6,) [rad, m] under ``wrench`` applied from zero: ``C_s w + B^T delta(B w)``.

    Path independent (the forces are determinate), so any loading history that ends
    at ``wrench`` gives this twist.
    """
    w = validate_wrench(wrench)
    lin = linear_structure(design, pose)
    g = lin.force_influence @ w
    return np.asarray(
        lin.structural_compliance @ w
        + lin.force_influence.T @ actuator_displacement(design.actuator, g)
    )


@dataclass(frozen=True)
class DeflectionCurve:
    """Platform deflection along a growing load (SI).

    Attributes
    ----------
    mode : str
        "planar-force", "moment", "vertical-force" or "wrench".
    loads : ndarray, shape (n,)
        Load values [N, N·m, or a scale for "wrench"], increasing, >= 0.
    wrenches : ndarray, shape (n, 6)
        Applied wrench at each load, (m_x, m_y, m_z, f_x, f_y, f_z) [N·m, N].
    twists : ndarray, shape (n, 6)
        Platform twist (phi_x, phi_y, phi_z, x, y, z) [rad, m] at P, axes of F_b.
    actuator_forces : ndarray, shape (n, n_legs)
        Axial actuator forces G_i [N].
    actuator_stiffness : ndarray, shape (n, n_legs)
        Tangent actuator stiffness (eq. 21) [N/m].
    actuator_displacements : ndarray, shape (n, n_legs)
        Signed actuator displacements [m] (:func:`actuator_displacement`).
    unit_wrench : ndarray, shape (6,)
        Wrench per unit load.
    pose : ndarray, shape (3,)
    alpha : float
        Direction of the planar force [rad] (NaN for other modes).
    method : str
        One of :data:`METHODS`.
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

    @property
    def load_unit(self) -> str:
        return LOAD_UNITS.get(self.mode, "1")

    def conjugate_displacement(self) -> FloatArray:
        """Displacement work-conjugate to the load, ``w_hat . t`` (n,) [m or rad]."""
        return np.asarray(self.twists @ self.unit_wrench)


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


def _integrate(
    model: _TangentModel,
    law: ActuatorModel,
    unit_wrench: FloatArray,
    g_unit: FloatArray,
    loads: FloatArray,
    rtol: float,
) -> FloatArray:
    """t(L) at ``loads`` by integrating dt/dL = K(L)^-1 w_hat from L = 0."""

    def rhs(load: float, _t: FloatArray) -> FloatArray:
        k = act.stiffness_from_force(law, load * g_unit)
        return np.asarray(np.linalg.solve(model.stiffness(k), unit_wrench))

    g_th = threshold_force(law)
    top = float(loads[-1])
    cuts = {0.0, top}
    for g in np.abs(g_unit):
        if g > 1e-12 * max(float(np.max(np.abs(g_unit))), 1e-300):
            cut = g_th / g
            if 0.0 < cut < top:
                cuts.add(cut)
    edges = sorted(cuts)
    out = np.zeros((loads.size, 6))
    state = np.zeros(6)
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        inside = (loads > a) & (loads <= b)
        points = np.unique(np.append(loads[inside], b))
        sol = solve_ivp(
            rhs, (a, b), state, method="DOP853", t_eval=points, rtol=rtol, atol=1e-16
        )
        if not sol.success:  # pragma: no cover - DOP853 on a smooth bounded RHS
            raise InputDataError(f"deflection integration failed: {sol.message}")
        out[inside] = sol.y.T[: int(np.count_nonzero(inside))]
        state = sol.y[:, -1]
    return out


def deflection_path(
    design: Design,
    unit_wrench: ArrayLike,
    loads: ArrayLike,
    pose: ArrayLike | None = None,
    method: str = "integrate",
    mode: str = "wrench",
    alpha: float = math.nan,
) -> DeflectionCurve:
    """Deflection under the load ``L * unit_wrench`` as L grows through ``loads``.

    Parameters
    ----------
    design : Design
    unit_wrench : array_like, shape (6,)
        (m_x, m_y, m_z, f_x, f_y, f_z) per unit load, at P, axes of F_b.
    loads : array_like, shape (n,)
        Increasing load values >= 0 (the path always starts at zero load).
    pose : array_like, shape (3,), optional
        (x [m], y [m], phi [rad]); the workspace centre if None.
    method : {"integrate", "closed-form", "linear"}
        See :data:`METHODS` and the module docstring.
    mode, alpha
        Labels stored in the result.

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
    p = workspace_centre(design) if pose is None else np.asarray(pose, dtype=float)
    law = design.actuator
    lin = linear_structure(design, p)
    g_unit = lin.force_influence @ w_hat
    forces = x[:, None] * g_unit[None, :]
    check_actuator_travel(design, actuator_displacement(law, forces[-1:]))
    if method == "integrate":
        twists = _integrate(_TangentModel(design, p), law, w_hat, g_unit, x, INTEGRATION_RTOL)
    elif method == "closed-form":
        twists = (
            x[:, None] * (lin.structural_compliance @ w_hat)[None, :]
            + actuator_displacement(law, forces) @ lin.force_influence
        )
    else:
        k0 = actuator_stiffness_vector(design, None)
        b = lin.force_influence
        c0 = lin.structural_compliance + b.T @ np.diag(1 / k0) @ b
        twists = x[:, None] * (c0 @ w_hat)[None, :]
    check_small_rotation(twists)
    if method == "linear":
        k_act = np.broadcast_to(actuator_stiffness_vector(design, None), forces.shape).copy()
        disp = forces / k_act
    else:
        k_act = act.stiffness_from_force(law, forces)
        disp = actuator_displacement(law, forces)
    return DeflectionCurve(
        mode=mode,
        loads=x,
        wrenches=x[:, None] * w_hat[None, :],
        twists=np.asarray(twists),
        actuator_forces=forces,
        actuator_stiffness=np.asarray(k_act),
        actuator_displacements=np.asarray(disp),
        unit_wrench=w_hat,
        pose=p,
        alpha=alpha,
        method=method,
    )


def deflection_curve(
    design: Design,
    mode: str,
    loads: ArrayLike,
    pose: ArrayLike | None = None,
    alpha: float = math.pi / 4,
    method: str = "integrate",
) -> DeflectionCurve:
    """Deflection along one of the Fig. 9 loading modes.

    Parameters
    ----------
    design : Design
    mode : {"planar-force", "moment", "vertical-force"}
    loads : array_like, shape (n,)
        Increasing loads >= 0 [N, or N·m for "moment"].
    pose : array_like, shape (3,), optional
        Workspace centre if None.
    alpha : float
        Direction of the planar force [rad] (default 45 deg, Fig. 10a).
    method : {"integrate", "closed-form", "linear"}

    Returns
    -------
    DeflectionCurve
    """
    w_hat = mode_wrench(mode, alpha)
    return deflection_path(
        design, w_hat, loads, pose, method, mode, alpha if mode == "planar-force" else math.nan
    )
