"""Benchmark: FE frame model (PyNite) vs virtual-joint model, time per pose, one run.

Designs: the built-in planar 3-PPR and the 6-UPS hexapod (examples/hexapod_6ups.toml)
by default, or those given by ``--design`` (repeatable). Poses: the home pose and the 5
seeded poses of ``ppm-stiffness validate`` (planar designs: its default box, +-10 mm,
+-5 deg; other designs: their required region, ``validate --region``). Each model is
warmed up once, then timed per pose as the best of ``--repeat`` runs (FE: build + six
load cases + inverse; virtual joints: ``stiffness_at_pose``). The batched virtual-joint
figure evaluates 1000 completed poses of the same box in one call of the batched
engine (``legs.engine``: ``reduce_chain`` + ``platform_stiffness``, the way the maps
use the model) and divides by the number of poses.

    .venv/bin/python benchmarks/bench_validation.py [--repeat N] [--design FILE ...] [--smoke]

After each design a line ``design=LABEL fe_ms=X vj_ms=X vj_batched_us=X fe_over_vj=R
fe_over_vj_batched=R`` (mean times per pose; LABEL: ``builtin`` or the file's stem).
``--smoke``: the built-in design only
(unless ``--design``), the home pose and one seeded pose, one run each, 20 batched
poses (a check that the script runs).

Needs the extra ``validate`` (PyNite).
"""

from __future__ import annotations

import argparse
import platform
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np

from ppm_stiffness.core.pose import ANGLE_COORDINATES, POSE_COORDINATES
from ppm_stiffness.design import Design, default_design, load_design
from ppm_stiffness.legs import engine
from ppm_stiffness.model import locked_actuator_stiffness, stiffness_at_pose
from ppm_stiffness.poses import full_poses
from ppm_stiffness.validation.compare import differences, sampling_box, validation_poses
from ppm_stiffness.validation.fe_model import fe_stiffness_at_pose, require_pynite

DEFAULT_DESIGNS = (None, "examples/hexapod_6ups.toml")


def best_time(fn: Callable[[], object], repeat: int) -> float:
    """Best wall time [s] of ``repeat`` runs."""
    return best_times(fn, repeat)[0]


def best_times(fn: Callable[[], object], repeat: int) -> tuple[float, float]:
    """Best wall time and best CPU time of this process [s] of ``repeat`` runs (on a
    shared machine the wall clock also counts the time others hold the cores)."""
    wall, cpu = float("inf"), float("inf")
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.process_time() - c0)
    return wall, cpu


def batched_vj_time_per_pose(design: Design, n: int = 1000) -> float:
    """Virtual-joint K at ``n`` completed, reachable poses of the validation box in one
    call of the batched engine; seconds per pose."""
    centre, half = sampling_box(design, region=not design.planar)
    rng = np.random.default_rng(0)
    draws = centre + rng.uniform(-1, 1, (4 * n, len(centre))) * half
    poses, ok = full_poses(design, draws)
    for leg in design.legs:
        ok &= leg.reachable(leg.solve(poses))
    poses = poses[ok][:n]
    k_act = locked_actuator_stiffness(design)

    def run() -> None:
        reductions = [
            engine.reduce_chain(leg.chain(leg.solve(poses)), len(poses)) for leg in design.legs
        ]
        engine.platform_stiffness(reductions, k_act)

    return best_time(run, 3) / len(poses)


def _pose_text(pose: np.ndarray) -> str:
    return " ".join(
        f"{np.degrees(v):6.2f}" if name in ANGLE_COORDINATES else f"{v * 1e3:7.2f}"
        for name, v in zip(POSE_COORDINATES, pose, strict=True)
    )


def bench_design(
    design: Design, label: str, repeat: int, n_poses: int = 5, n_batch: int = 1000
) -> None:
    poses = validation_poses(design, n_poses, seed=0, region=not design.planar)
    stiffness_at_pose(design, poses[0])  # warm-up
    fe0 = fe_stiffness_at_pose(design, poses[0])
    print(
        f"\n{design.name}: {len(design.legs)} legs; FE model {fe0.n_nodes} nodes, "
        f"{fe0.n_members} members, {fe0.n_springs} springs at the home pose"
    )
    print(
        f"{'pose':>4} {'x, y, z [mm]; rx, ry, rz [deg]':>45} {'FE ms':>7} {'VJ ms':>6} "
        f"{'FE/VJ':>5} {'figures'}"
    )
    t_fe, t_vj, c_fe, c_vj = [], [], [], []
    for i, pose in enumerate(poses):
        fe = fe_stiffness_at_pose(design, pose)
        diff = differences(design, stiffness_at_pose(design, pose), fe.stiffness)
        tf, cf = best_times(partial(fe_stiffness_at_pose, design, pose), repeat)
        tv, cv = best_times(partial(stiffness_at_pose, design, pose), 20 * repeat)
        t_fe.append(tf)
        t_vj.append(tv)
        c_fe.append(cf)
        c_vj.append(cv)
        figures = " ".join(f"{k} {v:.2e}" for k, v in diff.items())
        print(
            f"{'home' if i == 0 else i:>4} {_pose_text(pose)} {tf * 1e3:7.1f} "
            f"{tv * 1e3:6.3f} {tf / tv:5.0f} {figures}"
        )
    fe_mean, vj_mean = float(np.mean(t_fe)), float(np.mean(t_vj))
    vj_batch = batched_vj_time_per_pose(design, n_batch)
    print(
        f"mean time per pose: FE {fe_mean * 1e3:.1f} ms, virtual joints "
        f"{vj_mean * 1e3:.3f} ms (single pose), ratio FE/VJ = {fe_mean / vj_mean:.0f}"
    )
    print(
        f"mean CPU time per pose: FE {np.mean(c_fe) * 1e3:.1f} ms, virtual joints "
        f"{np.mean(c_vj) * 1e3:.3f} ms (single pose)"
    )
    print(
        f"virtual joints batched over {n_batch} poses: {vj_batch * 1e6:.1f} us per pose, "
        f"ratio FE/VJ = {fe_mean / vj_batch:.0f}"
    )
    print(
        f"design={label} fe_ms={fe_mean * 1e3:.2f} "
        f"vj_ms={vj_mean * 1e3:.4f} vj_batched_us={vj_batch * 1e6:.2f} "
        f"fe_over_vj={fe_mean / vj_mean:.0f} fe_over_vj_batched={fe_mean / vj_batch:.0f}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per pose (best kept)")
    parser.add_argument(
        "--design",
        action="append",
        help="design file (repeatable; default: the built-in design and the hexapod)",
    )
    parser.add_argument("--smoke", action="store_true", help="tiniest sizes (runs or not)")
    args = parser.parse_args()
    designs = args.design or ([None] if args.smoke else DEFAULT_DESIGNS)
    sizes = {"n_poses": 1, "n_batch": 20} if args.smoke else {}
    repeat = 1 if args.smoke else args.repeat
    pynite = require_pynite()
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, "
        f"PyNite {pynite.__version__}, {platform.machine()}"
    )
    for path in designs:
        design = default_design() if path is None else load_design(path)
        label = "builtin" if path is None else Path(path).stem
        bench_design(design, label, repeat, **sizes)


if __name__ == "__main__":
    main()
