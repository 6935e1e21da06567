"""The actuator law: a powered voice-coil actuator as a nonlinear spring (eq. 20-21).

Force and displacement follow ``G = k_a * delta**q`` (eq. 20), delta [m] the rod
displacement from its commanded position, G [N], k_a [N/m^q], 0 < q <= 1. The stiffness
(eq. 21) is the locked value below a displacement threshold and the tangent
``q k_a delta**(q-1)`` above it. The law is odd: a pull and a push of the same size
give the same stiffness. ``q = 1`` is a linear spring k_a; a threshold larger than any
displacement makes the actuator constant (locked).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray
from ppm_stiffness.design import ActuatorModel


def displacement_from_force(law: ActuatorModel, force: ArrayLike) -> FloatArray:
    """Displacement magnitude ``(|G| / k_a)**(1/q)`` [m] (inverse of eq. 20)."""
    g = np.abs(np.asarray(force, dtype=float))
    return np.asarray((g / law.k_a) ** (1.0 / law.q))


def force_from_displacement(law: ActuatorModel, displacement: ArrayLike) -> FloatArray:
    """Force magnitude ``k_a |delta|**q`` [N] (eq. 20)."""
    return np.asarray(law.k_a * np.abs(np.asarray(displacement, dtype=float)) ** law.q)


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
