"""Benchmark of the single-pose analysis through the public API.

``pose_us`` is the median over many calls of ``ppm_stiffness.analyze(design, pose)`` at
the workspace centre: K (inverse kinematics, joint chains, springs), the nonsingularity
check, the eigenscrews, the paper's decoupling and the least-squares one, the spatial
principal compliances and, for a design with a mass model, the first natural frequency,
as ``ppm-stiffness analyze`` prints them by default. For context, the medians of its
parts: ``model.stiffness_at_pose`` (K alone), ``analysis.analyze_matrix`` (eigenscrews,
both decouplings, principal compliances: ``matrix_us``), ``eigenscrews``,
``decouple(K, "paper")`` and ``dynamics.analysis.first_mode`` (``modes_us``: the mass
matrix by static condensation of the legs and the first mode).

Calls are timed in batches of 20 (the median of the per-call batch means), so that the
figure is robust to other processes on a shared machine.

The load average is printed before and after (the machine may be shared). The last
line is ``pose_us=N k_us=N eigenscrews_us=N decouple_us=N matrix_us=N modes_us=N``.
``--smoke``: one batch of each (a check that the script runs).
Run: ``.venv/bin/python benchmarks/bench_pose.py [--design FILE] [--repeats N] [--smoke]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from collections.abc import Callable

import numpy as np

import ppm_stiffness as pps
from ppm_stiffness.analysis import analyze_matrix
from ppm_stiffness.dynamics.analysis import first_mode
from ppm_stiffness.model import (
    actuator_stiffness_vector,
    stiffness_at_tool_point,
    validate_pose,
    workspace_centre,
)

BATCH = 20


def median_us(call: Callable[[], object], repeats: int) -> float:
    """Median over ``repeats`` batches of the mean time of one call [us]."""
    call()  # warm caches and lazy imports
    means = []
    for _ in range(repeats):
        t = time.perf_counter()
        for _ in range(BATCH):
            call()
        means.append((time.perf_counter() - t) / BATCH)
    return statistics.median(means) * 1e6


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--design", help="design file (default: the built-in 3-PPR)")
    parser.add_argument("--repeats", type=int, default=50, help="batches of 20 calls")
    parser.add_argument("--smoke", action="store_true", help="one batch of each")
    args = parser.parse_args(argv)
    if args.smoke:
        args.repeats = 1
    design = pps.load_design(args.design) if args.design else pps.default_design()
    pose = workspace_centre(design)
    print(
        f"design {design.name} ({design.architecture}) at pose {np.round(pose, 6).tolist()}; "
        f"numpy {np.__version__}, python {sys.version.split()[0]}; load average "
        + " ".join(f"{x:.2f}" for x in os.getloadavg())
    )
    pose_us = median_us(lambda: pps.analyze(design, pose).to_dict(), args.repeats)
    k = pps.stiffness_at_pose(design, pose)
    k_us = median_us(lambda: pps.stiffness_at_pose(design, pose), args.repeats)
    screws_us = median_us(lambda: pps.eigenscrews(k), args.repeats)
    dec_us = median_us(lambda: pps.decouple(k, "paper"), args.repeats)
    full = validate_pose(design, pose)
    tool = np.asarray(design.tool_point, dtype=float)
    k_act = actuator_stiffness_vector(design, None)
    k_tool = stiffness_at_tool_point(k, full, tool)
    matrix_us = median_us(lambda: analyze_matrix(k_tool).to_dict(), args.repeats)
    modes_us = median_us(lambda: first_mode(design, full, k_tool, k_act, tool), args.repeats)
    print(
        f"analyze (K, eigenscrews, both decouplings, principal compliances, first mode): "
        f"{pose_us:.0f} us; of which K {k_us:.0f} us, the matrix's analysis "
        f"{matrix_us:.0f} us (eigenscrews {screws_us:.0f} us, paper decoupling "
        f"{dec_us:.0f} us), the first mode {modes_us:.0f} us"
    )
    print("load average after: " + " ".join(f"{x:.2f}" for x in os.getloadavg()))
    print(
        f"pose_us={pose_us:.0f} k_us={k_us:.0f} eigenscrews_us={screws_us:.0f} "
        f"decouple_us={dec_us:.0f} matrix_us={matrix_us:.0f} modes_us={modes_us:.0f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
