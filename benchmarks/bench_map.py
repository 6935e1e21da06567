"""Benchmark of the stiffness map: batched path against a loop over the single-pose API.

Measured side by side in one run, on the built-in design (or ``--design FILE``, any
design: the hexapod and tripods too) on its default map (a planar design: x-y at
phi = 0; a spatial one: x-y, or its first two task coordinates, at the home pose's
other coordinates) with locked actuators; the machine's load (``os.getloadavg``) is
printed before and after:

- poses per second of ``workspace.stiffness_map`` (K, the principal stiffnesses of the
  design's default quantities: the paper's k_phi, k_x, k_y for a planar design, the six
  spatial ones for others; reachability and singularity masks) on a 1000 x 1000 grid
  (``--quick``: 300 x 300), median of three runs, by the wall clock and by the process's
  CPU time (``batched_cpu_poses_per_s``), on the path ``"auto"`` takes (the P-P-R reduced
  form, else the planar engine, else the general engine);
- on a design whose legs all offer the reduced form (P-P-R): the same map by the planar
  engine (``path="planar"``), the general engine of any architecture, and its rate
  over the reduced form's (``general_vs_reduced``), measured alternately in the same run;
- poses per second of a loop of ``model.stiffness_at_pose`` + ``decoupling.decouple``
  (a planar design) or + ``principal.principal_compliance`` at the tool point (others)
  on a subset of the same grid poses (every k-th one; 2000 poses, ``--quick``: 200), and
  the largest relative difference of the map's quantities to the loop's on that subset
  (``max_rel_diff``, relative to the largest value of each quantity set) and of the
  batched K (``batch.evaluate_poses`` with the matrices, length-balanced, relative to
  its largest entry: ``max_rel_diff_k``); both must be at most 1e-12 (else the exit
  status is 1);
- for context: the scattered-pose batched path (``batch.evaluate_poses`` on random
  poses with random phi) and the general 22-spring model batched with numpy
  (``chain.leg_springs`` + ``solver.bordered_stiffness``), which is what the reduced form
  replaces;
- the peak resident memory of a fresh process computing a 3163 x 3163 (> 10^7 poses;
  ``--memory-grid N``: N x N) map of the design, and of the same process before the
  map (imports only);
- for context, without ``--design``: ``batch.evaluate_poses`` on random poses over each
  shipped design's workspace box at phi = 0 by the planar engine
  (``planar_<design>_poses_per_s``) and by the general reference path (IK, chain
  springs, bordered inverse: ``general_<design>_poses_per_s``), 20 000 poses
  (``--quick``: 4000), best of two.

- a map call's fixed cost (``map_fixed_ms``): the median time of ``stiffness_map`` on a
  2 x 2 grid (everything but the per-pose work: bounds, path choice, the legs' reduced
  forms, result assembly), called 30 times on one design object after a first call;
  ``--fixed-only`` prints only this (a few seconds).

The last line is ``batched_poses_per_s=N loop_poses_per_s=N ratio=N
batched_cpu_poses_per_s=N max_rel_diff=X max_rel_diff_k=X peak_mb_1e7=N (peak_mb_gridN with
--memory-grid N)
[general_poses_per_s=N general_vs_reduced=R] [planar_<design>_poses_per_s=N
general_<design>_poses_per_s=N ...] map_fixed_ms=X extent_cpu_s=X`` (the map's rates are
over its default extent computed once beforehand, ``extent_cpu_s``, apart).
``--smoke``: a 10 x 10 map run once, a loop of 5 poses, a 10 x 10 memory run, 100
scattered poses, 20 per design for the context, 2 fixed-cost calls (a check that the
script runs; ``peak_mb_grid10``).
Run: ``.venv/bin/python benchmarks/bench_map.py [--design FILE] [--quick | --smoke]``.
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
from _common import load_text

from ppm_stiffness.core import solver
from ppm_stiffness.core.conventions import length_balanced
from ppm_stiffness.core.decoupling import decouple
from ppm_stiffness.core.errors import SingularConfigurationError, UnreachablePoseError
from ppm_stiffness.core.principal import principal_compliance
from ppm_stiffness.design import Design, default_design, load_design
from ppm_stiffness.legs.chain import leg_springs
from ppm_stiffness.maps import batch
from ppm_stiffness.maps.reduced_leg import reduced_design
from ppm_stiffness.maps.workspace import StiffnessMap, stiffness_map, workspace_bounds
from ppm_stiffness.model import stiffness_at_pose, stiffness_at_tool_point, validate_pose

#: Largest admissible difference between the batched and the single-pose path.
AGREEMENT = 1e-12

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


def default_extent(design: Design) -> tuple[np.ndarray, float]:
    """The default map's extent (the reachable box of its slice, sampled on a 101 x 101
    grid: ``maps.slices.slice_bounds``) and its CPU seconds: computed once, apart from
    the map's own rate (for a chain-leg design it costs as much as some 30,000 poses of
    inverse kinematics, whatever the map's size)."""
    from ppm_stiffness.maps.slices import map_slice, slice_grid

    c = time.process_time()
    # the corners of a 2 x 2 default grid: the extent shrunk as the map shrinks it (no
    # grid point exactly on a limit, where the map and the single-pose API may differ
    # by round-off)
    u, v = slice_grid(design, map_slice(design), 2)
    box = np.array([u[0], u[-1], v[0], v[-1]])
    return box, time.process_time() - c


