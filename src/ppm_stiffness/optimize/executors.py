"""Where the designs are evaluated: in this process, in local processes, or on a Dask
cluster, through any ``concurrent.futures``-style executor.

The library's sweeps and optimiser take an ``executor`` with ``submit(fn, *args)``
returning a future with ``result()`` and ``cancel()``: :class:`SerialExecutor` (the
default), :func:`process_executor` (``--workers N``), a Dask ``client.get_executor()``
(:func:`dask_executor`, ``--scheduler tcp://HOST:PORT``), an MPI pool, ... A task is one
design or a few (:func:`run_ordered`), each reduced inside the task to its summary
figures: the design and a few parameter values travel, never the maps.

Each task first calls :func:`limit_threads`: BLAS pools (through ``threadpoolctl`` when
it is installed) and numba use one thread per worker, so that N workers use N cores,
not N times the BLAS pool. Each worker process raises glibc's malloc thresholds once
(:func:`ppm_stiffness._allocator.tune_allocator`: local workers in :func:`init_worker`,
Dask workers through a worker plugin), so that a task runs as fast in a worker as in
this process. A task should take about 0.1 to 1 s, well above an executor's own cost
per task (1 to 3 ms): :func:`designs_per_task` chooses how many designs one task
evaluates. Results come back in submission order whatever the order in
which workers finish (:func:`run_ordered`), so the same inputs give the same results
with every executor.

This module imports neither numpy nor dask at its top: a spawned worker imports it
(for :func:`init_worker`) before anything loads a BLAS library, so the thread
variables it sets take effect.
"""

from __future__ import annotations

import os
import signal
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import Executor, Future
from contextlib import contextmanager
from typing import Any, TypeVar

from ppm_stiffness.core.errors import InputDataError

T = TypeVar("T")

#: Environment variables that size the BLAS / OpenMP thread pools.
THREAD_VARIABLES = (
    "OMP_NUM_THREADS",
    "OPENBLAS_NUM_THREADS",
    "MKL_NUM_THREADS",
    "BLIS_NUM_THREADS",
    "VECLIB_MAXIMUM_THREADS",
    "NUMEXPR_NUM_THREADS",
    "NUMBA_NUM_THREADS",
)
#: Seconds to wait for a Dask scheduler before giving up (well under the 30 s promised).
SCHEDULER_TIMEOUT = 10.0

_limited = False


def limit_threads() -> None:
    """One BLAS / numba thread in this process from now on (idempotent, cheap)."""
    global _limited
    if _limited:
        return
    _limited = True
    for name in THREAD_VARIABLES:
        os.environ.setdefault(name, "1")
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # the variables above then act in freshly started workers
        pass
    else:
        threadpool_limits(1)
    try:
        import numba
    except ImportError:
        return
    numba.set_num_threads(1)


def init_worker() -> None:
    """Initializer of local worker processes: one thread each (:func:`limit_threads`),
    glibc's malloc thresholds raised (:func:`ppm_stiffness._allocator.tune_allocator`),
    and Ctrl-C left to the parent (which cancels the work and keeps what is done)."""
    from ppm_stiffness._allocator import tune_allocator

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for name in THREAD_VARIABLES:
        os.environ[name] = "1"
    tune_allocator()
    limit_threads()


class SerialExecutor(Executor):
    """Runs each task at ``submit`` in this process; returns a finished future."""

    def submit(self, fn: Callable[..., T], /, *args: Any, **kwargs: Any) -> Future[T]:
        future: Future[T] = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as exc:
            if isinstance(exc, KeyboardInterrupt):
                raise
            future.set_exception(exc)
        return future


def process_executor(workers: int) -> Executor:
    """A pool of ``workers`` local processes (started with "spawn": no state shared with
    this process, safe with threads), each running :func:`init_worker` first.

    Raises
    ------
    InputDataError
        If ``workers`` is below 1.
    """
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    if workers < 1:
        raise InputDataError(f"--workers must be at least 1, got {workers}")
    return ProcessPoolExecutor(
        max_workers=workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=init_worker,
    )


