"""Benchmark of the stiffness map: batched path against a loop over the single-pose API.

Measured side by side in one run, on the built-in design (or ``--design FILE``) at
phi = 0 with locked actuators:

- poses per second of ``workspace.stiffness_map`` (K, paper decoupling, k_phi, k_x,
  k_y, reachability and singularity masks) on a 1000 x 1000 grid (``--quick``: 300 x 300),
  median of three runs, on the path ``"auto"`` takes (the P-P-R reduced form, else the
  planar engine);
- on a design whose legs all offer the reduced form (P-P-R): the same map by the planar
  engine (``path="planar"``), the general engine of any architecture, and its rate
  over the reduced form's (``general_vs_reduced``), measured alternately in the same run;
- poses per second of a loop of ``model.stiffness_at_pose`` + ``decoupling.decouple``
  on a subset of the same grid poses (every k-th one; 2000 poses, ``--quick``: 200), and
  the largest relative difference between the two paths on that subset;
- for context: the scattered-pose batched path (``batch.evaluate_poses`` on random
  poses with random phi) and the general 22-spring model batched with numpy
  (``chain.leg_springs`` + ``solver.bordered_stiffness``), which is what the reduced form
  replaces;
- the peak resident memory of a fresh process computing a 3163 x 3163 (> 10^7 poses)
  map of the design, and of the same process before the map (imports only);
- for context, without ``--design``: ``batch.evaluate_poses`` on random poses over each
  shipped design's workspace box at phi = 0 by the planar engine
  (``planar_<design>_poses_per_s``) and by the general reference path (IK, chain
  springs, bordered inverse: ``general_<design>_poses_per_s``), 20 000 poses
  (``--quick``: 4000), best of two.

The last line is ``batched_poses_per_s=N loop_poses_per_s=N ratio=N peak_mb_1e7=N
[general_poses_per_s=N general_vs_reduced=R] [planar_<design>_poses_per_s=N
general_<design>_poses_per_s=N ...]``.
Run: ``.venv/bin/python benchmarks/bench_map.py [--design FILE] [--quick]``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time

import numpy as np

from ppm_stiffness.core import solver
from ppm_stiffness.core.decoupling import decouple
from ppm_stiffness.core.errors import SingularConfigurationError, UnreachablePoseError
from ppm_stiffness.design import Design, default_design, load_design
from ppm_stiffness.legs.chain import leg_springs
from ppm_stiffness.maps import batch
from ppm_stiffness.maps.reduced_leg import reduced_design
from ppm_stiffness.maps.workspace import StiffnessMap, stiffness_map, workspace_bounds
from ppm_stiffness.model import stiffness_at_pose

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples")
GENERAL_DESIGNS = ("paper_3ppr", "redundant_4ppr", "3rpr", "3prr", "3rrr")

# Peak resident memory of the child itself: VmHWM of /proc/self/status (reset by exec);
# ru_maxrss is not, on Linux it can carry the parent's high-water mark into the child.
_MEMORY_CHILD = r"""
import json, resource, sys, time
from ppm_stiffness.design import default_design, load_design
from ppm_stiffness.maps.workspace import StiffnessMap, stiffness_map

def peak_kb():
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss

design = load_design(sys.argv[2]) if len(sys.argv) > 2 else default_design()
before = peak_kb()
t = time.perf_counter()
smap = stiffness_map(design, grid=int(sys.argv[1]))
elapsed = time.perf_counter() - t
print(json.dumps({"before_kb": before, "peak_kb": peak_kb(), "seconds": elapsed,
                  "poses": int(smap.reachable.size), "valid": int(smap.reachable.sum())}))