def time_map(
    design: Design,
    grid: int,
    repeats: int = 3,
    path: batch.Path = "auto",
    bounds: np.ndarray | None = None,
) -> tuple[float, float, StiffnessMap]:
    """Median wall-clock and CPU seconds of the design's default map over ``bounds``
    (the default extent if None), and the map."""
    times, cpu = [], []
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        smap = stiffness_map(design, actuators="max", grid=grid, path=path, bounds=bounds)
        times.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    return statistics.median(times), statistics.median(cpu), smap


def time_paths(
    design: Design, grid: int, repeats: int = 3, bounds: np.ndarray | None = None
) -> tuple[float, float]:
    """Median seconds of the reduced and the planar map, runs alternated."""
    reduced, planar = [], []
    for _ in range(repeats):
        reduced.append(time_map(design, grid, 1, "reduced", bounds)[0])
        planar.append(time_map(design, grid, 1, "planar", bounds)[0])
    return statistics.median(reduced), statistics.median(planar)


def grid_pose(design: Design, smap: StiffnessMap, i: int, j: int) -> np.ndarray:
    """The task values of grid point (j, i)."""
    values = dict(smap.fixed) | {smap.axes[0]: smap.u[i], smap.axes[1]: smap.v[j]}
    return np.array([values[name] for name in design.task_coordinates])


def single_quantities(design: Design, k: np.ndarray, pose: np.ndarray) -> list[np.ndarray]:
    """The map's default quantities by the single-pose path, as sets compared each to
    their largest value: [k_phi], [k_x, k_y] (planar); rotational, translational at the
    tool point (ascending; others)."""
    if design.planar:
        tool = np.asarray(design.tool_point, dtype=float)
        dec = decouple(stiffness_at_tool_point(k, pose, tool) if np.any(tool) else k, "paper")
        return [np.array([dec.rotational_values[2]]), np.asarray(dec.translational_values[:2])]
    k_t = stiffness_at_tool_point(k, validate_pose(design, pose), design.tool_point)
    pc = principal_compliance(k_t)
    return [np.sort(pc.rotational_values), np.sort(pc.translational_values)]