@contextmanager
def dask_executor(address: str, timeout: float = SCHEDULER_TIMEOUT) -> Iterator[Executor]:
    """An executor on the Dask distributed cluster at ``address`` (``tcp://HOST:PORT``).

    Dask's nanny starts its workers with one BLAS thread already; the tasks call
    :func:`limit_threads` too. A worker plugin
    (:class:`ppm_stiffness.optimize._dask_plugin.AllocatorPlugin`) raises glibc's
    malloc thresholds in every worker, present and future (Dask's nanny sets
    ``MALLOC_TRIM_THRESHOLD_``, which makes large numpy temporaries page-fault on every
    use: :mod:`ppm_stiffness._allocator`).

    Raises
    ------
    InputDataError
        If ``distributed`` is not installed (the ``dask`` extra), the address is not a
        scheduler address, or no scheduler answers within ``timeout`` seconds.
    """
    if "://" not in address or not address.split("://", 1)[1]:
        raise InputDataError(f"--scheduler must look like tcp://HOST:PORT, got {address!r}")
    try:
        from distributed import Client
    except ImportError:
        raise InputDataError(
            "--scheduler needs Dask distributed: pip install 'ppm-stiffness[dask]'"
        ) from None
    _refused_at_once(address)
    client = _connect(Client, address, timeout)
    try:
        from ppm_stiffness.optimize._dask_plugin import AllocatorPlugin

        client.register_plugin(AllocatorPlugin())
        yield client.get_executor()
    finally:
        client.close()


def _refused_at_once(address: str) -> None:
    """Fail at once (not after the whole timeout) when the address refuses connections."""
    import socket
    from urllib.parse import urlsplit

    try:
        parts = urlsplit(address)
        host, port = parts.hostname, parts.port
    except ValueError:
        raise InputDataError(f"--scheduler {address}: not a HOST:PORT address") from None
    if host is None or port is None:
        raise InputDataError(f"--scheduler must look like tcp://HOST:PORT, got {address!r}")
    try:
        with socket.create_connection((host, port), timeout=SCHEDULER_TIMEOUT):
            pass
    except ConnectionRefusedError:
        raise InputDataError(
            f"--scheduler {address}: connection refused (no Dask scheduler there)"
        ) from None
    except OSError:
        return  # unknown host, unreachable network, slow: the client's own timeout decides


def _connect(client_type: Any, address: str, timeout: float) -> Any:
    """``client_type(address)`` within ``timeout`` seconds (plus 5 s of grace), or an
    InputDataError. The connection runs in a daemon thread, so that nothing a
    half-answering address does (a proxy that accepts every connection, a failed
    client's slow clean-up) can hang the command."""
    import threading

    outcome: dict[str, Any] = {}
    abandoned = threading.Event()

    def connect() -> None:
        try:
            client = client_type(address, timeout=f"{timeout}s", set_as_default=False)
        except BaseException as exc:  # any failure means: no scheduler there
            outcome["error"] = exc
            return
        if abandoned.is_set():
            client.close()
        else:
            outcome["client"] = client

    thread = threading.Thread(target=connect, name="dask-connect", daemon=True)
    thread.start()
    thread.join(timeout + 5.0)
    if "client" in outcome:
        return outcome["client"]
    abandoned.set()
    error = outcome.get("error")
    reason = (str(error).splitlines() or [""])[0] if error is not None else "no answer"
    raise InputDataError(
        f"--scheduler {address}: no Dask scheduler reachable within {timeout:g} s "
        f"({(reason or type(error).__name__)[:100]})"
    )


class Interrupted(Exception):
    """Ctrl-C during :func:`run_ordered`; ``done`` maps task index -> result of the
    tasks that had finished."""

    def __init__(self, done: dict[int, Any]) -> None:
        super().__init__("interrupted")
        self.done = done


#: Seconds of work one task aims at when :func:`run_ordered` groups items into tasks:
#: well above an executor's own cost per task (1 to 3 ms for a process pool or Dask)
#: and well below a run's length (documented rule: a task takes 0.1 to 1 s).
TASK_SECONDS = 0.25
#: :func:`run_ordered` makes at least this many tasks (when there are that many items),
#: so that the workers finish together.
MIN_TASKS = 16


