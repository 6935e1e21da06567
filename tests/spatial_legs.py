"""Spatial legs built in code for the leg-level tests (parts of catalogue magnitude)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ppm_stiffness.legs.types.prs import PRSLeg
from ppm_stiffness.legs.types.rps import RPSLeg
from ppm_stiffness.legs.types.ups import UPSLeg

STEEL_TUBE = dict(
    young_modulus=2.1e11,
    shear_modulus=8.1e10,
    area=3.0e-4,
    torsion_constant=2.0e-8,
    inertia_y=1.0e-8,
    inertia_z=1.0e-8,
)
STEEL_ROD = dict(
    young_modulus=2.1e11,
    shear_modulus=8.1e10,
    area=1.2e-4,
    torsion_constant=4.0e-9,
    inertia_y=2.0e-9,
    inertia_z=2.0e-9,
)
LINEAR_ACTUATOR = dict(locked_stiffness=5e7, k_a=5e7, q=1.0, threshold_displacement=0.0)
GUIDE = dict(roll=1e3, pitch=2e3, yaw=2e3, lateral=1e7, vertical=2e7)
UNIVERSAL = dict(radial=1e8, axial=2e8, torsion=1e3)
SPHERICAL = dict(axial=3e8, radial=1.5e8)
REVOLUTE = dict(tilt=4e3, axial=1e7, radial=2e7)


def hexapod_legs(**overrides: Any) -> list[UPSLeg]:
    """Six U-P-S legs: base joints at 150 mm, platform joints at 100 mm, paired."""
    legs = []
    for k in range(3):
        for side in (-1, 1):
            a = np.radians(120 * k + 12 * side)
            b = np.radians(120 * k + 60 - 48 * side)
            fields: dict[str, Any] = dict(
                base_point=(0.15 * np.cos(a), 0.15 * np.sin(a), 0.0),
                platform_point=(0.10 * np.cos(b), 0.10 * np.sin(b), 0.0),
                cylinder_length=0.12,
                stroke=(0.15, 0.40),
                cylinder=STEEL_TUBE,
                rod=STEEL_ROD,
                actuator=LINEAR_ACTUATOR,
                guide=GUIDE,
                base_joint=UNIVERSAL,
                platform_joint=SPHERICAL,
            )
            fields.update(overrides)
            legs.append(UPSLeg(**fields))
    return legs


def tripod_angles(alpha0: float = np.radians(17.0)) -> list[float]:
    return [alpha0 + k * 2 * np.pi / 3 for k in range(3)]


def prs_legs(alpha0: float = np.radians(17.0), **overrides: Any) -> list[PRSLeg]:
    """A symmetric 3-PRS: vertical rails at 200 mm, platform joints at 100 mm,
    tangential revolute axes, links 250 mm."""
    legs = []
    for a in tripod_angles(alpha0):
        c, s = np.cos(a), np.sin(a)
        fields: dict[str, Any] = dict(
            base_point=(0.2 * c, 0.2 * s, 0.0),
            rail_direction=(0.0, 0.0, 1.0),
            revolute_axis=(-s, c, 0.0),
            link_length=0.25,
            platform_point=(0.1 * c, 0.1 * s, 0.0),
            stroke=(-0.5, 0.5),
            link=STEEL_TUBE,
            actuator=LINEAR_ACTUATOR,
            guide=GUIDE,
            carriage_revolute=REVOLUTE,
            platform_joint=SPHERICAL,
        )
        fields.update(overrides)
        legs.append(PRSLeg(**fields))
    return legs


def rps_legs(alpha0: float = np.radians(17.0), **overrides: Any) -> list[RPSLeg]:
    """A symmetric 3-RPS: base revolutes at 200 mm with tangential axes, platform
    joints at 100 mm, cylinders 120 mm."""
    legs = []
    for a in tripod_angles(alpha0):
        c, s = np.cos(a), np.sin(a)
        fields: dict[str, Any] = dict(
            base_point=(0.2 * c, 0.2 * s, 0.0),
            revolute_axis=(-s, c, 0.0),
            cylinder_length=0.12,
            platform_point=(0.1 * c, 0.1 * s, 0.0),
            stroke=(0.13, 0.5),
            cylinder=STEEL_TUBE,
            rod=STEEL_ROD,
            actuator=LINEAR_ACTUATOR,
            guide=GUIDE,
            base_revolute=REVOLUTE,
            platform_joint=SPHERICAL,
        )
        fields.update(overrides)
        legs.append(RPSLeg(**fields))
    return legs
