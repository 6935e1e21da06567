"""Plain constants of the conventions that need no numpy: the pose coordinates' names,
units and indices, and the reference actuator load of a map.

Defined here once and re-exported by :mod:`ppm_stiffness.core.pose` and
:mod:`ppm_stiffness.core.conventions`: the command line's argument definitions use them
without importing numpy (``ppm-stiffness COMMAND --help`` stays light; issue 32, item 6,
``tests/test_cold_start.py``).
"""

from __future__ import annotations

#: The six pose coordinates, in order.
POSE_COORDINATES = ("x", "y", "z", "rx", "ry", "rz")
#: SI unit of each pose coordinate.
POSE_UNITS = ("m", "m", "m", "rad", "rad", "rad")
#: Index of each pose coordinate.
POSE_INDEX = {name: i for i, name in enumerate(POSE_COORDINATES)}
#: The planar coordinates (x, y, phi = rz) of a pose, as indices.
PLANAR_INDEX = (0, 1, 5)
#: Pose coordinates that are angles.
ANGLE_COORDINATES = frozenset({"rx", "ry", "rz"})
#: CSV columns of a full pose in the command line's units: pose_x_mm, ..., pose_rz_deg.
POSE_CSV_COLUMNS = tuple(
    f"pose_{n}_deg" if n in ANGLE_COORDINATES else f"pose_{n}_mm" for n in POSE_COORDINATES
)

#: Reference actuator load [N, or N·m for a rotary actuator] that defines a map's "min"
#: actuator state (the tangent stiffness under this load, eq. 21).
DEFAULT_REFERENCE_FORCE = 10.0
