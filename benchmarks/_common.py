"""Helpers shared by the benchmark scripts (imported as ``_common``: the scripts run as
``python benchmarks/bench_*.py``, their folder first on ``sys.path``)."""

from __future__ import annotations

import os


def load_text() -> str:
    """The machine's 1, 5 and 15-minute load averages, as the benchmarks print them."""
    try:
        one, five, fifteen = os.getloadavg()
    except OSError:
        return "load average unknown"
    return f"load average {one:.2f}, {five:.2f}, {fifteen:.2f}"
