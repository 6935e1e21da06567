"""Several items per task (:func:`ppm_stiffness.optimize.executors.run_ordered`): on an
executor other than the serial one, items are grouped into tasks of about
TASK_SECONDS, at least MIN_TASKS of them, and the results are those of the items
evaluated one by one, in order."""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from concurrent.futures import Executor, Future
from typing import Any

import pytest

from ppm_stiffness.optimize.executors import (
    MIN_TASKS,
    TASK_SECONDS,
    SerialExecutor,
    items_per_task,
    run_ordered,
)


class CountingExecutor(Executor):
    """Runs tasks at once, counting them; not the serial executor (a stand-in for a
    process pool or Dask)."""

    def __init__(self) -> None:
        self.tasks = 0

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future[Any]:
        self.tasks += 1
        return SerialExecutor().submit(fn, *args, **kwargs)


def _square(x: int) -> int:
    return x * x


def test_items_per_task_rule() -> None:
    assert items_per_task(255, 0.01) == math.ceil(255 / MIN_TASKS)  # balance bound: 16
    assert items_per_task(10_000, 0.01) == int(TASK_SECONDS / 0.01)  # time bound: 25
    assert items_per_task(255, 0.5) == 1  # a design already longer than a task
    assert items_per_task(10, 0.001) == 1  # fewer items than MIN_TASKS
    assert items_per_task(100, float("nan")) == 1


def test_grouped_tasks_give_the_serial_results_in_order(monkeypatch: pytest.MonkeyPatch) -> None:
    """Item 0 is timed here on a clock that advances 2 ms per reading (a real clock made
    the task count depend on the machine's load: 17 tasks instead of 16 at load 8)."""
    ticks = iter(0.002 * k for k in range(1_000))
    monkeypatch.setattr(time, "perf_counter", lambda: next(ticks))
    pool = CountingExecutor()
    items = [(i,) for i in range(200)]
    advanced: list[float] = []
    out = run_ordered(pool, _square, items, advanced.append)
    assert out == [i * i for i in range(200)]
    assert sum(advanced) == 200
    # item 0 took 2 ms: the balance bound, the other 199 in tasks of ceil(199 / 16)
    assert items_per_task(199, 0.002) == math.ceil(199 / MIN_TASKS)
    assert pool.tasks == math.ceil(199 / math.ceil(199 / MIN_TASKS))


def test_serial_executor_runs_one_item_per_call() -> None:
    calls: list[int] = []

    def record(x: int) -> int:
        calls.append(x)
        return x

    assert run_ordered(SerialExecutor(), record, [(i,) for i in range(40)]) == list(range(40))
    assert calls == list(range(40))