def items_per_task(items: int, seconds_per_item: float) -> int:
    """How many items one task evaluates: about :data:`TASK_SECONDS` of work, but at
    least :data:`MIN_TASKS` tasks (fewer only when there are fewer items).

    Parameters
    ----------
    items : int
        Items to evaluate.
    seconds_per_item : float
        Measured time of one item [s] (non-positive or non-finite: one item per task).
    """
    import math

    if items <= 1 or not math.isfinite(seconds_per_item) or seconds_per_item <= 0:
        return 1
    by_time = max(1, int(TASK_SECONDS / seconds_per_item))
    by_balance = max(1, math.ceil(items / MIN_TASKS))
    return min(by_time, by_balance)


def _run_items(fn: Callable[..., T], argument_tuples: list[tuple[Any, ...]]) -> list[T]:
    """One task: ``fn`` over several argument tuples, in order."""
    return [fn(*args) for args in argument_tuples]


def run_ordered(
    executor: Executor,
    fn: Callable[..., T],
    argument_tuples: Sequence[tuple[Any, ...]] | Iterable[tuple[Any, ...]],
    advance: Callable[[float], None] | None = None,
) -> list[T]:
    """``[fn(*args) for args in argument_tuples]`` on ``executor``, in order.

    On an executor other than :class:`SerialExecutor`, the first item is evaluated in
    this process and timed, and the others are grouped into tasks of
    :func:`items_per_task` items (about :data:`TASK_SECONDS` each), so that the
    executor's cost per task is paid once per group, not once per design; each item's
    result is the same as when evaluated alone. ``advance(k)`` is called as each task
    of ``k`` items finishes (in any order).

    Raises
    ------
    Interrupted
        On Ctrl-C: the unstarted tasks are cancelled and the finished results kept.
    """
    import time
    from concurrent.futures import FIRST_COMPLETED, wait

    items = list(argument_tuples)
    futures: list[Future[list[T]]] = []
    starts: list[int] = []
    done: dict[int, T] = {}
    try:
        first = 0
        if not isinstance(executor, SerialExecutor) and len(items) > 1:
            start = time.perf_counter()
            done[0] = fn(*items[0])
            elapsed = time.perf_counter() - start
            if advance is not None:
                advance(1)
            first = 1
            per_task = items_per_task(len(items) - 1, elapsed)
        else:
            per_task = 1
        for i in range(first, len(items), per_task):
            starts.append(i)
            futures.append(executor.submit(_run_items, fn, items[i : i + per_task]))
        index = {id(f): i for i, f in enumerate(futures)}
        pending = set(futures)
        while pending:
            finished, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in finished:
                results = future.result()
                for j, result in enumerate(results):
                    done[starts[index[id(future)]] + j] = result
                if advance is not None:
                    advance(len(results))
    except KeyboardInterrupt:
        for future in futures:
            future.cancel()
        for k, future in enumerate(futures):
            if future.done() and not future.cancelled() and future.exception() is None:
                for j, result in enumerate(future.result()):
                    done[starts[k] + j] = result
        raise Interrupted(done) from None
    return [done[i] for i in range(len(items))]


@contextmanager
def open_executor(workers: int | None = None, scheduler: str | None = None) -> Iterator[Executor]:
    """The executor the command-line options ask for: ``scheduler`` (Dask), else
    ``workers`` local processes (when above 1), else :class:`SerialExecutor`.

    On leaving, a process pool is shut down without waiting for cancelled work.
    """
    if scheduler is not None:
        with dask_executor(scheduler) as executor:
            yield executor
        return
    if workers is not None and workers < 1:
        raise InputDataError(f"--workers must be at least 1, got {workers}")
    if workers is None or workers == 1:
        yield SerialExecutor()
        return
    pool = process_executor(workers)
    try:
        yield pool
    except BaseException:
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    else:
        pool.shutdown(wait=True)
