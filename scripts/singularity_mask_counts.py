"""Masked grid points of the built-in design's default maps under the old and the new
singularity criterion (docs/maps.md).

old: eigenvalues of K / s_i / s_j with s = (10, 10, 10, 1, 1, 1) (K_rr * L^2, L = 0.1 m),
     singular when lambda_min <= 1e-9 lambda_max;
new: model.check_nonsingular: the length-balanced K (K_rr / L^2), tolerance 1e-6.
Grid: the map command's defaults (200 x 200 over the workspace bounding box) at
phi = 0 and 30 deg, plus the same grid over a box 20 % wider than the workspace.
Last line: key=value counts. Run: .venv/bin/python scripts/singularity_mask_counts.py
"""

from __future__ import annotations

import numpy as np

from ppm_stiffness.design import default_design
from ppm_stiffness.maps import batch
from ppm_stiffness.maps.workspace import workspace_bounds, workspace_grid
from ppm_stiffness.model import eigenvalue_ratio

S_OLD = np.array([10.0, 10, 10, 1, 1, 1])


def counts(phi: float, widen: float) -> dict[str, int]:
    design = default_design()
    box = workspace_bounds(design, phi)
    pad = widen * np.array([box[1] - box[0], box[3] - box[2]])
    bounds = None if widen == 0 else box + np.array([-pad[0], pad[0], -pad[1], pad[1]])
    x, y = workspace_grid(design, phi, 200, bounds)
    xx, yy = np.meshgrid(x, y)
    poses = np.stack([xx, yy, np.full_like(xx, phi)], axis=-1).reshape(-1, 3)
    res = batch.evaluate_poses(design, poses, matrices=True)
    reach = res.reachable
    mats, _ = batch.general_stiffness(
        design, poses, [leg.actuator.locked_stiffness for leg in design.legs]
    )
    eig_old = np.linalg.eigvalsh(mats[reach] / S_OLD[:, None] / S_OLD[None, :])
    old_ok = np.zeros(reach.shape, dtype=bool)
    old_ok[reach] = eig_old[:, 0] > 1e-9 * eig_old[:, -1]
    new_ok = res.valid
    return {
        "points": int(reach.size),
        "outside_limits": int((~reach).sum()),
        "masked_old": int((~old_ok).sum()),
        "masked_new": int((~new_ok).sum()),
        "singular_old": int((reach & ~old_ok).sum()),
        "singular_new": int((reach & ~new_ok).sum()),
        "min_ratio_new_e9": int(1e9 * eigenvalue_ratio(mats[reach]).min()),
    }


def main() -> None:
    out = []
    for deg in (0.0, 30.0):
        for widen in (0.0, 0.1):
            c = counts(np.radians(deg), widen)
            label = f"phi{deg:g}" + ("_wide" if widen else "")
            print(label, c)
            out += [
                f"{label}_masked_old={c['masked_old']}",
                f"{label}_masked_new={c['masked_new']}",
            ]
    print(" ".join(out))


if __name__ == "__main__":
    main()
