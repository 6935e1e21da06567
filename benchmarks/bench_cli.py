"""Cold start of the command line: ``ppm-stiffness --help`` and every
``ppm-stiffness COMMAND --help`` against a bare interpreter.

Runs each command line ``--repeat`` times (default 5) in fresh processes, interleaved
so that all see the same machine load, and prints the medians; the load average is
printed before and after. Last line: ``bare_python_s=... help_s=...
help_minus_bare_s=... command_help_s=... slowest_command=NAME
slowest_command_help_s=... slowest_over_help_s=...`` (``command_help_s`` is
``ppm-stiffness map --help``; the target is ``slowest_over_help_s`` <= 0.1).

``--smoke``: one run of the bare interpreter, ``--help``, ``map --help`` and ``deflect
--help`` only (the other commands skipped; a check that the script runs).
Run: ``.venv/bin/python benchmarks/bench_cli.py [--repeat N] [--smoke]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

from ppm_stiffness.cli import COMMANDS

LINES = {
    "bare_python_s": [sys.executable, "-c", "pass"],
    "help_s": [sys.executable, "-m", "ppm_stiffness", "--help"],
    **{name: [sys.executable, "-m", "ppm_stiffness", name, "--help"] for name in COMMANDS},
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--smoke", action="store_true", help="one run, 2 commands")
    args = parser.parse_args()
    commands = ["map", "deflect"] if args.smoke else list(COMMANDS)
    lines = {k: v for k, v in LINES.items() if k in ("bare_python_s", "help_s", *commands)}
    repeat = 1 if args.smoke else args.repeat
    print("load average before: " + " ".join(f"{x:.2f}" for x in os.getloadavg()))
    times: dict[str, list[float]] = {key: [] for key in lines}
    for _ in range(repeat):
        for key, cmd in lines.items():
            start = time.perf_counter()
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
            times[key].append(time.perf_counter() - start)
    print("load average after: " + " ".join(f"{x:.2f}" for x in os.getloadavg()))
    med = {key: statistics.median(v) for key, v in times.items()}
    for name in commands:
        print(f"{name} --help: {med[name]:.3f} s ({med[name] - med['help_s']:+.3f} s)")
    slowest = max(commands, key=lambda name: med[name])
    print(
        f"bare_python_s={med['bare_python_s']:.3f} help_s={med['help_s']:.3f} "
        f"help_minus_bare_s={med['help_s'] - med['bare_python_s']:.3f} "
        f"command_help_s={med['map']:.3f} slowest_command={slowest} "
        f"slowest_command_help_s={med[slowest]:.3f} "
        f"slowest_over_help_s={med[slowest] - med['help_s']:.3f}"
    )


if __name__ == "__main__":
    main()
