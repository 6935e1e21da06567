"""Geometry of P-P-R legs: inverse kinematics and virtual springs at a pose.

This is the only module that knows a leg is P-P-R (actuated prismatic on a linear
guide, passive prismatic rod sliding in a bearing, revolute at the platform). It
turns a :class:`~ppm_stiffness.design.Design` and poses into
:class:`~ppm_stiffness.core.solver.LegSprings`. Functions take poses as arrays of shape
(..., 3) = (x [m], y [m], phi [rad]) in F_b, so one call serves one pose or a map.

Spring order in each leg (columns of ``screws``), following the paper's appendix:
0 actuator along u; 1-5 guide at B (roll u, pitch y_B, yaw z, lateral y_B,
vertical z); 6-11 proximal link, cantilever from B with its tip frame at C
(axes v, y_C, z); 12-15 bearing at C (tilt y_D, tilt z, radial y_D, radial z);
16-21 distal rod, cantilever from C with its tip frame at D (axes w, y_D, z).
Passive joints: cylindrical at C along w (rotation and translation), revolute at D.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ppm_stiffness.core.beam import cantilever_compliance
from ppm_stiffness.core.conventions import Z_AXIS, FloatArray, rotation_screw, translation_screw
from ppm_stiffness.core.errors import UnreachablePoseError
from ppm_stiffness.core.solver import LegSprings
from ppm_stiffness.design import Design, PPRLegModel

N_SPRINGS = 22


@dataclass(frozen=True)
class PPRLegGeometry:
    """Points (relative to P, axes of F_b, [m]) and joint values of one leg.

    All arrays have the batch shape of the poses, plus a trailing 3 for vectors.
    """

    u: FloatArray
    w: FloatArray
    b: FloatArray
    c: FloatArray
    d: FloatArray
    actuator_coordinate: FloatArray
    rod_length: FloatArray
    proximal_length: FloatArray
    reachable: FloatArray


def _unit_planar(angle: float) -> FloatArray:
    return np.array([np.cos(angle), np.sin(angle), 0.0])


def leg_directions(leg: PPRLegModel) -> tuple[FloatArray, FloatArray]:
    """Rail direction u and rod direction w of a leg (unit, F_b)."""
    return _unit_planar(leg.alpha), _unit_planar(leg.alpha + leg.beta)


def platform_point(leg: PPRLegModel, phi: ArrayLike) -> FloatArray:
    """Platform point D relative to P in F_b at orientation ``phi``; shape (..., 3)."""
    ph = np.asarray(phi, dtype=float)
    ang = leg.psi + ph
    r = leg.platform_radius
    return np.stack([-r * np.cos(ang), -r * np.sin(ang), np.zeros_like(ang)], axis=-1)


def leg_geometry(leg: PPRLegModel, poses: ArrayLike) -> PPRLegGeometry:
    """Inverse kinematics of one P-P-R leg for poses (..., 3)."""
    pose = np.asarray(poses, dtype=float)
    u, w = leg_directions(leg)
    d = platform_point(leg, pose[..., 2])
    p_abs = np.stack([pose[..., 0], pose[..., 1], np.zeros(pose.shape[:-1])], axis=-1)
    a = np.array([leg.base_point[0], leg.base_point[1], 0.0])
    d_from_a = p_abs + d - a
    rho = d_from_a @ u
    rod = d_from_a @ w - leg.bearing_offset
    # C and B relative to P
    c = a + rho[..., None] * u + leg.bearing_offset * w - p_abs
    b = a + (rho[..., None] + leg.guide_offset_u) * u + leg.guide_offset_w * w - p_abs
    prox = np.linalg.norm(c - b, axis=-1)
    reachable = (
        (rho >= leg.stroke[0])
        & (rho <= leg.stroke[1])
        & (rod >= leg.rod_length_range[0])
        & (rod <= leg.rod_length_range[1])
    )
    return PPRLegGeometry(u, w, b, c, d, rho, rod, prox, reachable)


def leg_springs(
    design: Design, leg: PPRLegModel, geometry: PPRLegGeometry, actuator_stiffness: ArrayLike
) -> LegSprings:
    """Virtual springs of one leg at the poses of ``geometry``.

    Parameters
    ----------
    design : Design
        Supplies the guide, bearing and link properties.
    leg : PPRLegModel
    geometry : PPRLegGeometry
        From :func:`leg_geometry`; unreachable poses still give finite arrays as long
        as the proximal and rod lengths are positive.
    actuator_stiffness : array_like, shape broadcastable to the batch shape [N/m]

    Returns
    -------
    LegSprings
        screws (..., 6, 22), compliance (..., 22, 22), passive (..., 6, 3).
    """
    batch = geometry.rod_length.shape
    u = np.broadcast_to(geometry.u, batch + (3,))
    w = np.broadcast_to(geometry.w, batch + (3,))
    z = np.broadcast_to(Z_AXIS, batch + (3,))
    y_b = np.cross(z, u)
    y_d = np.cross(z, w)
    prox = geometry.proximal_length
    v = (geometry.c - geometry.b) / np.where(prox > 0, prox, 1.0)[..., None]
    y_c = np.cross(z, v)
    b, c, d = geometry.b, geometry.c, geometry.d

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

    compliance = np.zeros(batch + (N_SPRINGS, N_SPRINGS))
    k_act = np.broadcast_to(np.asarray(actuator_stiffness, dtype=float), batch)
    compliance[..., 0, 0] = 1.0 / k_act
    g = design.guide
    for i, k in enumerate((g.roll, g.pitch, g.yaw, g.lateral, g.vertical), start=1):
        compliance[..., i, i] = 1.0 / k
    compliance[..., 6:12, 6:12] = cantilever_compliance(design.proximal.section(), prox)
    br = design.bearing
    for i, k in enumerate(
        (br.tilt_lateral, br.tilt_vertical, br.radial_lateral, br.radial_vertical), start=12
    ):
        compliance[..., i, i] = 1.0 / k
    compliance[..., 16:22, 16:22] = cantilever_compliance(
        design.distal.section(), geometry.rod_length
    )
    passive = np.stack(
        [rotation_screw(w, c), translation_screw(w), rotation_screw(z, d)], axis=-1
    )
    return LegSprings(screws=screws, compliance=compliance, passive=passive, actuator_index=0)


def inverse_kinematics(design: Design, poses: ArrayLike) -> list[PPRLegGeometry]:
    """Geometry of every leg at the poses (..., 3); no reachability check."""
    return [leg_geometry(leg, poses) for leg in design.legs]


def check_reachable(design: Design, pose: ArrayLike) -> list[PPRLegGeometry]:
    """Geometry of every leg at one pose, raising if the pose is unreachable."""
    geoms = inverse_kinematics(design, pose)
    for i, (leg, g) in enumerate(zip(design.legs, geoms, strict=True), start=1):
        rho = float(g.actuator_coordinate)
        rod = float(g.rod_length)
        if not leg.stroke[0] <= rho <= leg.stroke[1]:
            raise UnreachablePoseError(
                f"leg {i}: actuator coordinate {rho * 1e3:.2f} mm outside its stroke "
                f"[{leg.stroke[0] * 1e3:.2f}, {leg.stroke[1] * 1e3:.2f}] mm"
            )
        if not leg.rod_length_range[0] <= rod <= leg.rod_length_range[1]:
            raise UnreachablePoseError(
                f"leg {i}: rod free length {rod * 1e3:.2f} mm outside "
                f"[{leg.rod_length_range[0] * 1e3:.2f}, {leg.rod_length_range[1] * 1e3:.2f}] mm"
            )
    return geoms
