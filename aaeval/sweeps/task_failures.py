"""How a sweep's task can end other than by its method's answer, and how long it may run.

A task (a reference or a cell, all its repeats) that could not finish comes back from an
executor with one of these errors: :class:`WorkerDied` (the process running it died: a
segfault, ``os._exit``, the OOM killer) or :class:`TaskTimedOut` (it ran past the time limit
and its worker was stopped) is the task's own doing, and the sweep records the cell as failed
with that reason (a rerun tries it again); :class:`SchedulerLost` (the Dask cluster went away)
and :class:`WorkersCannotStart` (local workers that cannot start) are no task's doing and leave
their cells unrecorded.

Every task has a time limit (:func:`task_limit`): ``max_seconds`` (an experiment's
``max_seconds``), else the environment's ``AAEVAL_MAX_SECONDS``, else :data:`MAX_SECONDS`.
"""

from __future__ import annotations

import signal
from typing import Any

from aaeval.limits import env_seconds

__all__ = ["Outcome", "MAX_SECONDS", "WorkerDied", "TaskTimedOut", "WorkersCannotStart", "SchedulerLost",
           "WorkersLost", "NO_MAIN_GUARD", "task_limit", "worker_died", "timed_out"]

#: What an executor yields as each task finishes: ``(index, result, error)``.
Outcome = tuple[int, Any, BaseException | None]

#: Seconds one task (a reference or a cell, all its repeats) may run before it is stopped.
MAX_SECONDS = 600.0


class WorkerDied(RuntimeError):
    """The process running a task died before it answered (a signal or an exit)."""


class TaskTimedOut(RuntimeError):
    """A task ran past its time limit; its worker was stopped."""


class WorkersCannotStart(RuntimeError):
    """A local worker process ended before it was ready for its first task: no task's doing
    (each replacement would end the same way), so every task not yet answered comes back
    with it, unrecorded, and the sweep says why."""


class SchedulerLost(ConnectionError):
    """The Dask scheduler went away during the sweep: the cells it had not returned are lost
    (not recorded) and run on the next sweep."""


class WorkersLost(SchedulerLost):
    """Every worker of the Dask cluster died and none joined in time: lost like
    :class:`SchedulerLost` (its tasks would wait forever)."""


NO_MAIN_GUARD = ("a script that runs a sweep on local worker processes must start it under "
                 "'if __name__ == \"__main__\":' (each worker imports the script: without the guard it starts the "
                 "sweep again); or run it with workers=1")


def task_limit(configured: float | None = None) -> float:
    """The time limit of one task: ``configured`` (the experiment's ``max_seconds``), else
    ``AAEVAL_MAX_SECONDS``, else :data:`MAX_SECONDS`."""
    if configured is not None:
        return float(configured)
    return env_seconds("AAEVAL_MAX_SECONDS", MAX_SECONDS)


def worker_died(exitcode: int | None) -> WorkerDied:
    if exitcode is not None and exitcode < 0:
        try:
            name = f" ({signal.Signals(-exitcode).name})"
        except ValueError:
            name = ""
        return WorkerDied(f"worker died: signal {-exitcode}{name}")
    return WorkerDied(f"worker died: exit {exitcode}")


def timed_out(limit: float) -> TaskTimedOut:
    return TaskTimedOut(f"timed out: stopped after {limit:g} s (the limit: max_seconds in the config or "
                        "AAEVAL_MAX_SECONDS)")
