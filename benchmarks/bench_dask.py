"""A sweep on a real Dask cluster started by the ``dask`` command line, against serial
and 2 local processes, side by side in one run.

Starts ``dask scheduler`` and ``dask worker --nworkers 2 --nthreads 1`` (default
workers: a nanny each, which sets ``MALLOC_TRIM_THRESHOLD_=65536``) on 127.0.0.1 as
subprocesses, then times the same sweep (``--designs`` values of
``leg*.platform_radius`` of the shipped 3-RRR over a 25 x 25 x 16 region: 10,000 poses
per design, actuators locked) serially in this process (with the allocator tuned, as
the command line does), on 2 local processes (``--workers 2``) and on the cluster
through ``ppm_stiffness.optimize.executors.dask_executor`` (``--scheduler``). Executors
are started and warmed (a sweep of 4 designs) before the clock runs; the cluster's start-up is
printed as ``startup_s`` and not timed. The executors run in turn, ``--repeats`` rounds
(default 3), and the medians are compared, so that a load from other processes falls on
all three alike; the per-round ratios are printed too. The three results must be
identical (else exit status 1). The load average is printed before and after: the
machine may be shared.

``PPM_STIFFNESS_NO_MALLOPT=1`` in the environment (inherited by every process started)
measures the allocator as Dask leaves it. The Dask workers' minor page faults per design
are printed with each Dask round: a figure the machine's load does not change.

Last line: ``serial_s=... processes2_speedup=... dask2_speedup=... startup_s=...``.
``--smoke`` (a check that the script runs): 2 designs over a 5 x 5 x 4 region, one
round, serial and 2 local processes only: no Dask cluster is started (its start-up
alone costs several seconds of CPU time), ``dask2_speedup`` and ``startup_s`` print
``skipped``.
Run: ``.venv/bin/python benchmarks/bench_dask.py [--designs 256] [--repeats 3] [--smoke]``.
"""

from __future__ import annotations

import argparse
import os
import shutil
import socket
import statistics
import subprocess
import sys
import time
from concurrent.futures import Executor
from pathlib import Path

ROOT = Path(__file__).parents[1]
GRID = (25, 25, 16)  # 10,000 poses
SMOKE_GRID = (5, 5, 4)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _sweep(
    executor: Executor, designs: int, grid: tuple[int, int, int] = GRID
) -> tuple[float, list[object]]:
    import ppm_stiffness as pps
    from ppm_stiffness.optimize.region import make_region
    from ppm_stiffness.optimize.sweep import sweep_designs
    from ppm_stiffness.optimize.variables import parse_variable

    design = pps.load_design(ROOT / "examples/3rrr.toml")
    variable = parse_variable(f"leg*.platform_radius=0.05:0.07:{designs}", design, True)
    region = make_region((-0.01, 0.01), (-0.01, 0.01), (-0.1, 0.1), grid)
    start = time.perf_counter()
    result = sweep_designs(design, [variable], region, executor=executor, frequencies=False)
    return time.perf_counter() - start, [s.figures() for s in result.summaries]


def _minor_faults() -> int:
    """Minor page faults of this process so far (run on each Dask worker)."""
    import resource

    return int(resource.getrusage(resource.RUSAGE_SELF).ru_minflt)


