"""Tables of joint-list legs (``type = "chain"``, docs/legs.md) as the presets write
them (:meth:`ppm_stiffness.legs.base.LegModel.joint_list`): one writer per element, so
that every preset spells a joint, a link and the leg the same way (a private module:
the leg registry skips it). Points in F_b at the design's home pose [m]."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike


def home_points(leg: Any, home: ArrayLike) -> tuple[dict[str, Any], dict[str, float]]:
    """A preset leg at the design's home pose (6,): its points [m] in F_b (name -> (3,))
    and its scalar coordinates (name -> value [m or rad]), from its own solve."""
    h = np.asarray(home, dtype=float)
    at_home = leg.solve(h)
    points = {k: np.reshape(v, 3) + h[:3] for k, v in at_home.points.items()}
    coordinates = {
        k: float(np.reshape(v, -1)[0]) for k, v in at_home.coordinates.items() if np.size(v) == 1
    }
    return points, coordinates


def part_table(part: Any) -> dict[str, Any]:
    """A part's design-file table (its fields that are set)."""
    return dict(part.model_dump(exclude_none=True))


def joint_table(
    kind: str, name: str, point: ArrayLike, springs: Any = None, **keys: Any
) -> dict[str, Any]:
    """A joint element: its kind, name, point [m] and further keys (``axis``, ``axis2``,
    ``actuated``, ``stroke``, ``mounting_axis``), its springs' table when it has
    springs (rigid in its constrained directions without)."""
    xyz = np.asarray(point, dtype=float).reshape(3)
    out: dict[str, Any] = {"joint": kind, "name": name, "point": xyz.tolist()}
    out.update(keys)
    if springs is not None:
        out["springs"] = part_table(springs)
    return out


def link_table(section: Any, name: str) -> dict[str, Any]:
    """A beam link element (its section's table)."""
    return {"link": part_table(section), "name": name}


def chain_table(actuator: Any, elements: list[dict[str, Any]]) -> dict[str, Any]:
    """The leg's table: its actuator law and its elements, base to platform."""
    return {"type": "chain", "actuator": part_table(actuator), "elements": elements}


__all__ = ["chain_table", "home_points", "joint_table", "link_table", "part_table"]
