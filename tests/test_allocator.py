"""glibc's malloc thresholds (:mod:`ppm_stiffness._allocator`): a tuned process reuses
its large numpy temporaries instead of page-faulting them in on every use, also under
Dask's ``MALLOC_TRIM_THRESHOLD_=65536``; the opt-out variable and ``import
ppm_stiffness`` leave the allocator alone; local worker processes are tuned."""

from __future__ import annotations

import ctypes
import json
import os
import subprocess
import sys

import pytest

from ppm_stiffness._allocator import OPT_OUT
from ppm_stiffness.optimize.executors import process_executor

GLIBC = sys.platform.startswith("linux") and hasattr(ctypes.CDLL(None), "gnu_get_libc_version")
needs_glibc = pytest.mark.skipif(not GLIBC, reason="the thresholds are glibc's")

# 200 rounds of two 2.9 MB temporaries (10,000 poses of 6x6 matrices); prints the
# tuning outcome and the minor page faults of the loop
_CHILD = """
import json, resource, sys
import numpy as np
tuned = None
if sys.argv[1] == "tune":
    from ppm_stiffness._allocator import tune_allocator
    tuned = tune_allocator()
elif sys.argv[1] == "import":
    import ppm_stiffness, ppm_stiffness.cli
    tuned = "ppm_stiffness._allocator" in sys.modules
a = np.ones((10000, 6, 6))
f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(200):
    b = a * 2.0
    c = b + a
    del b, c
print(json.dumps([tuned, resource.getrusage(resource.RUSAGE_SELF).ru_minflt - f0]))
"""

#: Dask's nanny sets this in every worker (distributed.yaml, nanny.pre-spawn-environ).
DASK_ENV = {"MALLOC_TRIM_THRESHOLD_": "65536"}


def _faults(mode: str, **env: str) -> tuple[object, int]:
    environ = {k: v for k, v in os.environ.items() if k != OPT_OUT} | DASK_ENV | env
    out = subprocess.run(
        [sys.executable, "-c", _CHILD, mode],
        env=environ,
        capture_output=True,
        text=True,
        check=True,
    )
    tuned, faults = json.loads(out.stdout)
    return tuned, int(faults)


@needs_glibc
def test_tuned_process_reuses_large_temporaries() -> None:
    # measured: about 280,000 minor faults untuned (each 2.9 MB temporary mapped and
    # faulted in page by page), about 1,400 tuned
    _, untuned = _faults("none")
    tuned, faults = _faults("tune")
    assert tuned is True
    assert untuned > 100_000
    assert faults < untuned / 20


@needs_glibc
def test_opt_out_leaves_the_allocator_alone() -> None:
    tuned, faults = _faults("tune", **{OPT_OUT: "1"})
    assert tuned is False
    assert faults > 100_000


@needs_glibc
def test_importing_the_library_does_not_tune() -> None:
    imported, faults = _faults("import")
    assert imported is False  # the module is not even imported
    assert faults > 100_000


def _worker_state() -> tuple[object, str | None]:
    """The allocator's recorded outcome in this process, read without tuning it (None
    when nothing has called tune_allocator), and the trim variable of its environment."""
    import sys as worker_sys

    module = worker_sys.modules.get("ppm_stiffness._allocator")
    return getattr(module, "_state", None), os.environ.get("MALLOC_TRIM_THRESHOLD_")


@needs_glibc
def test_local_workers_are_tuned() -> None:
    # the pool's initializer ran tune_allocator before any task: the worker's recorded
    # outcome is read, not produced by the task (without the initializer it is None)
    with process_executor(1) as pool:
        state, _ = pool.submit(_worker_state).result()
    assert state is True


@needs_glibc
def test_dask_workers_are_tuned_by_the_plugin() -> None:
    distributed = pytest.importorskip("distributed")
    from ppm_stiffness.optimize.executors import open_executor

    # a nanny-started worker process: Dask sets MALLOC_TRIM_THRESHOLD_ in it
    with distributed.LocalCluster(
        n_workers=1,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        with open_executor(scheduler=cluster.scheduler_address) as executor:
            client = executor._client  # type: ignore[attr-defined]
            states = list(client.run(_worker_state).values())
    assert states == [(True, "65536")]


# a library process (no command line): counts the allocator's tunings and reads its state
# after a small map, then after two large ones of the built-in design
_MAP_CHILD = """
import json
import ppm_stiffness._allocator as allocator
from ppm_stiffness.design import default_design
from ppm_stiffness.maps.workspace import stiffness_map
calls = []
tune = allocator._tune
allocator._tune = lambda: calls.append(1) or tune()
design = default_design()
stiffness_map(design, grid=20)
small = [len(calls), allocator._state]
side = int(allocator.LARGE_MAP_POSES**0.5) + 1
for _ in range(2):
    stiffness_map(design, grid=side)
print(json.dumps([small, [len(calls), allocator._state]]))
"""


@needs_glibc
def test_a_large_map_from_the_library_tunes_once() -> None:
    environ = {k: v for k, v in os.environ.items() if k != OPT_OUT}
    out = subprocess.run(
        [sys.executable, "-c", _MAP_CHILD], env=environ, capture_output=True, text=True, check=True
    )
    small, large = json.loads(out.stdout)
    assert small == [0, None]  # a 20 x 20 map leaves the allocator alone
    assert large == [1, True]  # two maps of > LARGE_MAP_POSES poses: tuned once