def _load() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def _start_cluster(dask: str, port: int) -> list[subprocess.Popen[bytes]]:
    address = f"tcp://127.0.0.1:{port}"
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    scheduler = subprocess.Popen(
        [dask, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
        **quiet,  # type: ignore[call-overload]
    )
    worker = subprocess.Popen(
        [dask, "worker", address, "--nworkers", "2", "--nthreads", "1", "--no-dashboard"],
        **quiet,  # type: ignore[call-overload]
    )
    return [worker, scheduler]


def _smoke() -> int:
    """Serial and 2 local processes, 2 designs of 100 poses, one round (module doc)."""
    from ppm_stiffness._allocator import tune_allocator
    from ppm_stiffness.optimize.executors import SerialExecutor, process_executor

    print(f"load average before: {_load()}; cpus {os.cpu_count()}; tuned {tune_allocator()}")
    with process_executor(2) as pool:
        serial_s, serial = _sweep(SerialExecutor(), 2, SMOKE_GRID)
        pool_s, pooled = _sweep(pool, 2, SMOKE_GRID)
    print(f"load average after: {_load()}")
    same = pooled == serial
    print("results identical to serial" if same else "RESULTS DIFFER FROM SERIAL")
    print(
        f"serial_s={serial_s:.3f} processes2_speedup={serial_s / pool_s:.2f} "
        "dask2_speedup=skipped startup_s=skipped"
    )
    return 0 if same else 1


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=256)
    parser.add_argument("--repeats", type=int, default=3, help="rounds (medians kept)")
    parser.add_argument("--smoke", action="store_true", help="2 designs, no Dask cluster")
    args = parser.parse_args()
    if args.smoke:
        return _smoke()
    dask = shutil.which("dask", path=str(Path(sys.executable).parent)) or shutil.which("dask")
    if dask is None:
        print("the dask command line is not installed: pip install -e '.[dask]'")
        return 1
    from distributed import Client

    from ppm_stiffness._allocator import tune_allocator
    from ppm_stiffness.optimize.executors import SerialExecutor, dask_executor, process_executor

    print(f"load average before: {_load()}; cpus {os.cpu_count()}; tuned {tune_allocator()}")
    port = _free_port()
    start = time.perf_counter()
    procs = _start_cluster(dask, port)
    address = f"tcp://127.0.0.1:{port}"
    times: dict[str, list[float]] = {}
    results: dict[str, list[object]] = {}
    try:
        deadline = time.monotonic() + 60
        while True:  # the scheduler takes a moment to listen
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=1):
                    break
            except OSError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.1)
        with Client(address, timeout="60s") as client:
            client.wait_for_workers(2, timeout=60)
        startup = time.perf_counter() - start
        print(f"dask scheduler and 2 workers up in {startup:.2f} s")

        with process_executor(2) as pool, dask_executor(address) as on_dask:
            executors: dict[str, Executor] = {
                "serial": SerialExecutor(),
                "processes2": pool,
                "dask2": on_dask,
            }
            for executor in executors.values():
                _sweep(executor, 4)  # warm: imports and first calls in every worker
            client = on_dask._client  # type: ignore[attr-defined]
            for r in range(args.repeats):  # the executors in turn, so they share the load
                for name, executor in executors.items():
                    before = sum(client.run(_minor_faults).values())
                    t, results[name] = _sweep(executor, args.designs)
                    times.setdefault(name, []).append(t)
                    faults = ""
                    if name == "dask2":
                        after = sum(client.run(_minor_faults).values())
                        faults = f" ({(after - before) / args.designs:,.0f} minor faults/design)"
                    print(f"round {r + 1}, {name}: {args.designs} designs in {t:.3f} s{faults}")
    finally:
        for proc in procs:
            proc.terminate()
        for proc in procs:
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                proc.kill()
    print(f"load average after: {_load()}")
    same = all(r == results["serial"] for r in results.values())
    print("results identical to serial" if same else "RESULTS DIFFER FROM SERIAL")
    med = {name: statistics.median(t) for name, t in times.items()}
    for name in ("processes2", "dask2"):
        ratios = [s / t for s, t in zip(times["serial"], times[name], strict=True)]
        print(f"{name} speed-up per round: {', '.join(f'{x:.2f}' for x in ratios)}")
    print(
        f"serial_s={med['serial']:.3f} "
        f"processes2_speedup={med['serial'] / med['processes2']:.2f} "
        f"dask2_speedup={med['serial'] / med['dask2']:.2f} startup_s={startup:.2f}"
    )
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
