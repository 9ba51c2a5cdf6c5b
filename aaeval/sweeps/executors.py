"""Where a sweep's tasks run: this process, local worker processes, or a Dask cluster.

Each executor has one method, ``run(fn, payloads)``, yielding ``(index, result, error)``
as tasks finish, in any order; ``error`` is set only when the task could not finish
(:mod:`aaeval.sweeps.task_failures`: how a task can fail, and its time limit). The
executors themselves: :mod:`aaeval.sweeps.local_workers` (this process, or local worker
processes) and :mod:`aaeval.sweeps.dask_executor` (a Dask cluster).
"""

from __future__ import annotations

import os
from typing import Any

from aaeval.sweeps.dask_executor import DaskExecutor
from aaeval.sweeps.local_workers import ProcessExecutor, SerialExecutor

__all__ = ["make_executor"]


def make_executor(workers: int | None = None, scheduler: Any = None, max_seconds: float | None = None):
    """``scheduler`` (an address or a Client) wins; else ``workers`` local processes
    (default: every core), run in this process when that is one. ``max_seconds``: the
    limit of one task (:func:`~aaeval.sweeps.task_failures.task_limit`)."""
    if scheduler is not None:
        return DaskExecutor(scheduler, max_seconds=max_seconds)
    n = workers or os.cpu_count() or 1
    return SerialExecutor(max_seconds) if n == 1 else ProcessExecutor(n, max_seconds)
