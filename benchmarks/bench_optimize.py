"""Designs per second of a sweep on each executor, side by side in one run.

The same sweep (``--designs`` values of ``leg*.platform_radius`` of the shipped 3-RRR,
over its ``[workspace.required]`` region: 405 poses, actuators locked; ``--wrench``
adds the loaded state at every pose) is evaluated serially, on 2 local processes
(``--workers 2``) and on a Dask ``LocalCluster`` of 2 single-threaded worker processes.
Each executor is started and warmed up (one task per worker) before the clock runs, so
the figures are throughput, not start-up; the start-up times are printed apart. The
results of the three runs are checked to be identical.

Last line: ``serial_designs_per_s=... workers2_designs_per_s=... dask2_designs_per_s=...
speedup_workers2=... speedup_dask2=... cpus=...``.

Run: ``.venv/bin/python benchmarks/bench_optimize.py [--designs N] [--wrench]``
(the Dask run needs the ``dask`` extra).
"""

from __future__ import annotations

import argparse
import os
import time
from concurrent.futures import Executor
from pathlib import Path

ROOT = Path(__file__).parents[1]


def _sweep(executor: Executor, designs: int, wrench: bool) -> tuple[float, list[object]]:
    import ppm_stiffness as pps
    from ppm_stiffness.optimize.region import region_of
    from ppm_stiffness.optimize.sweep import sweep_designs
    from ppm_stiffness.optimize.variables import parse_variable

    design = pps.load_design(ROOT / "examples/3rrr.toml")
    variable = parse_variable(f"leg*.platform_radius=0.05:0.07:{designs}", design, True)
    w = [0.0, 0.0, 0.2, 5.0, -3.0, 0.0] if wrench else None
    start = time.perf_counter()
    result = sweep_designs(design, [variable], region_of(design), wrench=w, executor=executor)
    elapsed = time.perf_counter() - start
    return elapsed, [s.figures() for s in result.summaries]


def _warm(executor: Executor, workers: int) -> None:
    from ppm_stiffness.optimize.executors import limit_threads

    for future in [executor.submit(limit_threads) for _ in range(workers)]:
        future.result()
    _sweep(executor, 2, False)  # imports and first calls in every worker


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=64)
    parser.add_argument("--wrench", action="store_true", help="add the loaded state")
    args = parser.parse_args()
    from ppm_stiffness.optimize.executors import SerialExecutor, process_executor

    rate: dict[str, float] = {}
    results: dict[str, list[object]] = {}
    t, results["serial"] = _sweep(SerialExecutor(), args.designs, args.wrench)
    t, results["serial"] = _sweep(SerialExecutor(), args.designs, args.wrench)  # warm
    rate["serial"] = args.designs / t
    print(f"serial: {args.designs} designs in {t:.3f} s")

    start = time.perf_counter()
    with process_executor(2) as pool:
        _warm(pool, 2)
        print(f"workers2: pool start-up and warm-up {time.perf_counter() - start:.2f} s")
        t, results["workers2"] = _sweep(pool, args.designs, args.wrench)
    rate["workers2"] = args.designs / t
    print(f"workers2: {args.designs} designs in {t:.3f} s")

    try:
        from distributed import Client, LocalCluster
    except ImportError:
        print("dask2: skipped (distributed is not installed: pip install -e '.[dask]')")
        rate["dask2"] = float("nan")
    else:
        start = time.perf_counter()
        with (
            LocalCluster(
                n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
            ) as cluster,
            Client(cluster) as client,
        ):
            executor = client.get_executor()
            _warm(executor, 2)
            print(f"dask2: cluster start-up and warm-up {time.perf_counter() - start:.2f} s")
            t, results["dask2"] = _sweep(executor, args.designs, args.wrench)
        rate["dask2"] = args.designs / t
        print(f"dask2: {args.designs} designs in {t:.3f} s")
    for name, figures in results.items():
        assert figures == results["serial"], f"{name} differs from serial"
    print(
        f"serial_designs_per_s={rate['serial']:.2f} workers2_designs_per_s={rate['workers2']:.2f} "
        f"dask2_designs_per_s={rate['dask2']:.2f} "
        f"speedup_workers2={rate['workers2'] / rate['serial']:.2f} "
        f"speedup_dask2={rate['dask2'] / rate['serial']:.2f} cpus={os.cpu_count()}"
    )


if __name__ == "__main__":
    main()
