"""Benchmark of the single-pose analysis through the public API.

``pose_us`` is the median over many calls of ``ppm_stiffness.analyze(design, pose)`` at
the workspace centre: K (inverse kinematics, joint chains, springs), the nonsingularity
check, the eigenscrews, the paper's decoupling and the least-squares one, the spatial
principal compliances and, for a design with a mass model, the first natural frequency,
as ``ppm-stiffness analyze`` prints them by default. For context, the medians of its
parts: ``model.stiffness_at_pose`` (K alone), ``analysis.analyze_matrix`` (eigenscrews,
both decouplings, principal compliances: ``matrix_us``), ``eigenscrews``,
``decouple(K, "paper")`` and ``dynamics.analysis.first_mode`` with the default dynamics
model (``modes_us``: the mass matrix by static condensation of the legs, each leg's
fixed-interface modes, :data:`~ppm_stiffness.dynamics.legmodes.DEFAULT_LINK_MODES`
per leg, and the first mode) and with the condensed one (``modes0_us``: ``link_modes``
0).

Calls are timed in batches of 20 by the process's CPU time (the median of the per-call
batch means), so that the figure is robust to other processes on a shared machine;
``pose_wall_us`` is the same median of ``analyze`` by the wall clock. Run with
``OPENBLAS_NUM_THREADS=1`` on a shared machine (a multi-threaded BLAS pool spends
several times the CPU on these small matrices under load; the variable is printed).

The load average is printed before and after (the machine may be shared). The last
line is ``pose_us=N pose_wall_us=N k_us=N eigenscrews_us=N decouple_us=N matrix_us=N
modes_us=N modes0_us=N``.
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


def median_us(call: Callable[[], object], repeats: int, wall: bool = False) -> float:
    """Median over ``repeats`` batches of the mean CPU time (the wall clock's with
    ``wall``) of one call [us]."""
    clock = time.perf_counter if wall else time.process_time
    call()  # warm caches and lazy imports
    means = []
    for _ in range(repeats):
        t = clock()
        for _ in range(BATCH):
            call()
        means.append((clock() - t) / BATCH)
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
        f"numpy {np.__version__}, python {sys.version.split()[0]}; OPENBLAS_NUM_THREADS="
        f"{os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}; load average "
        + " ".join(f"{x:.2f}" for x in os.getloadavg())
    )
    pose_us = median_us(lambda: pps.analyze(design, pose).to_dict(), args.repeats)
    wall_us = median_us(lambda: pps.analyze(design, pose).to_dict(), args.repeats, wall=True)
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
    modes0_us = median_us(
        lambda: first_mode(design, full, k_tool, k_act, tool, link_modes=0), args.repeats
    )
    print(
        f"analyze (K, eigenscrews, both decouplings, principal compliances, first mode): "
        f"{pose_us:.0f} us CPU ({wall_us:.0f} us wall); of which K {k_us:.0f} us, the "
        f"matrix's analysis {matrix_us:.0f} us (eigenscrews {screws_us:.0f} us, paper "
        f"decoupling {dec_us:.0f} us), the first mode {modes_us:.0f} us (condensed: "
        f"{modes0_us:.0f} us)"
    )
    print("load average after: " + " ".join(f"{x:.2f}" for x in os.getloadavg()))
    print(
        f"pose_us={pose_us:.0f} pose_wall_us={wall_us:.0f} k_us={k_us:.0f} "
        f"eigenscrews_us={screws_us:.0f} decouple_us={dec_us:.0f} matrix_us={matrix_us:.0f} "
        f"modes_us={modes_us:.0f} modes0_us={modes0_us:.0f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
