"""The Dask worker plugin that tunes each worker's allocator (imported only with Dask).

Dask's nanny starts workers with ``MALLOC_TRIM_THRESHOLD_=65536``, which leaves glibc's
mmap threshold at 128 KiB: the batch temporaries of a design's task are then mapped and
unmapped on every use (:mod:`ppm_stiffness._allocator`). :class:`AllocatorPlugin` calls
:func:`~ppm_stiffness._allocator.tune_allocator` once in every worker process, those
that join later included; :func:`ppm_stiffness.optimize.executors.dask_executor`
registers it.
"""

from __future__ import annotations

from typing import Any

from distributed.diagnostics.plugin import WorkerPlugin

from ppm_stiffness._allocator import tune_allocator


class AllocatorPlugin(WorkerPlugin):
    """Runs :func:`~ppm_stiffness._allocator.tune_allocator` (and limits BLAS to one
    thread) in each worker process when it starts or when the plugin is registered."""

    name = "ppm-stiffness-allocator"

    def setup(self, worker: Any) -> None:
        from ppm_stiffness.optimize.executors import limit_threads

        tune_allocator()
        limit_threads()