def time_loop(design: Design, smap: StiffnessMap, n_loop: int) -> tuple[float, int, float, float]:
    """Seconds for the single-pose loop on ``n_loop`` grid poses, their count, the largest
    relative difference of the map's quantities and of the batched K (module doc)."""
    us, vs = smap.u, smap.v
    total = us.size * vs.size
    step = max(total // n_loop, 1)
    flat = np.arange(0, total, step)[:n_loop]
    results = []
    t = time.perf_counter()
    for n in flat:
        j, i = divmod(int(n), us.size)
        pose = grid_pose(design, smap, i, j)
        try:
            k = stiffness_at_pose(design, pose)
        except (UnreachablePoseError, SingularConfigurationError):
            results.append((j, i, pose, None, None))
            continue
        results.append((j, i, pose, k, single_quantities(design, k, pose)))
    elapsed = time.perf_counter() - t
    names = list(smap.quantities)
    sets = [names[:1], names[1:3]] if design.planar else [names[:3], names[3:6]]
    worst = 0.0
    valid = [r for r in results if r[3] is not None]
    for j, i, _, k, ref in results:
        if k is None:
            assert not smap.reachable[j, i]
            continue
        assert smap.reachable[j, i]
        for group, values in zip(sets, ref, strict=True):
            got = np.array([float(smap.quantities[q][j, i]) for q in group])
            worst = max(worst, float(np.max(np.abs(got - values)) / np.max(np.abs(values))))
    if not valid:  # no reachable pose in the loop's subset (a tiny --smoke grid)
        return elapsed, len(flat), worst, 0.0
    poses = np.array([r[2] for r in valid])
    res = batch.evaluate_poses(design, poses, matrices=True)
    assert res.stiffness is not None and res.valid.all()
    a, b = length_balanced(res.stiffness), length_balanced(np.array([r[3] for r in valid]))
    worst_k = float(np.max(np.max(np.abs(a - b), axis=(1, 2)) / np.max(np.abs(b), axis=(1, 2))))
    return elapsed, len(flat), worst, worst_k


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


def time_fixed(design: Design, calls: int = 30) -> float:
    """Median time of a 2 x 2 map of ``design`` [ms] (its first call not counted)."""
    stiffness_map(design, grid=2)
    times = []
    for _ in range(calls):
        start = time.perf_counter()
        stiffness_map(design, grid=2)
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1e3


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--design", help="design file (default: the built-in 3-PPR)")
    parser.add_argument("--quick", action="store_true", help="smaller grid and loop (< 1 min)")
    parser.add_argument(
        "--memory-grid",
        type=int,
        default=3163,
        metavar="N",
        help="N x N poses of the peak-memory run (default 3163: > 10^7 poses)",
    )
    parser.add_argument("--fixed-only", action="store_true", help="only map_fixed_ms")
    parser.add_argument("--smoke", action="store_true", help="tiniest sizes (runs or not)")
    args = parser.parse_args(argv)
    repeats = 1 if args.smoke else 3
    if args.smoke:
        args.memory_grid = 10
    if args.fixed_only:
        design = load_design(args.design) if args.design else default_design()
        print(f"design {design.name}; {load_text()}")
        print(f"map_fixed_ms={time_fixed(design):.2f}")
        return 0
    grid, n_loop = (10, 5) if args.smoke else (300, 200) if args.quick else (1000, 2000)
    design = load_design(args.design) if args.design else default_design()
    cores = os.cpu_count()
    print(
        f"machine: {cores} cores, numpy {np.__version__}, python {sys.version.split()[0]}; "
        f"design {design.name} ({design.architecture}); {load_text()}"
    )

    bounds, extent_cpu = default_extent(design)
    print(f"default extent (101 x 101 reachable samples of the slice): {extent_cpu:.3f} s CPU")
    seconds, cpu_seconds, smap = time_map(design, grid, repeats, bounds=bounds)
    n_map = grid * grid
    batched_rate = n_map / seconds
    cpu_rate = n_map / cpu_seconds
    reduced = reduced_design(design) is not None
    kind = "reduced" if reduced else ("planar" if design.planar else "general")
    slice_text = ", ".join(f"{k} = {v:.4g}" for k, v in smap.fixed.items())
    print(
        f"batched map {smap.axes[0]}-{smap.axes[1]} at {slice_text} (SI), {grid} x {grid} = "
        f"{n_map} poses ({kind} path; {', '.join(smap.quantities)}): {seconds:.3f} s "
        f"(median of {repeats}), {batched_rate:,.0f} poses/s ({cpu_rate:,.0f} poses/s of CPU "
        f"time), {int(smap.reachable.sum())} in the workspace"
    )

    loop_s, n_done, worst, worst_k = time_loop(design, smap, n_loop)
    loop_rate = n_done / loop_s
    what = "decouple" if design.planar else "principal_compliance"
    print(
        f"single-pose loop (stiffness_at_pose + {what}) on {n_done} of the same poses: "
        f"{loop_s:.3f} s, {loop_rate:,.0f} poses/s ({1e6 / loop_rate:.0f} us/pose); "
        f"largest relative difference to the map {worst:.1e}, of the batched K "
        f"(length-balanced) {worst_k:.1e}"
    )
    ratio = batched_rate / loop_rate
    print(f"ratio batched / loop: {ratio:,.0f}x")
    extra = ""
    if reduced:
        red_s, gen_s = time_paths(design, grid, repeats, bounds)
        general_rate, reduced_rate = n_map / gen_s, n_map / red_s
        print(
            f"same map, runs alternated (median of {repeats}): reduced form {reduced_rate:,.0f} "
            f"poses/s, planar engine (any architecture) {general_rate:,.0f} poses/s, "
            f"ratio {general_rate / reduced_rate:.3f}"
        )
        extra = (
            f" general_poses_per_s={general_rate:.0f} "
            f"general_vs_reduced={general_rate / reduced_rate:.3f}"
        )

    mem = peak_memory(args.memory_grid, args.design)
    peak_mb = mem["peak_kb"] / 1024.0
    print(
        f"memory: {args.memory_grid} x {args.memory_grid} = {mem['poses']} poses map in a "
        "fresh process: "
        f"{mem['seconds']:.2f} s, peak RSS {peak_mb:.0f} MB "
        f"(imports alone {mem['before_kb'] / 1024.0:.0f} MB)"
    )
    context = ""
    if not args.design:
        n_ctx = 100 if args.smoke else 20_000 if args.quick else 100_000
        print(
            f"context: scattered poses (evaluate_poses, random phi, {n_ctx}): "
            f"{time_scattered(n_ctx * 5):,.0f} poses/s; general 22-spring model batched "
            f"with numpy ({n_ctx // 5} poses, K only): {time_general_numpy(n_ctx // 5):,.0f} "
            "poses/s"
        )
        n_gen = 20 if args.smoke else 4000 if args.quick else 20_000
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
    calls = 2 if args.smoke else 30
    fixed_ms = time_fixed(design, calls)
    print(f"a map call's fixed cost (2 x 2 grid, median of {calls}): {fixed_ms:.2f} ms")
    memory_key = "peak_mb_1e7" if args.memory_grid == 3163 else f"peak_mb_grid{args.memory_grid}"
    print(f"after the runs: {load_text()}")
    print(
        f"batched_poses_per_s={batched_rate:.0f} loop_poses_per_s={loop_rate:.0f} "
        f"ratio={ratio:.0f} batched_cpu_poses_per_s={cpu_rate:.0f} max_rel_diff={worst:.1e} "
        f"max_rel_diff_k={worst_k:.1e} {memory_key}={peak_mb:.0f}"
        + extra
        + context
        + f" map_fixed_ms={fixed_ms:.2f} extent_cpu_s={extent_cpu:.3f}"
    )
    if max(worst, worst_k) > AGREEMENT:
        print(f"batched and single-pose paths differ by more than {AGREEMENT:g}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
