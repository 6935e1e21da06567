"""Designs per second of a serial design sweep at 10,000 poses per design.

The sweep: ``--designs`` values (default 1,000) of ``leg*.platform_radius`` of the
shipped 3-RRR over a 25 x 25 x 16 region (x, y in +-10 mm, phi in +-0.1 rad: 10,000
poses), actuators locked, evaluated serially in this process by
``ppm_stiffness.optimize.sweep.sweep_designs`` (the stiffness summary figures of every
design; ``frequencies=False``: the example's mass model would add its f1 figures, which
cost several times the stiffness ones),
with glibc's malloc thresholds raised as the command line raises them
(``ppm_stiffness._allocator``; ``--untuned`` leaves them alone). A warm-up sweep of 4
designs runs first. The load average is printed before and after: the machine may be
shared. Executors (2 local processes, a Dask cluster) are compared by
``benchmarks/bench_dask.py``.

Last line: ``designs_per_s=... seconds=... cpu_seconds=... designs=... poses=...
tuned=...`` (the CPU time of this process: less sensitive to other processes than the
wall-clock time, not insensitive: they share the caches and memory bandwidth).
``--smoke``: 2 designs over a 5 x 5 x 4 region, a warm-up of 2 (a check that the
script runs; ``poses=`` then says 100).
Run: ``.venv/bin/python benchmarks/bench_optimize.py [--designs N] [--untuned] [--smoke]``.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

ROOT = Path(__file__).parents[1]
GRID = (25, 25, 16)  # 10,000 poses
SMOKE_GRID = (5, 5, 4)


def _sweep(designs: int, grid: tuple[int, int, int] = GRID) -> tuple[float, float]:
    import ppm_stiffness as pps
    from ppm_stiffness.optimize.region import make_region
    from ppm_stiffness.optimize.sweep import sweep_designs
    from ppm_stiffness.optimize.variables import parse_variable

    design = pps.load_design(ROOT / "examples/3rrr.toml")
    variable = parse_variable(f"leg*.platform_radius=0.05:0.07:{designs}", design, True)
    region = make_region((-0.01, 0.01), (-0.01, 0.01), (-0.1, 0.1), grid)
    start, cpu = time.perf_counter(), time.process_time()
    result = sweep_designs(design, [variable], region, frequencies=False)
    elapsed, cpu = time.perf_counter() - start, time.process_time() - cpu
    assert len(result.summaries) == designs
    return elapsed, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=1000)
    parser.add_argument("--untuned", action="store_true", help="leave malloc alone")
    parser.add_argument("--smoke", action="store_true", help="2 designs, 100 poses")
    args = parser.parse_args()
    grid = SMOKE_GRID if args.smoke else GRID
    if args.smoke:
        args.designs = 2
    tuned = False
    if not args.untuned:
        from ppm_stiffness._allocator import tune_allocator

        tuned = tune_allocator()
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    _sweep(2 if args.smoke else 4, grid)
    t, cpu = _sweep(args.designs, grid)
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    each_ms = 1e3 * t / args.designs
    poses = grid[0] * grid[1] * grid[2]
    print(
        f"{args.designs} designs x {poses:,} poses in {t:.2f} s ({each_ms:.2f} ms each; "
        f"{cpu:.2f} s of CPU time)"
    )
    print(
        f"designs_per_s={args.designs / t:.1f} seconds={t:.2f} cpu_seconds={cpu:.2f} "
        f"designs={args.designs} poses={poses} tuned={tuned}"
    )


if __name__ == "__main__":
    main()
