"""An axis angle set by a glob over a pattern's copies (``leg*.crank_drive.axis.tilt``).

A leg ``pattern`` (:meth:`~ppm_stiffness.legs.types.chain_leg.ChainLegModel.pattern_copies`)
writes one leg and its copies: each copy is the leg turned about z (``R``), or mirrored
(``M``: y -> -y) and turned. A point or a direction of the copy is ``R M x``; a
revolute's axis, an axial vector, is ``-R M a`` in a mirrored copy. One tilt for every
copy would therefore not be the pattern edited: the mirror image of a tilt t is pi - t.

A glob over the same axis of several legs sets the first match's angle (as
:func:`~ppm_stiffness.design.points.with_component` does) and moves every other match as
its copy: its map from the first leg (turn, or mirror and turn) is found from the two
legs' points, and checked on the axis itself. Legs that are not such copies of the first
(one of them edited by hand, say) are refused: there is no symmetry to keep.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ppm_stiffness.core.conventions import FloatArray, rotation_z
from ppm_stiffness.core.errors import DesignError

#: The mirror of a pattern (y -> -y).
MIRROR = np.diag([1.0, -1.0, 1.0])
#: Largest relative mismatch [1] of a copy's points and axis with the first leg's image
#: (copies are written by rotation matrices: round-off only).
COPY_TOLERANCE = 1e-9


@dataclass(frozen=True)
class AxisOfLeg:
    """One match of an axis glob.

    Attributes
    ----------
    axis : ndarray (3,)
        The axis as written [1], F_b.
    points : ndarray (k, 3) [m]
        The leg's points (every 3-vector point field, in the leg's order), F_b.
    axial : bool
        A revolute's axis (mirrored as ``-M a``), not a direction (``M a``).
    """

    axis: FloatArray
    points: FloatArray
    axial: bool


def copy_maps(first: FloatArray, other: FloatArray) -> list[tuple[FloatArray, bool]]:
    """The maps ``(T, mirrored)`` with ``other = first @ T.T`` (T = R or R M), each leg's
    points (k, 3) [m]; empty when ``other`` is no turned or mirrored copy of ``first``."""
    out = []
    scale = max(float(np.max(np.abs(first), initial=0.0)), 1e-300)
    for mirrored in (False, True):
        source = first @ MIRROR if mirrored else first
        j = int(np.argmax(np.hypot(source[:, 0], source[:, 1])))
        turn = float(np.arctan2(other[j, 1], other[j, 0]) - np.arctan2(source[j, 1], source[j, 0]))
        t = rotation_z(turn) @ (MIRROR if mirrored else np.eye(3))
        if np.max(np.abs(first @ t.T - other)) <= COPY_TOLERANCE * scale:
            out.append((np.asarray(t), mirrored))
    return out


def copies_of_first(
    matches: Sequence[AxisOfLeg], first_axis: FloatArray, names: Sequence[str]
) -> list[list[float]]:
    """Every match's axis when the first match's axis becomes ``first_axis`` (3,),
    each other one its copy's image (module doc).

    Raises
    ------
    DesignError
        A match that is not a copy of the first leg, naming it.
    """
    first = matches[0]
    out = [np.asarray(first_axis, dtype=float).tolist()]
    for match, name in zip(matches[1:], names[1:], strict=True):
        image = None
        for t, mirrored in copy_maps(first.points, match.points):
            sign = -1.0 if mirrored and first.axial else 1.0
            if np.max(np.abs(sign * t @ first.axis - match.axis)) <= COPY_TOLERANCE:
                image = sign * t @ np.asarray(first_axis, dtype=float)
                break
        if image is None:
            raise DesignError(
                f"{name}: this leg is not a turned or mirrored copy of the first match's, "
                f"so a glob has no symmetry to keep; set each axis by its own name "
                f"(legN.JOINT.axis.tilt)"
            )
        out.append(image.tolist())
    return out
