"""Benchmark of the load-margin map (issue 32, item 2): ``stiffness_map(...,
quantities=["load_margin"], actuators="wrench")`` of the 3-RRR and of the hexapod.

Each design (examples/3rrr.toml, examples/hexapod_6ups.toml) on its default slice, a
10 x 10 grid (``--grid N``), under a wrench that gives finite margins (:data:`CASES`:
limit points or bifurcations within the range searched at most poses). Each map is
computed in a fresh interpreter (``--worker``) with this checkout's ``src`` first on
``PYTHONPATH``, once, timed by the process's CPU time
and the wall clock; the machine's load (``os.getloadavg``) is printed before and after.

``--baseline SRC``: the same maps with the library at ``SRC`` (a ``src`` directory of
another checkout, e.g. the code before a change: ``git worktree add /tmp/old COMMIT``
and ``--baseline /tmp/old/src``) put first on ``PYTHONPATH``, in the same run, its
figures printed beside with the ratio (``*_speedup``, by CPU time per pose) and the
largest relative difference of the margins (``*_max_rel_diff``, over the poses with a
finite margin in both; the same poses must be refused or unlimited, else exit status 1;
a difference above 1e-8 also gives exit status 1).

The last line is ``rrr_s=X rrr_poses_per_s=X hexapod_s=X hexapod_poses_per_s=X``
(CPU seconds of the map and reachable poses per CPU second), with ``rrr_old_s=X
rrr_old_poses_per_s=X rrr_speedup=X rrr_max_rel_diff=X`` and the same for the hexapod
added under ``--baseline``.
``--smoke``: a 3 x 3 grid, no baseline (a check that the script runs).
Run: ``OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/bench_margin.py [--grid N]
[--baseline SRC] [--smoke]``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

from _common import load_text

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "examples")
#: This checkout's library.
SRC = os.path.join(HERE, "..", "src")
#: Largest admissible relative difference of a margin to the baseline's.
AGREEMENT = 1e-8
#: (key, example file, wrench at P [N·m, N], axes of F_b).
CASES = (
    ("rrr", "3rrr.toml", (0.0, 0.0, 2.0, 400.0, 400.0, 0.0)),
    ("hexapod", "hexapod_6ups.toml", (2000.0, 2000.0, -5000.0, 20000.0, 20000.0, 50000.0)),
)


def worker(name: str, wrench: list[float], grid: int) -> None:
    """Compute one map and print its timing and values as one JSON line."""
    import numpy as np

    from ppm_stiffness.design import load_design
    from ppm_stiffness.maps.workspace import stiffness_map

    design = load_design(os.path.join(EXAMPLES, name))
    cpu, wall = time.process_time(), time.perf_counter()
    m = stiffness_map(
        design, actuators="wrench", wrench=wrench, grid=grid, quantities=["load_margin"]
    )
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    values = np.asarray(np.ma.filled(m.quantities["load_margin"], np.nan), dtype=float).ravel()
    print(json.dumps({"cpu": cpu, "wall": wall, "values": [float(v) for v in values]}))


def run(name: str, wrench: tuple[float, ...], grid: int, src: str) -> dict:
    """One map in a fresh interpreter with the library at ``src``."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.abspath(src) + os.pathsep + env.get("PYTHONPATH", "")
    out = subprocess.run(
        [sys.executable, __file__, "--worker", name, json.dumps(list(wrench)), str(grid)],
        capture_output=True,
        text=True,
        env=env,
        check=True,
    )
    result: dict = json.loads(out.stdout.strip().splitlines()[-1])
    return result


def compare(new: list[float], old: list[float]) -> tuple[float, bool]:
    """Largest relative difference over the finite pairs, and whether the NaN pattern
    agrees."""
    import numpy as np

    a, b = np.asarray(new), np.asarray(old)
    same = bool(np.array_equal(np.isnan(a), np.isnan(b)))
    both = np.isfinite(a) & np.isfinite(b)
    diff = np.abs(a[both] - b[both]) / np.abs(b[both])
    return float(np.max(diff, initial=0.0)), same


def main() -> int:
    if len(sys.argv) > 1 and sys.argv[1] == "--worker":
        worker(sys.argv[2], json.loads(sys.argv[3]), int(sys.argv[4]))
        return 0
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, default=10)
    parser.add_argument("--baseline", default=None, help="another checkout's src directory")
    parser.add_argument("--smoke", action="store_true")
    args = parser.parse_args()
    grid = 3 if args.smoke else args.grid
    baseline = None if args.smoke else args.baseline
    print(load_text(), "(before)")
    print(f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}")
    fields: list[str] = []
    status = 0
    for key, name, wrench in CASES:
        new = run(name, wrench, grid, SRC)
        poses = sum(1 for v in new["values"] if v == v)
        fields += [f"{key}_s={new['cpu']:.3f}", f"{key}_poses_per_s={poses / new['cpu']:.3g}"]
        print(
            f"{name}: {grid}x{grid} margin map, {poses} reachable poses, "
            f"{new['cpu']:.2f} s CPU ({new['wall']:.2f} s wall)"
        )
        if baseline is not None:
            old = run(name, wrench, grid, baseline)
            diff, same = compare(new["values"], old["values"])
            speedup = old["cpu"] / new["cpu"]
            print(
                f"  baseline: {old['cpu']:.2f} s CPU ({old['wall']:.2f} s wall): "
                f"{speedup:.1f}x; largest relative difference {diff:.2e}"
            )
            fields += [
                f"{key}_old_s={old['cpu']:.3f}",
                f"{key}_old_poses_per_s={poses / old['cpu']:.3g}",
                f"{key}_speedup={speedup:.3g}",
                f"{key}_max_rel_diff={diff:.2e}",
            ]
            if not same or diff > AGREEMENT:
                print(f"  DISAGREEMENT with the baseline (same refusals: {same})")
                status = 1
    print(load_text(), "(after)")
    print(" ".join(fields))
    return status


if __name__ == "__main__":
    sys.exit(main())
