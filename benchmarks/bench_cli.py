"""Cold start of the command line: ``ppm-stiffness --help`` against a bare interpreter.

Runs each command line ``--repeat`` times (default 7) in fresh processes, interleaved
so that both see the same machine load, and prints the medians. Last line:
``bare_python_s=... help_s=... help_minus_bare_s=... command_help_s=...`` (the last one
is ``ppm-stiffness map --help``).

Run: ``.venv/bin/python benchmarks/bench_cli.py [--repeat N]``.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time

LINES = {
    "bare_python_s": [sys.executable, "-c", "pass"],
    "help_s": [sys.executable, "-m", "ppm_stiffness", "--help"],
    "command_help_s": [sys.executable, "-m", "ppm_stiffness", "map", "--help"],
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    times: dict[str, list[float]] = {key: [] for key in LINES}
    for _ in range(args.repeat):
        for key, cmd in LINES.items():
            start = time.perf_counter()
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
            times[key].append(time.perf_counter() - start)
    med = {key: statistics.median(v) for key, v in times.items()}
    med["help_minus_bare_s"] = med["help_s"] - med["bare_python_s"]
    order = ("bare_python_s", "help_s", "help_minus_bare_s", "command_help_s")
    print(" ".join(f"{key}={med[key]:.3f}" for key in order))


if __name__ == "__main__":
    main()
