"""Regenerate the SYNTHETIC identification examples in examples/identification/.

A "prototype" of the built-in 3-PPR whose element stiffnesses differ from the
catalogue by known factors (TRUE_FACTORS) is loaded at several poses; its platform
deflections (the model's loaded equilibrium, nonlinear actuator law) plus Gaussian
noise (fixed seeds) are written as measurement files. They are not measurements.

- ``measurements.csv``: the identification data (pose, wrench, six twist components
  with their sigma columns);
- ``held_out.csv``: a planar-force curve at the workspace centre (deflect's format),
  not used by the fit, to check the identified model's prediction;
- ``3rps_measurements.csv``: the same for a prototype of the spatial 3-RPS example
  (examples/3rps.toml; SPATIAL_FACTORS) at four poses given by their task coordinates
  (z, rx, ry) and the x, y, rz its legs impose (the parasitic motion), six pose
  columns.

    .venv/bin/python scripts/synthetic_identification_data.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ppm_stiffness.design import Design, default_design, load_design
from ppm_stiffness.fit.identify import predict_twists
from ppm_stiffness.model import workspace_centre
from ppm_stiffness.poses import full_poses
from ppm_stiffness.statics.deflection import deflection_curve

ROOT = Path(__file__).parents[1]
OUT = ROOT / "examples/identification"

#: The prototype: catalogue value times this factor.
TRUE_FACTORS = {
    "leg1.guide.yaw": 0.80,
    "leg2.guide.yaw": 1.15,
    "leg*.actuator.locked_stiffness": 0.90,
    "leg3.distal.young_modulus": 1.10,
    "leg1.proximal.young_modulus": 0.90,
}
#: Instrument noise (1 sigma): an autocollimator and dial indicators.
SIGMA_DEG = 0.001
SIGMA_MM = 0.001
SEED, HELD_OUT_SEED = 41, 42
#: Pose offsets from the workspace centre [mm, mm, deg].
POSES = ((0, 0, 0), (5, 0, 0), (0, 5, 0), (-5, -5, 3), (5, -5, -3))
#: Wrenches [fx, fy, fz N, mx, my, mz N·m] applied at each pose.
WRENCHES = (
    (8, 0, 0, 0, 0, 0),
    (0, 8, 0, 0, 0, 0),
    (0, 0, 15, 0, 0, 0),
    (0, 0, 0, 0, 0, 0.3),
    (4, -4, 10, 0, 0, -0.1),
)
COLUMNS = ("phi_x_deg", "phi_y_deg", "phi_z_deg", "x_mm", "y_mm", "z_mm")
FACTORS = np.array([180 / math.pi] * 3 + [1e3] * 3)


def prototype() -> object:
    design = default_design()
    return design.with_parameters(
        {name: design.parameter(name) * f for name, f in TRUE_FACTORS.items()}
    )


def _noise_columns() -> np.ndarray:
    return np.array([SIGMA_DEG] * 3 + [SIGMA_MM] * 3)


def measurements() -> str:
    design = default_design()
    truth = prototype()
    centre = workspace_centre(design)
    poses, wrenches = [], []
    for dx, dy, dphi in POSES:
        for fx, fy, fz, mx, my, mz in WRENCHES:
            poses.append(centre + [dx * 1e-3, dy * 1e-3, math.radians(dphi)])
            wrenches.append([mx, my, mz, fx, fy, fz])
    twists = predict_twists(truth, np.array(poses), np.array(wrenches, dtype=float))  # type: ignore[arg-type]
    rng = np.random.default_rng(SEED)
    sig = _noise_columns()
    measured = twists * FACTORS + rng.normal(size=twists.shape) * sig
    lines = [
        "# SYNTHETIC identification data -- NOT a measurement.",
        "# The built-in 3-PPR with element stiffnesses changed by known factors:",
        *(f"#   {n} x {f:g}" for n, f in TRUE_FACTORS.items()),
        f"# plus Gaussian noise {SIGMA_DEG} deg / {SIGMA_MM} mm, default_rng(seed={SEED}).",
        "# Regenerate: scripts/synthetic_identification_data.py",
        "pose_x_mm,pose_y_mm,pose_phi_deg,fx_N,fy_N,fz_N,mx_Nm,my_Nm,mz_Nm,"
        + ",".join(COLUMNS)
        + ","
        + ",".join(f"sigma_{c}" for c in COLUMNS),
    ]
    for p, w, t in zip(poses, wrenches, measured, strict=True):
        pose = [p[0] * 1e3, p[1] * 1e3, math.degrees(p[2])]
        load = [w[3], w[4], w[5], w[0], w[1], w[2]]
        lines.append(
            ",".join(f"{v:.6g}" for v in pose)
            + ","
            + ",".join(f"{v:g}" for v in load)
            + ","
            + ",".join(f"{v:.6f}" for v in t)
            + ","
            + ",".join(f"{v:g}" for v in sig)
        )
    return "\n".join(lines) + "\n"


def held_out() -> str:
    truth = prototype()
    loads = np.arange(1, 11) * 1.0
    curve = deflection_curve(truth, "planar-force", loads, alpha=math.radians(45))  # type: ignore[arg-type]
    rng = np.random.default_rng(HELD_OUT_SEED)
    cols = (2, 3, 4)
    t = curve.twists[:, cols] * FACTORS[list(cols)]
    t = t + rng.normal(size=t.shape) * _noise_columns()[list(cols)]
    lines = [
        "# SYNTHETIC held-out deflections -- NOT a measurement (not used by the fit).",
        "# The prototype of measurements.csv at the workspace centre, planar force at",
        f"# 45 deg, plus noise {SIGMA_DEG} deg / {SIGMA_MM} mm, default_rng(seed={HELD_OUT_SEED}).",
        "# mode: planar-force",
        "# alpha_deg: 45",
        "load,phi_z_deg,x_mm,y_mm",
    ]
    for load, row in zip(loads, t, strict=True):
        lines.append(f"{load:g}," + ",".join(f"{v:.6f}" for v in row))
    return "\n".join(lines) + "\n"


#: The spatial prototype: the 3-RPS example's values times these factors.
SPATIAL_FACTORS = {
    "leg1.actuator.k_a": 0.85,
    "leg2.actuator.k_a": 1.10,
    "leg3.actuator.k_a": 0.95,
    "leg*.base_revolute.tilt": 1.20,
    "leg*.guide.lateral": 0.90,
}
#: Its instrument noise (1 sigma): capacitive probes and an autocollimator.
SPATIAL_SIGMA_DEG = 1e-4
SPATIAL_SIGMA_MM = 1e-4
SPATIAL_SEED = 43
#: Poses: task coordinates z [mm], rx, ry [deg] of the 3-RPS.
SPATIAL_POSES = ((350, 0, 0), (330, 5, 0), (370, 0, -5), (350, -4, 4))
#: Wrenches [fx, fy, fz N, mx, my, mz N·m] applied at each pose.
SPATIAL_WRENCHES = (
    (200, 0, 0, 0, 0, 0),
    (0, 200, 0, 0, 0, 0),
    (0, 0, 3000, 0, 0, 0),
    (0, 0, 0, 50, 0, 0),
    (0, 0, 0, 0, 50, 0),
    (0, 0, 0, 0, 0, 20),
)
POSE_COLUMNS = ("pose_x_mm", "pose_y_mm", "pose_z_mm", "pose_rx_deg", "pose_ry_deg", "pose_rz_deg")
POSE_FACTORS = np.array([1e3] * 3 + [180 / math.pi] * 3)


def spatial_prototype() -> Design:
    design = load_design(ROOT / "examples/3rps.toml")
    return design.with_parameters(
        {name: design.parameter(name) * f for name, f in SPATIAL_FACTORS.items()}
    )


def spatial_measurements() -> str:
    design = load_design(ROOT / "examples/3rps.toml")
    truth = spatial_prototype()
    tasks = np.array(
        [[z * 1e-3, math.radians(rx), math.radians(ry)] for z, rx, ry in SPATIAL_POSES]
    )
    poses, ok = full_poses(design, tasks)  # the parasitic x, y, rz of the catalogue legs
    assert bool(np.all(ok))
    rows = [(pose, w) for pose in poses for w in SPATIAL_WRENCHES]
    wrenches = np.array([[w[3], w[4], w[5], w[0], w[1], w[2]] for _, w in rows], dtype=float)
    twists = predict_twists(truth, np.array([p for p, _ in rows]), wrenches)
    rng = np.random.default_rng(SPATIAL_SEED)
    sig = np.array([SPATIAL_SIGMA_DEG] * 3 + [SPATIAL_SIGMA_MM] * 3)
    measured = twists * FACTORS + rng.normal(size=twists.shape) * sig
    lines = [
        "# SYNTHETIC identification data of a spatial design -- NOT a measurement.",
        "# The 3-RPS example (examples/3rps.toml) with element stiffnesses changed by",
        "# known factors:",
        *(f"#   {n} x {f:g}" for n, f in SPATIAL_FACTORS.items()),
        f"# plus Gaussian noise {SPATIAL_SIGMA_DEG} deg / {SPATIAL_SIGMA_MM} mm, "
        f"default_rng(seed={SPATIAL_SEED}).",
        "# Poses: the task coordinates z, rx, ry and the x, y, rz the legs impose there.",
        "# Regenerate: scripts/synthetic_identification_data.py",
        ",".join(POSE_COLUMNS)
        + ",fx_N,fy_N,fz_N,mx_Nm,my_Nm,mz_Nm,"
        + ",".join(COLUMNS)
        + ","
        + ",".join(f"sigma_{c}" for c in COLUMNS),
    ]
    for (pose, w), t in zip(rows, measured, strict=True):
        lines.append(
            ",".join(f"{v:.10g}" for v in pose * POSE_FACTORS)
            + ","
            + ",".join(f"{v:g}" for v in w)
            + ","
            + ",".join(f"{v:.7f}" for v in t)
            + ","
            + ",".join(f"{v:g}" for v in sig)
        )
    return "\n".join(lines) + "\n"


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "measurements.csv").write_text(measurements(), encoding="utf-8")
    (OUT / "held_out.csv").write_text(held_out(), encoding="utf-8")
    (OUT / "3rps_measurements.csv").write_text(spatial_measurements(), encoding="utf-8")


if __name__ == "__main__":
    main()