"""


def time_map(
    design: Design, grid: int, repeats: int = 3, path: batch.Path = "auto"
) -> tuple[float, StiffnessMap]:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        smap = stiffness_map(design, phi=0.0, actuators="max", grid=grid, path=path)
        times.append(time.perf_counter() - t)
    return statistics.median(times), smap


def time_paths(design: Design, grid: int, repeats: int = 3) -> tuple[float, float]:
    """Median seconds of the reduced and the planar map, runs alternated."""
    reduced, planar = [], []
    for _ in range(repeats):
        reduced.append(time_map(design, grid, 1, "reduced")[0])
        planar.append(time_map(design, grid, 1, "planar")[0])
    return statistics.median(reduced), statistics.median(planar)


def time_loop(design: Design, smap: StiffnessMap, n_loop: int) -> tuple[float, int, float]:
    """Seconds for the single-pose loop on ``n_loop`` grid poses, count, max rel diff."""
    xs, ys = smap.x, smap.y
    total = xs.size * ys.size
    step = max(total // n_loop, 1)
    flat = np.arange(0, total, step)[:n_loop]
    worst = 0.0
    results = []
    t = time.perf_counter()
    for n in flat:
        j, i = divmod(int(n), xs.size)
        try:
            k = stiffness_at_pose(design, np.array([xs[i], ys[j], 0.0]))
        except (UnreachablePoseError, SingularConfigurationError):
            results.append((j, i, None))
            continue
        dec = decouple(k, "paper")
        results.append((j, i, dec.rotational_values[2], *dec.translational_values[:2]))
    elapsed = time.perf_counter() - t
    for j, i, *ref in results:
        if ref[0] is None:
            assert not smap.reachable[j, i]
            continue
        got = [smap.k_phi[j, i], smap.k_x[j, i], smap.k_y[j, i]]
        worst = max(worst, float(np.max(np.abs(np.subtract(got, ref)) / np.abs(ref))))
    return elapsed, len(flat), worst


def time_scattered(n: int) -> float:
    design = default_design()
    rng = np.random.default_rng(0)
    poses = np.stack(
        [rng.uniform(-0.014, 0.008, n), rng.uniform(-0.02, 0.02, n), rng.uniform(-0.2, 0.2, n)],
        axis=-1,
    )
    t = time.perf_counter()
    batch.evaluate_poses(design, poses)
    return n / (time.perf_counter() - t)


def time_general_numpy(n: int) -> float:
    """The 22-spring model batched with numpy (K only): poses per second, best of two."""
    design = default_design()
    rng = np.random.default_rng(1)
    poses = np.stack(
        [rng.uniform(-0.014, 0.008, n), rng.uniform(-0.02, 0.02, n), np.zeros(n)], axis=-1
    )
    best = float("inf")
    for _ in range(2):  # the first run also pays for fresh memory pages
        t = time.perf_counter()
        total = np.zeros((n, 6, 6))
        for leg in design.legs:
            springs = leg_springs(leg.chain(leg.solve(poses)), leg.actuator.locked_stiffness)
            total += solver.leg_stiffness(springs)
        best = min(best, time.perf_counter() - t)
    return n / best


def time_general_path(design: Design, n: int, path: batch.Path = "general") -> float:
    """Poses per second of ``evaluate_poses`` on ``path``, best of two."""
    box = workspace_bounds(design, 0.0)
    rng = np.random.default_rng(2)
    poses = np.stack(
        [rng.uniform(box[0], box[1], n), rng.uniform(box[2], box[3], n), np.zeros(n)], axis=-1
    )
    best = float("inf")
    for _ in range(2):
        t = time.perf_counter()
        batch.evaluate_poses(design, poses, path=path)
        best = min(best, time.perf_counter() - t)
    return n / best


def peak_memory(grid: int, design_file: str | None) -> dict[str, float]:
    env = dict(os.environ)
    out = subprocess.run(
        [sys.executable, "-c", _MEMORY_CHILD, str(grid), *([design_file] if design_file else [])],
        check=True,
        capture_output=True,
        text=True,
        env=env,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--design", help="design file (default: the built-in 3-PPR)")
    parser.add_argument("--quick", action="store_true", help="smaller grid and loop (< 1 min)")
    args = parser.parse_args(argv)
    grid, n_loop = (300, 200) if args.quick else (1000, 2000)
    design = load_design(args.design) if args.design else default_design()
    cores = os.cpu_count()
    print(
        f"machine: {cores} cores, numpy {np.__version__}, python {sys.version.split()[0]}; "
        f"design {design.name} ({design.architecture})"
    )

    seconds, smap = time_map(design, grid)
    n_map = grid * grid
    batched_rate = n_map / seconds
    reduced = reduced_design(design) is not None
    print(
        f"batched map {grid} x {grid} = {n_map} poses ({'reduced' if reduced else 'planar'} "
        f"path): {seconds:.3f} s (median of 3), {batched_rate:,.0f} poses/s, "
        f"{int(smap.reachable.sum())} in the workspace"
    )

    loop_s, n_done, worst = time_loop(design, smap, n_loop)
    loop_rate = n_done / loop_s
    print(
        f"single-pose loop (stiffness_at_pose + decouple) on {n_done} of the same poses: "
        f"{loop_s:.3f} s, {loop_rate:,.0f} poses/s ({1e6 / loop_rate:.0f} us/pose); "
        f"largest relative difference to the map {worst:.1e}"
    )
    ratio = batched_rate / loop_rate
    print(f"ratio batched / loop: {ratio:,.0f}x")
    extra = ""
    if reduced:
        red_s, gen_s = time_paths(design, grid)
        general_rate, reduced_rate = n_map / gen_s, n_map / red_s
        print(
            f"same map, runs alternated (median of 3): reduced form {reduced_rate:,.0f} "
            f"poses/s, planar engine (any architecture) {general_rate:,.0f} poses/s, "
            f"ratio {general_rate / reduced_rate:.3f}"
        )
        extra = (
            f" general_poses_per_s={general_rate:.0f} "
            f"general_vs_reduced={general_rate / reduced_rate:.3f}"
        )

    mem = peak_memory(3163, args.design)
    peak_mb = mem["peak_kb"] / 1024.0
    print(
        f"memory: 3163 x 3163 = {mem['poses']} poses map in a fresh process: "
        f"{mem['seconds']:.2f} s, peak RSS {peak_mb:.0f} MB "
        f"(imports alone {mem['before_kb'] / 1024.0:.0f} MB)"
    )
    context = ""
    if not args.design:
        n_ctx = 20_000 if args.quick else 100_000
        print(
            f"context: scattered poses (evaluate_poses, random phi, {n_ctx}): "
            f"{time_scattered(n_ctx * 5):,.0f} poses/s; general 22-spring model batched "
            f"with numpy ({n_ctx // 5} poses, K only): {time_general_numpy(n_ctx // 5):,.0f} "
            "poses/s"
        )
        n_gen = 4000 if args.quick else 20_000
        rates = {}
        for name in GENERAL_DESIGNS:
            other = (
                default_design()
                if name == "paper_3ppr"
                else load_design(os.path.join(EXAMPLES, f"{name}.toml"))
            )
            rates[f"planar_{name}"] = time_general_path(other, n_gen * 5, "planar")
            rates[f"general_{name}"] = time_general_path(other, n_gen, "general")
            print(
                f"evaluate_poses, {other.architecture} ({name}): planar engine "
                f"{rates[f'planar_{name}']:,.0f} poses/s ({n_gen * 5} poses), general "
                f"reference path {rates[f'general_{name}']:,.0f} poses/s ({n_gen} poses)"
            )
        context = " " + " ".join(f"{k}_poses_per_s={v:.0f}" for k, v in rates.items())
    print(
        f"batched_poses_per_s={batched_rate:.0f} loop_poses_per_s={loop_rate:.0f} "
        f"ratio={ratio:.0f} peak_mb_1e7={peak_mb:.0f}" + extra + context
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
