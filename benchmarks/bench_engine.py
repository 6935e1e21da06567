"""Benchmark of the batched engine (legs/engine.py) on the shipped spatial designs.

The legs are built from the ``[[legs]]`` and ``[parts]`` tables of
examples/hexapod_6ups.toml (6 U-P-S), 3prs.toml and 3rps.toml, and evaluated at random
poses of each design's required region (its task coordinates uniform in their range,
the dependent ones completed from the legs' constraints), measured in one run:

- poses per second of the batched path, IK (``leg.solve``), chain (``leg.chain``),
  ``engine.reduce_chain`` and ``engine.leg_stiffness`` with the locked actuator
  stiffness, summed over the legs, in chunks of ``engine.CHUNK`` poses: median of 5 runs,
  by the wall clock (``*_poses_per_s``) and by the process's CPU time
  (``*_cpu_poses_per_s``: on a shared machine the wall clock also counts the time
  others hold the cores);
- the dense definition (``chain.leg_springs`` + ``solver.leg_stiffness``, batched with
  numpy) on the same hexapod legs and its rate, and the largest length-balanced
  relative difference of K between the two on those poses (``max_rel_diff``);
- the single-pose cost of the engine path on the hexapod (n = 1, median over poses:
  ``single_pose_us``);
- with ``--baseline SRC``: the hexapod path of another source tree (for instance
  ``git archive <ref> src | tar -x -C /tmp/base``, then ``--baseline /tmp/base/src``)
  against this one, in fresh processes run alternately (5 each): the medians.

The last line is ``hexapod_poses_per_s=N tripod_poses_per_s=N rps_poses_per_s=N
definition_poses_per_s=N ratio=R hexapod_cpu_poses_per_s=N tripod_cpu_poses_per_s=N
single_pose_us=N max_rel_diff=X [baseline_poses_per_s=N baseline_cpu_poses_per_s=N
speedup=R]``, where ``tripod`` is the 3-PRS, ``rps`` the 3-RPS and ``ratio`` the
hexapod's rate over the definition's.
``--smoke``: 64 poses (32 for the definition), one timed run, 3 single poses, no
baseline (a check that the script runs; its figures mean nothing).
Run: ``.venv/bin/python benchmarks/bench_engine.py [--quick | --smoke] [--baseline SRC]
[--chunk N]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SRC = Path(__file__).resolve().parents[1] / "src"
POSE_INDEX = {"x": 0, "y": 1, "z": 2, "rx": 3, "ry": 4, "rz": 5, "phi": 5}
BALANCE = np.array([10.0, 10.0, 10.0, 1.0, 1.0, 1.0])  # 1 / LENGTH_SCALE on rotations
REPEATS = 5


def design_legs(name: str) -> tuple[list[Any], np.ndarray, list[str]]:
    """The legs of an example file, its home pose (6,) and its task coordinates."""
    from ppm_stiffness.design.validation import apply_parts
    from ppm_stiffness.legs.registry import leg_types

    path = EXAMPLES / f"{name}.toml"
    applied = apply_parts(tomllib.loads(path.read_text()))
    if applied.issues:
        raise ValueError(f"{path}: {applied.issues}")
    data = applied.merged
    types = leg_types()
    legs = [types[leg["type"]](**leg) for leg in data["legs"]]
    ws = data["workspace"]
    home = np.array([ws[k] for k in ("centre_x", "centre_y", "centre_z", "rx", "ry", "phi")])
    return legs, home, list(data["task_coordinates"])


def sample_poses(name: str, n: int, seed: int = 0) -> tuple[list[Any], np.ndarray]:
    """A design's legs and n poses of its required region (dependent coordinates
    completed; the poses that do not converge are dropped)."""
    from ppm_stiffness.legs.completion import complete_poses

    legs, home, task = design_legs(name)
    path = EXAMPLES / f"{name}.toml"
    required = tomllib.loads(path.read_text())["workspace"]["required"]
    rng = np.random.default_rng(seed)
    poses = np.tile(home, (n, 1))
    for coordinate in task:
        lo, hi = required[coordinate]
        poses[:, POSE_INDEX[coordinate]] = rng.uniform(lo, hi, n)
    dependent = sorted(set(range(6)) - {POSE_INDEX[c] for c in task})
    if dependent:
        poses, ok = complete_poses(legs, dependent, poses)
        poses = poses[ok]
    return legs, poses


def engine_path(legs: list[Any], poses: np.ndarray, chunk: int) -> np.ndarray:
    """K (n, 6, 6) by the engine, chunk by chunk, summed over the legs."""
    from ppm_stiffness.legs import engine

    out = np.empty((poses.shape[0], 6, 6))
    for lo in range(0, poses.shape[0], chunk):
        q = poses[lo : lo + chunk]
        total = None
        for leg in legs:
            reduction = engine.reduce_chain(leg.chain(leg.solve(q)), q.shape[0])
            k = engine.leg_stiffness(reduction, leg.actuator.locked_stiffness)
            total = k if total is None else total + k
        out[lo : lo + chunk] = total
    return out


def definition_path(legs: list[Any], poses: np.ndarray) -> np.ndarray:
    """K (n, 6, 6) by the definition (dense springs, batched with numpy)."""
    from ppm_stiffness.core import solver
    from ppm_stiffness.legs.chain import leg_springs

    total = np.zeros((poses.shape[0], 6, 6))
    for leg in legs:
        springs = leg_springs(leg.chain(leg.solve(poses)), leg.actuator.locked_stiffness)
        total += solver.leg_stiffness(springs)
    return total


def rates(run: Any, n: int, repeats: int = REPEATS) -> tuple[float, float]:
    """Median poses per second of ``run()`` over n poses: wall clock, CPU time."""
    run()  # warm caches and lazy imports
    wall, cpu = [], []
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        run()
        wall.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    return n / statistics.median(wall), n / statistics.median(cpu)


def single_pose_us(legs: list[Any], poses: np.ndarray, count: int) -> float:
    """Median time [us] of the engine path at one pose (n = 1)."""
    times = []
    for i in range(count):
        q = poses[i % poses.shape[0]][None, :]
        t = time.perf_counter()
        engine_path(legs, q, 1)
        times.append(time.perf_counter() - t)
    return 1e6 * statistics.median(times[1:])


def kernel(n: int) -> dict[str, float]:
    """The hexapod rates of the ppm_stiffness on sys.path (run in a child process)."""
    from ppm_stiffness.legs import engine

    legs, poses = sample_poses("hexapod_6ups", n)
    chunk = getattr(engine, "CHUNK", 4096)
    wall, cpu = rates(lambda: engine_path(legs, poses, chunk), poses.shape[0])
    return {"wall": wall, "cpu": cpu}


def compare(baseline: str, n: int) -> tuple[dict[str, float], dict[str, float]]:
    """Medians of the hexapod rates of ``baseline`` and of this tree, run alternately."""
    results: dict[str, list[dict[str, float]]] = {"baseline": [], "this": []}
    for _ in range(REPEATS):
        for label, src in (("baseline", baseline), ("this", str(SRC))):
            env = dict(os.environ, PYTHONPATH=src)
            out = subprocess.run(
                [sys.executable, __file__, "--kernel", str(n)],
                check=True,
                capture_output=True,
                text=True,
                env=env,
            )
            results[label].append(json.loads(out.stdout.strip().splitlines()[-1]))
    med = {
        label: {k: statistics.median(r[k] for r in runs) for k in ("wall", "cpu")}
        for label, runs in results.items()
    }
    return med["baseline"], med["this"]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer poses (< 1 min)")
    parser.add_argument("--smoke", action="store_true", help="tiniest sizes (runs or not)")
    parser.add_argument("--baseline", help="src folder of another tree to compare with")
    parser.add_argument("--chunk", type=int, help="poses per chunk (default engine.CHUNK)")
    parser.add_argument("--kernel", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.kernel:
        print(json.dumps(kernel(args.kernel)))
        return 0

    from ppm_stiffness.legs import engine

    if args.chunk:
        engine.CHUNK = args.chunk
    repeats = 1 if args.smoke else REPEATS
    if args.smoke:
        args.baseline = None
    n, n_def = (64, 32) if args.smoke else (8192, 1000) if args.quick else (40960, 4000)
    print(
        f"machine: {os.cpu_count()} cores, numpy {np.__version__}, python "
        f"{sys.version.split()[0]}, load {os.getloadavg()[0]:.1f}; chunk {engine.CHUNK}"
    )
    found: dict[str, float] = {}
    for label, name in (("hexapod", "hexapod_6ups"), ("tripod", "3prs"), ("rps", "3rps")):
        legs, poses = sample_poses(name, n)
        wall, cpu = rates(
            lambda legs=legs, poses=poses: engine_path(legs, poses, engine.CHUNK),
            poses.shape[0],
            repeats,
        )
        found[label], found[f"{label}_cpu"] = wall, cpu
        print(
            f"{name}: {len(legs)} legs, {poses.shape[0]} poses: {wall:,.0f} poses/s "
            f"(CPU time: {cpu:,.0f} poses/s)"
        )
    legs, poses = sample_poses("hexapod_6ups", n_def, seed=1)
    wall, cpu = rates(lambda: definition_path(legs, poses), poses.shape[0], min(3, repeats))
    found["definition"] = wall
    fast, ref = engine_path(legs, poses, engine.CHUNK), definition_path(legs, poses)
    scale = np.max(np.abs(ref * BALANCE[:, None] * BALANCE), axis=(1, 2))
    diff = np.max(np.abs((fast - ref) * BALANCE[:, None] * BALANCE), axis=(1, 2)) / scale
    found["max_rel_diff"] = float(np.max(diff))
    print(
        f"definition (dense springs, numpy) on {poses.shape[0]} hexapod poses: "
        f"{wall:,.0f} poses/s (CPU time: {cpu:,.0f}); engine / definition "
        f"{found['hexapod'] / wall:.1f}x; largest relative difference of K "
        f"(length-balanced) {found['max_rel_diff']:.1e}"
    )
    found["single_pose_us"] = single_pose_us(
        legs, poses, 3 if args.smoke else 201 if args.quick else 1001
    )
    print(f"one pose (n = 1), engine path on the hexapod: {found['single_pose_us']:.0f} us")
    extra = ""
    if args.baseline:
        base, this = compare(args.baseline, n)
        print(
            f"hexapod, fresh processes run alternately (medians of {REPEATS}): baseline "
            f"{base['wall']:,.0f} poses/s (CPU {base['cpu']:,.0f}), this tree "
            f"{this['wall']:,.0f} poses/s (CPU {this['cpu']:,.0f}): "
            f"{this['wall'] / base['wall']:.2f}x (CPU {this['cpu'] / base['cpu']:.2f}x)"
        )
        extra = (
            f" baseline_poses_per_s={base['wall']:.0f} baseline_cpu_poses_per_s="
            f"{base['cpu']:.0f} this_poses_per_s={this['wall']:.0f} this_cpu_poses_per_s="
            f"{this['cpu']:.0f} speedup={this['wall'] / base['wall']:.2f}"
        )
    print(
        f"hexapod_poses_per_s={found['hexapod']:.0f} tripod_poses_per_s={found['tripod']:.0f} "
        f"rps_poses_per_s={found['rps']:.0f} definition_poses_per_s={found['definition']:.0f} "
        f"ratio={found['hexapod'] / found['definition']:.1f} "
        f"hexapod_cpu_poses_per_s={found['hexapod_cpu']:.0f} "
        f"tripod_cpu_poses_per_s={found['tripod_cpu']:.0f} "
        f"single_pose_us={found['single_pose_us']:.0f} "
        f"max_rel_diff={found['max_rel_diff']:.1e}" + extra
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
