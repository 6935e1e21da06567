"""Benchmark: FE frame model (PyNite) vs virtual-joint model, time per pose, one run.

Poses: the workspace centre and the 5 seeded poses of ``ppm-stiffness validate``.
Each model is warmed up once, then timed per pose as the best of ``--repeat`` runs
(FE: build + six load cases + inverse; virtual joints: ``stiffness_at_pose``). The
batched virtual-joint figure evaluates all poses of a 1000-pose map in one call and
divides by the number of poses (the way the maps use the model).

    .venv/bin/python benchmarks/bench_validation.py [--repeat N] [--design FILE]

Needs the extra ``validate`` (PyNite).
"""

from __future__ import annotations

import argparse
import platform
import time
from collections.abc import Callable
from functools import partial

import numpy as np

from ppm_stiffness.core.solver import cartesian_stiffness
from ppm_stiffness.design import Design, default_design, load_design
from ppm_stiffness.legs.chain import leg_springs
from ppm_stiffness.model import stiffness_at_pose, workspace_centre
from ppm_stiffness.validation.compare import BLOCKS, block_difference, validation_poses
from ppm_stiffness.validation.fe_model import fe_stiffness_at_pose, require_pynite


def best_time(fn: Callable[[], object], repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def batched_vj_time_per_pose(design: Design, n: int = 1000) -> float:
    """Virtual-joint K at ``n`` poses in one batched call; seconds per pose."""
    rng = np.random.default_rng(0)
    poses = workspace_centre(design) + rng.uniform(-1, 1, (n, 3)) * [0.005, 0.005, 0.05]

    def run() -> None:
        legs = [
            leg_springs(leg.chain(leg.solve(poses)), leg.actuator.locked_stiffness)
            for leg in design.legs
        ]
        cartesian_stiffness(legs)

    return best_time(run, 3) / n


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per pose (best kept)")
    parser.add_argument("--design", help="design file (default: the built-in design)")
    args = parser.parse_args()
    pynite = require_pynite()
    design = default_design() if args.design is None else load_design(args.design)
    poses = validation_poses(design, 5, seed=0)
    stiffness_at_pose(design, poses[0])  # warm-up
    fe_stiffness_at_pose(design, poses[0])
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, "
        f"PyNite {pynite.__version__}, {platform.machine()}"
    )
    print(
        f"{'pose':>6} {'x mm':>8} {'y mm':>8} {'phi deg':>8} {'FE ms':>8} {'VJ ms':>8} "
        f"{'FE/VJ':>6} {'planar':>9} {'out-of-pl':>9}"
    )
    t_fe, t_vj = [], []
    for i, pose in enumerate(poses):
        fe = fe_stiffness_at_pose(design, pose)
        k_vj = stiffness_at_pose(design, pose)
        diff = {b: block_difference(k_vj, fe.stiffness, idx) for b, idx in BLOCKS.items()}
        tf = best_time(partial(fe_stiffness_at_pose, design, pose), args.repeat)
        tv = best_time(partial(stiffness_at_pose, design, pose), 20 * args.repeat)
        t_fe.append(tf)
        t_vj.append(tv)
        print(
            f"{'centre' if i == 0 else i:>6} {pose[0] * 1e3:8.3f} {pose[1] * 1e3:8.3f} "
            f"{np.degrees(pose[2]):8.3f} {tf * 1e3:8.1f} {tv * 1e3:8.3f} {tf / tv:6.0f} "
            f"{diff['planar']:9.2e} {diff['out_of_plane']:9.2e}"
        )
    fe_mean, vj_mean = float(np.mean(t_fe)), float(np.mean(t_vj))
    vj_batch = batched_vj_time_per_pose(design)
    print(
        f"mean time per pose: FE {fe_mean * 1e3:.1f} ms, virtual joints "
        f"{vj_mean * 1e3:.3f} ms (single pose), ratio FE/VJ = {fe_mean / vj_mean:.0f}"
    )
    print(
        f"virtual joints batched over 1000 poses: {vj_batch * 1e6:.1f} us per pose, "
        f"ratio FE/VJ = {fe_mean / vj_batch:.0f}"
    )


if __name__ == "__main__":
    main()
