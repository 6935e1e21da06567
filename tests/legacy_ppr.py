"""The P-P-R leg's 22 springs written out by hand, as the project computed them before the
joint-chain builder (``ppm_stiffness/ppr.py`` at the 0.1 layout, kept verbatim in its
spring order; geometry by orthogonal projection, so valid for beta = +-90 deg only).

An independent reference for tests/test_architectures.py: the chain builder must give
the same matrix for the same legs."""

from __future__ import annotations

import numpy as np

from ppm_stiffness.core.beam import cantilever_compliance
from ppm_stiffness.core.conventions import Z_AXIS, rotation_screw, translation_screw
from ppm_stiffness.core.solver import LegSprings


def _unit_planar(angle: float) -> np.ndarray:
    return np.array([np.cos(angle), np.sin(angle), 0.0])


def leg_springs(leg, pose: np.ndarray) -> LegSprings:  # type: ignore[no-untyped-def]
    """Springs of one P-P-R leg (a ``PPRLeg``) at one pose, the pre-chain way."""
    u, w = _unit_planar(leg.alpha), _unit_planar(leg.alpha + leg.beta)
    ang = leg.psi + pose[2]
    r = leg.platform_radius
    d = np.array([-r * np.cos(ang), -r * np.sin(ang), 0.0])
    p_abs = np.array([pose[0], pose[1], 0.0])
    a = np.array([leg.base_point[0], leg.base_point[1], 0.0])
    d_from_a = p_abs + d - a
    rho = d_from_a @ u
    rod = d_from_a @ w - leg.bearing_offset
    c = a + rho * u + leg.bearing_offset * w - p_abs
    b = a + (rho + leg.guide_offset_u) * u + leg.guide_offset_w * w - p_abs
    z = Z_AXIS
    y_b, y_d = np.cross(z, u), np.cross(z, w)
    v = (c - b) / np.linalg.norm(c - b)
    y_c = np.cross(z, v)
    cols = [
        translation_screw(u),
        rotation_screw(u, b),
        rotation_screw(y_b, b),
        rotation_screw(z, b),
        translation_screw(y_b),
        translation_screw(z),
        rotation_screw(v, c),
        rotation_screw(y_c, c),
        rotation_screw(z, c),
        translation_screw(v),
        translation_screw(y_c),
        translation_screw(z),
        rotation_screw(y_d, c),
        rotation_screw(z, c),
        translation_screw(y_d),
        translation_screw(z),
        rotation_screw(w, d),
        rotation_screw(y_d, d),
        rotation_screw(z, d),
        translation_screw(w),
        translation_screw(y_d),
        translation_screw(z),
    ]
    screws = np.stack(cols, axis=-1)
    comp = np.zeros((22, 22))
    comp[0, 0] = 1.0 / leg.actuator.locked_stiffness
    g = leg.guide
    for i, k in enumerate((g.roll, g.pitch, g.yaw, g.lateral, g.vertical), start=1):
        comp[i, i] = 1.0 / k
    comp[6:12, 6:12] = cantilever_compliance(leg.proximal.section(), np.linalg.norm(c - b))
    br = leg.bearing
    for i, k in enumerate(
        (br.tilt_lateral, br.tilt_vertical, br.radial_lateral, br.radial_vertical), start=12
    ):
        comp[i, i] = 1.0 / k
    comp[16:22, 16:22] = cantilever_compliance(leg.distal.section(), rod)
    passive = np.stack([rotation_screw(w, c), translation_screw(w), rotation_screw(z, d)], axis=-1)
    return LegSprings(screws=screws, compliance=comp, passive=passive, actuator_index=0)
