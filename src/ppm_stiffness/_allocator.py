"""glibc's malloc thresholds for a process that computes with large numpy temporaries.

glibc serves an allocation of at least ``M_MMAP_THRESHOLD`` bytes by a fresh ``mmap``
and returns it to the system on ``free``; below it, from the heap, which it trims back
to the system when more than ``M_TRIM_THRESHOLD`` bytes are free at its top. By default
the mmap threshold starts at 128 KiB and *grows* to the size of the largest block freed
(up to 32 MiB), so a process that reuses temporaries of a few MiB soon keeps them on the
heap. **Setting either threshold (by ``mallopt`` or by the ``MALLOC_TRIM_THRESHOLD_`` /
``MALLOC_MMAP_THRESHOLD_`` environment variables) turns that growth off.** Dask's nanny
starts every worker with ``MALLOC_TRIM_THRESHOLD_=65536`` (to hand freed memory back to
the system, so that the worker's "unmanaged memory" stays low): the mmap threshold then
stays at 128 KiB, every batch temporary of 128 KiB or more (about 455 poses of 6x6
matrices) is mapped, unmapped and faulted in again page by page on each use, and a task
runs several times slower than in a plain process (docs/optimization.md).

:func:`tune_allocator` sets ``M_MMAP_THRESHOLD`` to 32 MiB (glibc's largest) and
``M_TRIM_THRESHOLD`` to 64 MiB, once per process. The library never calls it on import:
the command line calls it before running a command,
:func:`ppm_stiffness.maps.workspace.stiffness_map` before a map of at least
:data:`LARGE_MAP_POSES` poses (a map called from the library; a smaller map leaves the
allocator alone), and the local worker processes
(:func:`ppm_stiffness.optimize.executors.init_worker`) and Dask workers
(:class:`ppm_stiffness.optimize._dask_plugin.AllocatorPlugin`) when they start. It does
nothing where the C library is not glibc, or when the environment variable
:data:`OPT_OUT` is set to anything but ``""`` or ``"0"``. The cost: a process keeps up to
64 MiB of freed heap instead of returning it at once.
"""

from __future__ import annotations

import os
import sys
import warnings

#: ``mallopt`` parameter numbers (glibc's malloc.h).
M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3
#: Bytes: blocks below this come from the heap (glibc's largest value on 64-bit).
MMAP_THRESHOLD = 32 * 2**20
#: Bytes of free heap top kept before trimming (at least :data:`MMAP_THRESHOLD`).
TRIM_THRESHOLD = 64 * 2**20
#: Grid poses from which a map called from the library tunes the allocator (a map of
#: that size takes about a second or more; a 10^6-pose hexapod map runs about 20 %
#: faster tuned).
LARGE_MAP_POSES = 100_000
#: Set to anything but "" or "0" to leave the allocator as it is.
OPT_OUT = "PPM_STIFFNESS_NO_MALLOPT"

_state: bool | None = None


def tune_allocator() -> bool:
    """Raise glibc's mmap and trim thresholds in this process (once; later calls
    return the first outcome).

    Returns
    -------
    bool
        True when both thresholds were set; False when opted out (:data:`OPT_OUT`),
        not on glibc, or when ``mallopt`` refused (then with a ``RuntimeWarning``).
    """
    global _state
    if _state is None:
        _state = _tune()
    return _state


def _tune() -> bool:
    if os.environ.get(OPT_OUT, "") not in ("", "0"):
        return False
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        libc = ctypes.CDLL(None)  # the C library this process already runs on
    except OSError:
        return False
    # glibc and no other C library exports gnu_get_libc_version (musl's mallopt is a stub)
    if not hasattr(libc, "gnu_get_libc_version") or not hasattr(libc, "mallopt"):
        return False
    mallopt = libc.mallopt
    mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
    mallopt.restype = ctypes.c_int
    for param, value, name in (
        (M_MMAP_THRESHOLD, MMAP_THRESHOLD, "M_MMAP_THRESHOLD"),
        (M_TRIM_THRESHOLD, TRIM_THRESHOLD, "M_TRIM_THRESHOLD"),
    ):
        if mallopt(param, value) != 1:
            warnings.warn(
                f"mallopt({name}, {value}) was refused; large temporaries may be slow "
                f"(set {OPT_OUT}=1 to skip this)",
                RuntimeWarning,
                stacklevel=3,
            )
            return False
    return True
