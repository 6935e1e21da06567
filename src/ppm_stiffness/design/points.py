"""Scalar design parameters of a leg's points: the components of a point-like vector.

A leg's point fields (a chain leg's joint ``point``, a last link's ``end``, a
parallelogram's ``near`` and ``far``; a preset's ``base_point`` and
``platform_point``) are vectors, [m], in the frame the design file gives them in:
F_b at the home pose for a chain leg's points and a preset's ``base_point``, the
platform frame F_p for a preset's ``platform_point``. Each gets scalar parameters
named after it (``leg1.crank_joint.point.x``):

- ``.x``, ``.y``, ``.z`` [m]: its components (``.z`` only for a 3-vector);
- ``.radius`` [m]: its distance from the z axis; setting it scales x and y alike,
  keeping the polar angle and z;
- ``.angle`` [rad]: its polar angle about z, ``atan2(y, x)``; setting it turns the
  point about z, keeping the radius and z.

Axes and directions (unit vectors: ``axis``, ``crossbar``, ``rail_direction``) are not
points and get no component parameters.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

from ppm_stiffness.core.errors import DesignError

#: The component parameters of a point, with their units.
COMPONENT_UNITS = {"x": "m", "y": "m", "z": "m", "radius": "m", "angle": "rad"}
#: Relative spread within which a glob's matches of one component count as one value
#: (:meth:`~ppm_stiffness.design.schema.Design.parameter`): points turned by a pattern's
#: rotation matrix or written from cos and sin differ in radius by rounding (at most
#: 1.5e-15 relative over the shipped examples: examples/3prs.toml's platform points).
POINT_SPREAD = 1e-14


def is_point_field(key: str, value: Any, unit: str) -> bool:
    """True for a leg's point field: ``key`` (dotted within the leg) ends in ``point``,
    ``_point``, ``end``, ``near`` or ``far``, its unit is m and ``value`` has 2 or 3
    numbers (a stroke or a length range, also 2 numbers in m, is not a point)."""
    field = key.rsplit(".", 1)[-1]
    named = field == "point" or field.endswith("_point") or field in ("end", "near", "far")
    return named and unit == "m" and isinstance(value, tuple) and len(value) in (2, 3)


def component_names(prefix: str, value: tuple[float, ...]) -> list[str]:
    """The component parameters of a point ``value`` named ``prefix``
    (``leg1.crank_joint.point``): x, y (z for a 3-vector), radius, angle."""
    keys = ("x", "y", "z")[: len(value)] + ("radius", "angle")
    return [f"{prefix}.{k}" for k in keys]


def split_component(name: str) -> tuple[str, str] | None:
    """``(point name, component)`` of a component parameter name, None otherwise."""
    head, _, last = name.rpartition(".")
    return (head, last) if head and last in COMPONENT_UNITS else None


def component(point: Iterable[float], key: str) -> float:
    """Component ``key`` (x, y, z, radius, angle) of ``point`` [m, rad]."""
    p = [float(v) for v in point]
    if key == "radius":
        return math.hypot(p[0], p[1])
    if key == "angle":
        return math.atan2(p[1], p[0])
    return p["xyz".index(key)]


def with_component(point: Iterable[float], key: str, value: float, name: str) -> list[float]:
    """``point`` with component ``key`` set to ``value`` (module doc).

    Raises
    ------
    DesignError
        A negative or non-finite radius, a non-finite value, or a radius or angle set on
        a point on the z axis (its polar angle is undefined there): naming ``name``.
    """
    p = [float(v) for v in point]
    if not math.isfinite(value):
        raise DesignError(f"{name} = {value:g}: a finite number")
    if key in ("x", "y", "z"):
        p["xyz".index(key)] = value
        return p
    radius = math.hypot(p[0], p[1])
    if key == "radius" and value < 0:
        raise DesignError(f"{name} = {value:g}: a radius (distance from the z axis) is >= 0 m")
    if radius == 0.0:
        raise DesignError(
            f"{name} = {value:g}: the point is on the z axis (radius 0), its polar angle "
            "is undefined; set its .x and .y"
        )
    if key == "radius":
        p[0], p[1] = p[0] * (value / radius), p[1] * (value / radius)
    else:
        p[0], p[1] = radius * math.cos(value), radius * math.sin(value)
    return p
