"""Masked grid points of the shipped designs' default maps under the previous and the
current singularity test (docs/maps.md, "How the masks changed").

previous: the spread of K, the length-balanced eigenvalue ratio of K at or below 1e-6;
current: the transmission index of core.singularity at or below 1e-6 (or K not finite).
Grid: the map command's defaults (200 x 200 over the workspace bounding box at the
design's workspace phi, locked actuators) for every shipped design, the built-in design
also at phi = 30 deg and over a box 20 % wider, and the rigid-structure limit of the
3-RPR (moduli 1e20 Pa, joint springs 1e13 times stiffer). Last line: key=value counts.
Run: .venv/bin/python scripts/singularity_mask_counts.py
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from ppm_stiffness.core.singularity import transmission_index
from ppm_stiffness.design import Design, default_design, load_design
from ppm_stiffness.maps import batch
from ppm_stiffness.maps.workspace import workspace_bounds, workspace_grid
from ppm_stiffness.model import MATRIX_RATIO_TOLERANCE, eigenvalue_ratio

ROOT = Path(__file__).parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from test_singularity import rigid_structure  # noqa: E402


def counts(design: Design, phi: float, widen: float = 0.0) -> dict[str, float]:
    box = workspace_bounds(design, phi)
    pad = widen * np.array([box[1] - box[0], box[3] - box[2]])
    bounds = None if widen == 0 else box + np.array([-pad[0], pad[0], -pad[1], pad[1]])
    x, y = workspace_grid(design, phi, 200, bounds)
    xx, yy = np.meshgrid(x, y)
    poses = np.stack([xx, yy, np.full_like(xx, phi)], axis=-1).reshape(-1, 3)
    res = batch.evaluate_poses(design, poses)
    reach = res.reachable
    k_lock = [leg.actuator.locked_stiffness for leg in design.legs]
    mats, pis, _ = batch.general_stiffness(design, poses, k_lock)
    ratio = eigenvalue_ratio(mats[reach])
    tau = transmission_index(pis[reach])
    previous_ok = np.zeros(reach.shape, dtype=bool)
    previous_ok[reach] = np.isfinite(ratio) & (ratio > MATRIX_RATIO_TOLERANCE)
    return {
        "points": int(reach.size),
        "outside_limits": int((~reach).sum()),
        "masked_previous": int((~previous_ok).sum()),
        "masked_now": int((~res.valid).sum()),
        "singular_previous": int((reach & ~previous_ok).sum()),
        "singular_now": int((reach & ~res.valid).sum()),
        "min_ratio": float(ratio.min()) if ratio.size else float("nan"),
        "min_index": float(tau.min()) if tau.size else float("nan"),
    }


def main() -> None:
    cases: list[tuple[str, Design, float, float]] = [
        ("paper", default_design(), 0.0, 0.0),
        ("paper_phi30", default_design(), np.radians(30.0), 0.0),
        ("paper_wide", default_design(), 0.0, 0.1),
    ]
    for name in ("symmetric_3ppr", "redundant_4ppr", "3rpr", "3prr", "3rrr"):
        design = load_design(ROOT / "examples" / f"{name}.toml")
        cases.append((name, design, design.workspace.phi, 0.0))
    stiff = rigid_structure(load_design(ROOT / "examples" / "3rpr.toml"))
    cases.append(("3rpr_rigid_structure", stiff, 0.0, 0.0))
    out = []
    for label, design, phi, widen in cases:
        c = counts(design, phi, widen)
        print(label, {k: (f"{v:.3g}" if isinstance(v, float) else v) for k, v in c.items()})
        out += [f"{label}_masked_previous={c['masked_previous']}"]
        out += [f"{label}_masked_now={c['masked_now']}"]
    print(" ".join(out))


if __name__ == "__main__":
    main()
