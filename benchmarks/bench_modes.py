"""Benchmark of the first-frequency map: ``map --quantities f1`` against a loop over the
single-pose modal analysis.

On a shipped spatial example (``--design FILE``, default examples/hexapod_6ups.toml) on
its default slice (x-y at the home pose's other coordinates, or its first two task
coordinates), locked actuators, measured in one run; the machine's load
(``os.getloadavg``) is printed before and after:

- poses per second of ``workspace.stiffness_map(..., quantities=["f1"])`` on a 100 x 100
  grid (10^4 poses; ``--grid N``), median of five runs, by the wall clock
  (``f1_map_poses_per_s``; the issue's target: 10^4 poses in under 1 s, i.e. at least
  10^4 poses/s) and by the process's CPU time (``f1_map_cpu_poses_per_s``); the same map
  of ``translational_min`` alone for context (``stiffness_map_poses_per_s``);
- poses per second of ``mass_matrix`` alone at the map's valid poses
  (``mass_matrix_poses_per_s``);
- poses per second of a loop of ``stiffness_at_pose`` + ``mass_matrix_at_pose`` +
  ``mode_shapes`` (``loop_poses_per_s``) over every k-th valid grid pose (200 poses;
  ``--loop N``), and the largest relative differences on them of the map's f1 to the
  loop's (``max_rel_diff``) and of the batched ``mass_matrix`` to ``mass_matrix_at_pose``
  (``max_rel_diff_m``, relative to the largest entry of each M); both must be at most
  1e-12, else the exit status is 1.

- with the legs' own modes (issue 30 item 5; ``--link-modes N``, default 2 per leg):
  the same f1 map's process CPU time (``f1_link_map_cpu_s``, one run: the issue's
  target is under 2 s for 10^4 hexapod poses with two modes per strut) beside the
  condensed map's (``f1_map_cpu_s``, median), measured in the same run, and the
  largest relative difference of its f1 to ``modal_analysis(..., link_modes=N)`` at
  5 valid grid poses (``max_rel_diff_link``, at most 1e-10 else exit status 1).

The last line is ``f1_map_poses_per_s=N f1_map_cpu_poses_per_s=N
stiffness_map_poses_per_s=N mass_matrix_poses_per_s=N loop_poses_per_s=N ratio=N
max_rel_diff=X max_rel_diff_m=X``; the line before it ``link_modes=N
f1_link_map_cpu_s=X f1_map_cpu_s=X cpu_ratio=X max_rel_diff_link=X``. The BLAS pool
is reported (``OPENBLAS_NUM_THREADS``): under load, a multi-threaded pool spends
several times the CPU of one thread on these small matrices; run with
``OPENBLAS_NUM_THREADS=1``.
``--smoke``: a 4 x 4 grid, a loop of 3 poses, one run of each map (a check that the
script runs).
Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/bench_modes.py [--design FILE]
[--grid N] [--loop N] [--link-modes N] [--smoke]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numpy as np
from _common import load_text

from ppm_stiffness.design import Design, load_design
from ppm_stiffness.dynamics.mass import mass_matrix, mass_matrix_at_pose
from ppm_stiffness.dynamics.modes import mode_shapes
from ppm_stiffness.maps.result import StiffnessMap
from ppm_stiffness.maps.workspace import stiffness_map
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.poses import full_poses

#: Largest admissible difference between the batched and the single-pose path.
AGREEMENT = 1e-12
#: The same with link modes (the map and ``modal_analysis`` share the legs' FE).
LINK_AGREEMENT = 1e-10
EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples")


def time_map(
    design: Design, grid: int, quantities: list[str], repeats: int, link_modes: int = 0
) -> tuple[float, float, StiffnessMap]:
    """Median wall-clock and CPU seconds of the map, and the map."""
    wall, cpu = [], []
    smap = None
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        smap = stiffness_map(design, grid=grid, quantities=quantities, link_modes=link_modes)
        wall.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    assert smap is not None
    return statistics.median(wall), statistics.median(cpu), smap


def grid_tasks(design: Design, smap: StiffnessMap) -> tuple[np.ndarray, np.ndarray]:
    """Task values (n, n_task) of the valid grid points and their flat indices."""
    jj, ii = np.nonzero(smap.reachable)
    values = {smap.axes[0]: smap.u[ii], smap.axes[1]: smap.v[jj]}
    values |= {k: np.full(ii.size, v) for k, v in smap.fixed.items()}
    tasks = np.column_stack([values[n] for n in design.task_coordinates])
    return tasks, np.ravel_multi_index((jj, ii), smap.reachable.shape)


def link_map(design: Design, grid: int, link_modes: int) -> tuple[float, float]:
    """CPU seconds of one f1 map with ``link_modes`` per leg, and the largest relative
    difference of its f1 to ``modal_analysis`` at 5 valid grid poses."""
    from ppm_stiffness.dynamics.analysis import modal_analysis

    c = time.process_time()
    smap = stiffness_map(design, grid=grid, quantities=["f1"], link_modes=link_modes)
    cpu = time.process_time() - c
    tasks, flat = grid_tasks(design, smap)
    poses, _ = full_poses(design, tasks)
    f1 = smap.quantities["f1"].filled(np.nan).ravel()[flat]
    diff = 0.0
    for i in np.linspace(0, poses.shape[0] - 1, min(5, poses.shape[0])).astype(int):
        single = modal_analysis(design, poses[i], link_modes=link_modes).frequencies[0]
        diff = max(diff, abs(f1[i] - single) / single)
    return cpu, diff


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--design", default=os.path.join(EXAMPLES, "hexapod_6ups.toml"))
    parser.add_argument("--grid", type=int, default=100, help="N x N grid (default 100)")
    parser.add_argument("--loop", type=int, default=200, help="poses of the loop (200)")
    parser.add_argument("--link-modes", type=int, default=2, help="modes per leg (2)")
    parser.add_argument("--smoke", action="store_true", help="4 x 4 grid, 3 poses, 1 run")
    args = parser.parse_args(argv)
    repeats = 1 if args.smoke else 5
    if args.smoke:
        args.grid, args.loop = 4, 3
    design = load_design(args.design)
    threads = os.environ.get("OPENBLAS_NUM_THREADS", "unset")
    print(
        f"{design.name}: {args.grid} x {args.grid} grid; OPENBLAS_NUM_THREADS={threads}; "
        f"before the runs: {load_text()}"
    )
    for modes in (0, args.link_modes):  # warm up imports
        stiffness_map(design, grid=min(4, args.grid), quantities=["f1"], link_modes=modes)
    wall, cpu, smap = time_map(design, args.grid, ["f1"], repeats)
    link_cpu, link_diff = link_map(design, args.grid, args.link_modes)
    wall_k, _, _ = time_map(design, args.grid, ["translational_min"], repeats)
    n = smap.reachable.size
    tasks, flat = grid_tasks(design, smap)
    poses, _ = full_poses(design, tasks)
    t = time.process_time()
    batched_m = mass_matrix(design, poses)
    m_rate = poses.shape[0] / (time.process_time() - t)

    step = max(1, poses.shape[0] // args.loop)
    subset = np.arange(0, poses.shape[0], step)[: args.loop]
    f1_map = smap.quantities["f1"].filled(np.nan).ravel()[flat]
    diff_f, diff_m = 0.0, 0.0
    t = time.perf_counter()
    for i in subset:
        k = stiffness_at_pose(design, poses[i])
        m = mass_matrix_at_pose(design, poses[i])
        f1 = mode_shapes(k, m).frequencies[0]
        diff_f = max(diff_f, abs(f1_map[i] - f1) / f1)
        diff_m = max(diff_m, float(np.max(np.abs(batched_m[i] - m)) / np.max(np.abs(m))))
    loop_rate = subset.size / (time.perf_counter() - t)
    rate = n / wall
    print(
        f"f1 map: {n} poses ({np.mean(smap.reachable):.1%} valid) in {wall:.3f} s wall, "
        f"{cpu:.3f} s CPU (median of {repeats}); translational_min alone {wall_k:.3f} s"
    )
    print(f"after the runs: {load_text()}")
    print(
        f"link_modes={args.link_modes} f1_link_map_cpu_s={link_cpu:.3f} f1_map_cpu_s={cpu:.3f} "
        f"cpu_ratio={link_cpu / cpu:.1f} max_rel_diff_link={link_diff:.2e}"
    )
    print(
        f"f1_map_poses_per_s={rate:.0f} f1_map_cpu_poses_per_s={n / cpu:.0f} "
        f"stiffness_map_poses_per_s={n / wall_k:.0f} mass_matrix_poses_per_s={m_rate:.0f} "
        f"loop_poses_per_s={loop_rate:.0f} ratio={rate / loop_rate:.0f} "
        f"max_rel_diff={diff_f:.2e} max_rel_diff_m={diff_m:.2e}"
    )
    if max(diff_f, diff_m) > AGREEMENT:
        print(f"batched and single-pose paths differ by more than {AGREEMENT:g}")
        return 1
    if link_diff > LINK_AGREEMENT:
        print(f"the link-modes map and modal_analysis differ by more than {LINK_AGREEMENT:g}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
