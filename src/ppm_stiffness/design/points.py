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

An axis or direction of a chain leg's joint (``axis``, ``axis2``) or element (a
parallelogram's ``crossbar``), a unit vector in F_b, gets two angle parameters
(``leg1.crank_drive.axis.tilt``):

- ``.tilt`` [rad]: its angle from +z, ``acos(a_z / |a|)`` in [0, pi]; setting it turns
  the axis in its vertical plane, keeping its azimuth and length;
- ``.azimuth`` [rad]: its polar angle about z, ``atan2(a_y, a_x)``; setting it turns the
  axis about z, keeping its tilt and length.

The two commute. A glob over the same axis of several legs keeps a pattern's
symmetry (:mod:`ppm_stiffness.design.axis_globs`). A joint whose axes must stay
perpendicular (a U's ``axis`` and ``axis2``) is refused by the design's own validation
when only one of them is turned (an optimiser takes such a candidate as infeasible).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

from ppm_stiffness.core.errors import DesignError

#: The component parameters of a point, with their units.
COMPONENT_UNITS = {
    "x": "m",
    "y": "m",
    "z": "m",
    "radius": "m",
    "angle": "rad",
    "tilt": "rad",
    "azimuth": "rad",
}
#: The angle parameters of an axis (module doc).
AXIS_COMPONENTS = ("tilt", "azimuth")
#: The dotted field names (last part) of a chain leg's axes and directions.
AXIS_FIELDS = ("axis", "axis2", "crossbar")
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


def is_axis_field(key: str, value: Any, unit: str) -> bool:
    """True for an axis of a chain leg's element (module doc): ``key`` ends in ``axis``,
    ``axis2`` or ``crossbar``, its unit is 1 and ``value`` has 3 numbers."""
    field = key.rsplit(".", 1)[-1]
    return field in AXIS_FIELDS and unit == "1" and isinstance(value, tuple) and len(value) == 3


def axis_component_names(prefix: str) -> list[str]:
    """The angle parameters of an axis named ``prefix``: tilt, azimuth."""
    return [f"{prefix}.{k}" for k in AXIS_COMPONENTS]


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
    if key in ("angle", "azimuth"):
        return math.atan2(p[1], p[0])
    if key == "tilt":
        return math.acos(max(-1.0, min(1.0, p[2] / math.hypot(*p))))
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
    if key in AXIS_COMPONENTS:
        return _turned_axis(p, key, value, name)
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


def _turned_axis(a: list[float], key: str, value: float, name: str) -> list[float]:
    """Axis ``a`` with its tilt or azimuth set (module doc), its length kept."""
    length = math.hypot(*a)
    if length == 0.0:
        raise DesignError(f"{name} = {value:g}: the axis has no direction (length 0)")
    tilt = math.acos(max(-1.0, min(1.0, a[2] / length)))
    horizontal = math.hypot(a[0], a[1])
    if key == "tilt":
        if not 0.0 <= value <= math.pi:
            raise DesignError(f"{name} = {value:g}: a tilt from +z is within [0, pi] rad")
        if horizontal == 0.0 and 0.0 < value < math.pi:
            raise DesignError(
                f"{name} = {value:g}: the axis is along z, its azimuth is undefined; "
                "set its .azimuth after writing the axis off z in the design file"
            )
        tilt = value
    elif horizontal == 0.0:
        raise DesignError(
            f"{name} = {value:g}: the axis is along z (tilt 0 or pi), its azimuth is undefined"
        )
    azimuth = value if key == "azimuth" else math.atan2(a[1], a[0])
    s = math.sin(tilt)
    return [length * s * math.cos(azimuth), length * s * math.sin(azimuth), length * math.cos(tilt)]
