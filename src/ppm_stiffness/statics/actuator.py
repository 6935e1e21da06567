"""The actuator law: a powered voice-coil actuator as a nonlinear spring (eq. 20-21).

Force and displacement follow ``G = k_a * delta**q`` (eq. 20), delta [m] the rod
displacement from its commanded position, G [N], k_a [N/m^q], 0 < q <= 1. The stiffness
(eq. 21) is the locked value below a displacement threshold and the tangent
``q k_a delta**(q-1)`` above it. The law is odd: a pull and a push of the same size
give the same stiffness. ``q = 1`` is a linear spring k_a; a threshold larger than any
displacement makes the actuator constant (locked).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.legs.parts import ActuatorModel

if TYPE_CHECKING:
    from ppm_stiffness.legs.base import LegModel


def displacement_from_force(law: ActuatorModel, force: ArrayLike) -> FloatArray:
    """Displacement magnitude ``(|G| / k_a)**(1/q)`` [m] (inverse of eq. 20)."""
    g = np.abs(np.asarray(force, dtype=float))
    return np.asarray((g / law.k_a) ** (1.0 / law.q))


def stiffness_from_displacement(law: ActuatorModel, displacement: ArrayLike) -> FloatArray:
    """Actuator stiffness [N/m] at a displacement (eq. 21)."""
    delta = np.abs(np.asarray(displacement, dtype=float))
    locked = delta <= law.threshold_displacement
    safe = np.where(locked, 1.0, delta)
    tangent = law.q * law.k_a * safe ** (law.q - 1.0)
    return np.asarray(np.where(locked, law.locked_stiffness, tangent))


def stiffness_from_force(law: ActuatorModel, force: ArrayLike) -> FloatArray:
    """Actuator stiffness [N/m] under an axial force [N] (eq. 20 then 21)."""
    return stiffness_from_displacement(law, displacement_from_force(law, force))


def threshold_force(law: ActuatorModel) -> float:
    """Force at which eq. (21) leaves the locked branch: ``k_a delta_th^q`` [N or N·m]."""
    return float(law.k_a * law.threshold_displacement**law.q)


def actuator_displacement(law: ActuatorModel, force: ArrayLike) -> FloatArray:
    """The actuator displacement under force G: ``delta(G) = int_0^G dG' / K_act(G')``.

    This is the one actuator displacement of the library (loaded state, deflection,
    maps): its derivative is the tangent compliance ``1 / K_act`` of eq. (21)
    everywhere, so a deflection integrated along any load path ends where the
    equilibrium of :mod:`ppm_stiffness.statics.equilibrium` says. ``G / K_locked`` up to
    the threshold force ``G_th``; above it ``G_th / K_locked + (|G|/k_a)^(1/q) -
    delta_th``, with the sign of G. Above the threshold it exceeds the bare law
    ``(G/k_a)^(1/q)`` by ``G_th/K_locked - delta_th`` (20.9 µm for the paper's law):
    eq. (21)'s locked branch and eq. (20) do not describe the same displacement, and
    the bare law is not even monotone at the threshold (docs/actuation.md).

    Parameters
    ----------
    law : ActuatorModel
    force : array_like [N, or N·m for a rotary actuator]

    Returns
    -------
    ndarray, same shape [m, or rad]
    """
    g = np.asarray(force, dtype=float)
    mag = np.abs(g)
    g_th = threshold_force(law)
    locked = mag / law.locked_stiffness
    powered = (
        g_th / law.locked_stiffness + displacement_from_force(law, mag) - law.threshold_displacement
    )
    return np.asarray(np.sign(g) * np.where(mag <= g_th, locked, powered))


def powered_stiffness(law: ActuatorModel, force: ArrayLike) -> FloatArray:
    """The powered branch of eq. (21) at a force, ``q k_a delta^(q-1)`` with the bare
    law's ``delta = (|G|/k_a)^(1/q)``, whatever the threshold [N/m or N·m/rad]."""
    delta = displacement_from_force(law, force)
    safe = np.where(delta > 0, delta, 1.0)
    at_zero = np.inf if law.q < 1 else law.k_a  # the tangent of delta^q at 0
    return np.asarray(np.where(delta > 0, law.q * law.k_a * safe ** (law.q - 1.0), at_zero))


def drive_force(law: ActuatorModel, parallel: float, force: ArrayLike) -> FloatArray:
    """The drive's share G [N or N·m] of a joint force ``tau`` carried by the drive and
    an elastic stiffness ``k_h`` in parallel with it (a flexure hinge resting at the
    unloaded pose): the root of ``G + k_h delta(G) = tau`` (both see the joint's
    displacement ``delta(G)``, :func:`actuator_displacement`); ``tau`` itself for
    ``k_h = 0``.

    ``G + k_h delta(G)`` is odd and strictly increasing (slope ``1 + k_h / K_act``), and
    its root lies between 0 and tau: Newton's method kept inside that bracket
    (bisection where a step leaves it), to a few ulps of tau.

    Parameters
    ----------
    law : ActuatorModel
    parallel : float
        ``k_h`` [N/m or N·m/rad], >= 0.
    force : array_like
        ``tau`` [N or N·m].

    Returns
    -------
    ndarray, the shape of ``force``
    """
    tau = np.asarray(force, dtype=float)
    if parallel == 0.0:
        return tau.copy()
    mag = np.abs(tau)
    lo, hi = np.zeros_like(mag), mag.copy()
    g = mag * law.locked_stiffness / (law.locked_stiffness + parallel)
    for _ in range(200):
        phi = g + parallel * actuator_displacement(law, g) - mag
        lo = np.where(phi <= 0, g, lo)
        hi = np.where(phi >= 0, g, hi)
        if np.all(np.abs(phi) <= 4 * np.finfo(float).eps * np.maximum(mag, 1e-300)):
            break
        step = g - phi / (1.0 + parallel / stiffness_from_force(law, g))
        g = np.where((step > lo) & (step < hi), step, 0.5 * (lo + hi))
    return np.asarray(np.sign(tau) * g)


# -- each leg's law, a passive constraining leg included -------------------------------
# A passive leg (no actuated joint, LegModel.actuator None) has no actuator column: its
# actuator twist is zero, so its "force" is exactly 0, its displacement 0 and its
# stiffness inf (1/inf = 0: it enters no compliance). These keep every loaded path's
# per-leg arrays (n_legs,) without a special case.


def leg_displacement(leg: LegModel, force: ArrayLike) -> FloatArray:
    """:func:`actuator_displacement` of the leg's law; 0 for a passive leg [m or rad]."""
    if leg.actuator is None:
        return np.zeros(np.shape(force))
    return actuator_displacement(leg.actuator, force)


def leg_tangent_stiffness(leg: LegModel, force: ArrayLike) -> FloatArray:
    """:func:`stiffness_from_force` of the leg's law; inf for a passive leg."""
    if leg.actuator is None:
        return np.full(np.shape(force), np.inf)
    return stiffness_from_force(leg.actuator, force)


def leg_powered_stiffness(leg: LegModel, force: ArrayLike) -> FloatArray:
    """:func:`powered_stiffness` of the leg's law; inf for a passive leg."""
    if leg.actuator is None:
        return np.full(np.shape(force), np.inf)
    return powered_stiffness(leg.actuator, force)


def leg_threshold_force(leg: LegModel) -> float:
    """:func:`threshold_force` of the leg's law; inf for a passive leg (its zero force
    never leaves the locked branch)."""
    return math.inf if leg.actuator is None else threshold_force(leg.actuator)
