"""Cantilever beams as 6x6 tip compliances (paper eq. 3c, read as a compliance).

Eq. (3c) is printed as a stiffness ``K_s(l)`` but its entries (L/EA, L^3/3EI, ...) are
the tip compliance of a cantilever: the beam is clamped at its root, its axis is the
local x axis running from root to tip, and the local frame sits at the tip. The
components are ordered as twists and wrenches (``conventions``): the compliance maps
the tip wrench ``(m_x, m_y, m_z, f_x, f_y, f_z)`` to the tip twist
``(phi_x, phi_y, phi_z, u_x, u_y, u_z)``. Euler-Bernoulli theory, no shear.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.conventions import FloatArray


@dataclass(frozen=True)
class BeamSection:
    """Material and cross-section of a straight prismatic beam (SI).

    Attributes
    ----------
    young_modulus, shear_modulus : float
        E and G [Pa].
    area : float
        Cross-section area A [m^2].
    torsion_constant : float
        I_x, the polar moment used for torsion [m^4].
    inertia_y, inertia_z : float
        Second moments of area about the local y and z axes [m^4].
    """

    young_modulus: float
    shear_modulus: float
    area: float
    torsion_constant: float
    inertia_y: float
    inertia_z: float


def cantilever_compliance(section: BeamSection, length: ArrayLike) -> FloatArray:
    """Tip compliance of a cantilever in its local tip frame (eq. 3c).

    Parameters
    ----------
    section : BeamSection
    length : array_like, shape (...)
        Free length L of the beam [m].

    Returns
    -------
    ndarray, shape (..., 6, 6)
        Symmetric compliance [rad/(N·m), rad/N, m/N] in the order of ``conventions``.
    """
    L = np.asarray(length, dtype=float)
    e, g = section.young_modulus, section.shear_modulus
    ei_y = e * section.inertia_y
    ei_z = e * section.inertia_z
    out = np.zeros(L.shape + (6, 6))
    out[..., 0, 0] = L / (g * section.torsion_constant)
    out[..., 1, 1] = L / ei_y
    out[..., 2, 2] = L / ei_z
    out[..., 3, 3] = L / (e * section.area)
    out[..., 4, 4] = L**3 / (3.0 * ei_z)
    out[..., 5, 5] = L**3 / (3.0 * ei_y)
    out[..., 2, 4] = out[..., 4, 2] = L**2 / (2.0 * ei_z)
    out[..., 1, 5] = out[..., 5, 1] = -(L**2) / (2.0 * ei_y)
    return out
