"""Regenerate the SYNTHETIC example data shipped in src/ppm_stiffness/data/.

The paper's raw data (Fig. 4b actuator force-displacement, Fig. 10 measured
deflections) are not published. These files are made from the model plus Gaussian
noise, with fixed seeds, so that the fitting and comparison tools have something to
run on. They are not measurements.

    .venv/bin/python scripts/synthetic_actuation_data.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ppm_stiffness.design import default_design
from ppm_stiffness.statics.actuator_fit import power_law_force
from ppm_stiffness.statics.deflection import deflection_curve

DATA = Path(__file__).parents[1] / "src/ppm_stiffness/data"

K_A, Q = 44.75, 0.225  # eq. (20)
FORCE_SIGMA = 0.10  # N
ACTUATOR_SEED = 3

ORIENTATION_SIGMA_DEG = 0.05
POSITION_SIGMA_MM = 0.05
#: mode -> (seed, loads, measured columns)
MEASUREMENTS = {
    "planar": ("planar-force", 31, np.arange(1, 11) * 1.0, ("phi_z_deg", "x_mm", "y_mm")),
    "moment": ("moment", 32, np.arange(1, 11) * 0.05, ("phi_z_deg", "x_mm", "y_mm")),
    "vertical": ("vertical-force", 33, np.arange(1, 11) * 2.0, ("z_mm",)),
}
_INDEX = {"phi_x_deg": 0, "phi_y_deg": 1, "phi_z_deg": 2, "x_mm": 3, "y_mm": 4, "z_mm": 5}


def actuator_data() -> str:
    rng = np.random.default_rng(ACTUATOR_SEED)
    d_mm = np.geomspace(0.01, 1.0, 30)
    force = power_law_force(d_mm * 1e-3, K_A, Q) + rng.normal(0.0, FORCE_SIGMA, d_mm.size)
    lines = [
        "# SYNTHETIC actuator force-displacement data -- NOT a measurement.",
        "# The paper's Fig. 4(b) data are not published. Generated from eq. (20),",
        f"# G = k_a * delta^q with k_a = {K_A} N/m^q, q = {Q}, delta in metres,",
        "# at 30 displacements log-spaced from 0.01 mm to 1 mm, plus Gaussian noise",
        f"# on the force, sigma = {FORCE_SIGMA} N, numpy default_rng(seed={ACTUATOR_SEED}).",
        "# Regenerate: scripts/synthetic_actuation_data.py",
        "displacement_mm,force_N",
    ]
    lines += [f"{d:.6f},{g:.5f}" for d, g in zip(d_mm, force, strict=True)]
    return "\n".join(lines) + "\n"


def measurement_data(key: str) -> str:
    mode, seed, loads, cols = MEASUREMENTS[key]
    design = default_design()
    curve = deflection_curve(design, mode, loads)
    rng = np.random.default_rng(seed)
    unit = "N·m" if mode == "moment" else "N"
    lines = [
        "# SYNTHETIC deflection measurements -- NOT a measurement.",
        "# The paper's Fig. 10 data are not published. Generated from the built-in design",
        "# at its workspace centre, ppm_stiffness.statics.deflection.deflection_curve (integrated",
        "# actuator law), plus Gaussian noise: sigma = "
        f"{ORIENTATION_SIGMA_DEG} deg per orientation column, {POSITION_SIGMA_MM} mm per",
        f"# position column, numpy default_rng(seed={seed}). Load in {unit}.",
        "# Regenerate: scripts/synthetic_actuation_data.py",
        f"# mode: {mode}",
    ]
    if mode == "planar-force":
        lines.append(f"# alpha_deg: {math.degrees(curve.alpha):g}")
    lines.append(",".join(("load",) + cols))
    for k, load in enumerate(loads):
        cells = [f"{load:g}"]
        for c in cols:
            i = _INDEX[c]
            if i < 3:
                v = math.degrees(curve.twists[k, i]) + rng.normal(0.0, ORIENTATION_SIGMA_DEG)
            else:
                v = curve.twists[k, i] * 1e3 + rng.normal(0.0, POSITION_SIGMA_MM)
            cells.append(f"{v:.4f}")
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


def main() -> None:
    (DATA / "actuator_synthetic.csv").write_text(actuator_data(), encoding="utf-8")
    for key in MEASUREMENTS:
        (DATA / f"measurements_synthetic_{key}.csv").write_text(
            measurement_data(key), encoding="utf-8"
        )
    print(f"wrote synthetic data to {DATA}")


if __name__ == "__main__":
    main()
