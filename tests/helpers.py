"""Helpers shared by the tests."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ppm_stiffness.design import Design, default_design, design_from_dict, load_design
from ppm_stiffness.maps.workspace import workspace_bounds

ROOT = Path(__file__).parents[1]


def design_named(name: str) -> Design:
    """The built-in design ("paper") or ``examples/<name>.toml``."""
    return default_design() if name == "paper" else load_design(ROOT / "examples" / f"{name}.toml")


def poses_around_workspace(
    design: Design, n: int, seed: int, pad: float, phi_max: float
) -> np.ndarray:
    """Seeded random poses (n, 3) over the workspace's box at phi = 0 widened by ``pad``
    of its size on each side, phi uniform in [-phi_max, phi_max]."""
    box = workspace_bounds(design, 0.0)
    margin = pad * np.array([box[1] - box[0], box[3] - box[2]])
    rng = np.random.default_rng(seed)
    return np.column_stack(
        [
            rng.uniform(box[0] - margin[0], box[1] + margin[0], n),
            rng.uniform(box[2] - margin[1], box[3] + margin[1], n),
            rng.uniform(-phi_max, phi_max, n),
        ]
    )


def wide_design(design: Design | None = None) -> Design:
    """The design (built-in by default) with strokes and rod ranges opened, so that
    poses far from the centre count as reachable."""
    data = (design or default_design()).model_dump()
    for leg in data["legs"]:
        leg["stroke"] = (-1.0, 1.0)
        leg["rod_length_range"] = (1e-4, 1.0)
    return design_from_dict(data)
