"""Helpers shared by the tests."""

from __future__ import annotations

from ppm_stiffness.design import Design, default_design, design_from_dict


def wide_design(design: Design | None = None) -> Design:
    """The design (built-in by default) with strokes and rod ranges opened, so that
    poses far from the centre count as reachable."""
    data = (design or default_design()).model_dump()
    for leg in data["legs"]:
        leg["stroke"] = (-1.0, 1.0)
        leg["rod_length_range"] = (1e-4, 1.0)
    return design_from_dict(data)
