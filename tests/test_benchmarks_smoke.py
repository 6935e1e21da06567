"""Every script of benchmarks/ runs (issue 32, item 7): each is found by glob and run
with ``--smoke`` (its tiniest sizes, one repeat, no baseline, no Dask cluster) in a
fresh interpreter; it must exit 0 and print at least one line of ``key=value`` fields,
the lines the benchmarks are read by. No figure is asserted: this only guards against
a benchmark broken by a change of the library (an import moved, a signature changed).
Measured: 22 s of CPU time for the eight scripts at a load of 7 on 2 cores (each
script's CPU time is printed with ``pytest -s``)."""

from __future__ import annotations

import re
import resource
import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARKS = sorted((Path(__file__).parents[1] / "benchmarks").glob("bench_*.py"))  # not _common.py
#: A line of the machine-readable figures: one or more space-separated key=value fields.
KEY_VALUES = re.compile(r"^[A-Za-z_][\w.]*=\S+( [A-Za-z_][\w.]*=\S+)*$")
#: Optional extras a benchmark needs (it is skipped without them).
EXTRAS = {"bench_validation": "Pynite"}


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def test_the_benchmarks_are_found() -> None:
    assert len(BENCHMARKS) >= 8, BENCHMARKS


@pytest.mark.parametrize("script", BENCHMARKS, ids=lambda p: p.stem)
def test_benchmark_runs_in_smoke_mode(script: Path) -> None:
    if script.stem in EXTRAS:
        pytest.importorskip(EXTRAS[script.stem])
    cpu = _children_cpu()
    run = subprocess.run(
        [sys.executable, str(script), "--smoke"],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=script.parents[1],
    )
    print(f"{script.stem} --smoke: {_children_cpu() - cpu:.2f} s of CPU time")
    assert run.returncode == 0, run.stderr[-2000:] or run.stdout[-2000:]
    lines = [line for line in run.stdout.splitlines() if KEY_VALUES.match(line.strip())]
    assert lines, run.stdout[-2000:]
