"""Where a sweep's tasks run: this process, local worker processes, or a Dask cluster.

Each executor has one method, ``run(fn, payloads)``, yielding ``(index, result, error)``
as tasks finish, in any order. ``error`` is set only when the task could not run at all
(a worker died, the cluster went away); the sweep does not record those cells, so a
rerun tries them again.

An interrupt (Ctrl-C, or SIGTERM/SIGHUP, which the command line turns into one) ends the
workers before it goes on: none outlives the sweep. Local workers also watch their parent
and exit when it is gone, so even a ``kill -9`` of the sweep leaves no orphan computing.
"""

from __future__ import annotations

import multiprocessing
import os
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from typing import Any, Callable, Iterator, Sequence

__all__ = ["SerialExecutor", "ProcessExecutor", "DaskExecutor", "SchedulerLost", "connect", "make_executor",
           "close_quietly"]

Outcome = tuple[int, Any, BaseException | None]


class SerialExecutor:
    """Runs every task in this process, one after the other (``--workers 1``)."""

    workers = 1
    description = "this process"

    def run(self, fn: Callable, payloads: Sequence) -> Iterator[Outcome]:
        for i, payload in enumerate(payloads):
            yield i, fn(*payload), None

    def close(self) -> None:
        pass


def _exit_with_parent(parent: int) -> None:
    """Worker initializer: exit as soon as the sweep process that started us is gone."""

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)  # no cleanup to wait for: results go back to the parent, which is gone

    threading.Thread(target=watch, name="aaeval-parent-watch", daemon=True).start()


class ProcessExecutor:
    """Local worker processes; each warms its JIT once, on its first task of a method."""

    def __init__(self, workers: int):
        self.workers = workers
        self.description = f"{workers} local worker processes"
        # spawn: Dr.Jit's threads do not survive fork
        self._pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"),
                                         initializer=_exit_with_parent, initargs=(os.getpid(),))

    def run(self, fn: Callable, payloads: Sequence) -> Iterator[Outcome]:
        # keep about two tasks per worker queued, so a kill loses little and memory stays flat
        pending: dict = {}
        todo = iter(enumerate(payloads))
        exhausted = False
        try:
            while pending or not exhausted:
                while not exhausted and len(pending) < 2 * self.workers:
                    try:
                        i, payload = next(todo)
                    except StopIteration:
                        exhausted = True
                        break
                    pending[self._pool.submit(fn, *payload)] = i
                if not pending:
                    break
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    i = pending.pop(future)
                    exc = future.exception()
                    yield i, (None if exc else future.result()), exc
        except (KeyboardInterrupt, SystemExit):
            self.terminate()  # do not wait for cells in flight: the user asked to stop
            raise

    def terminate(self) -> None:
        """End the workers now; their cells in flight are lost (and rerun next time)."""
        processes = list((getattr(self._pool, "_processes", None) or {}).values())
        for p in processes:
            p.terminate()
        for p in processes:
            p.join(5)
            if p.is_alive():
                p.kill()
        self._pool.shutdown(wait=True, cancel_futures=True)

    def close(self) -> None:
        self._pool.shutdown(wait=True, cancel_futures=True)


# Seconds to wait for the scheduler to answer, and for a scheduler with no workers to get
# one, before the sweep is refused (AAEVAL_DASK_TIMEOUT, AAEVAL_DASK_WORKER_TIMEOUT).
CONNECT_TIMEOUT = 20.0
WORKER_TIMEOUT = 60.0


class SchedulerLost(ConnectionError):
    """The Dask scheduler went away during the sweep: the cells it had not returned are lost
    (not recorded) and run on the next sweep."""


def _seconds(name: str, default: float) -> float:
    text = os.environ.get(name)
    if not text:
        return default
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value > 0:
        raise ValueError(f"{name}={text!r}: expected a positive number of seconds")
    return value


def connect(address: Any):
    """A ``distributed.Client`` of the scheduler at ``address`` (or ``address`` itself if it
    is a Client) that has at least one worker.

    An unreachable scheduler is a ``ConnectionError`` after ``AAEVAL_DASK_TIMEOUT`` seconds
    (default 20); one with no worker, after ``AAEVAL_DASK_WORKER_TIMEOUT`` seconds (default
    60) of waiting for one to join. Called before a sweep touches its folder.
    """
    from distributed import Client

    if isinstance(address, Client):
        client = address
    else:
        timeout = _seconds("AAEVAL_DASK_TIMEOUT", CONNECT_TIMEOUT)
        try:
            client = Client(address, timeout=f"{timeout}s")
        except (OSError, TimeoutError) as exc:
            raise ConnectionError(f"cannot reach the Dask scheduler at {address} within {timeout:g} s: {exc}") from None
    if not client.scheduler_info().get("workers"):
        wait = _seconds("AAEVAL_DASK_WORKER_TIMEOUT", WORKER_TIMEOUT)
        try:
            client.wait_for_workers(1, timeout=wait)
        except (TimeoutError, OSError) as exc:
            where = getattr(client.scheduler, "address", address)
            if client is not address:
                client.close()
            raise ConnectionError(f"the Dask scheduler at {where} has no workers: none joined within {wait:g} s "
                                  f"(start one with 'dask worker {where}'; AAEVAL_DASK_WORKER_TIMEOUT sets the "
                                  f"wait; {type(exc).__name__})") from None
    return client


class DaskExecutor:
    """The same tasks on a Dask distributed cluster: ``Client(address)``, ``client.map``,
    ``as_completed``.

    ``description`` and ``workers`` follow the cluster: a worker that dies during the sweep
    is seen in the records written after it (:meth:`current`). A scheduler that goes away
    ends the run: every task not yet returned comes back as :class:`SchedulerLost`.
    """

    def __init__(self, address: Any):
        from distributed import Client

        self._own = not isinstance(address, Client)
        self.client = connect(address)
        self.address = self.client.scheduler.address
        self.started_with = self._live_workers()
        self.workers = max(1, self.started_with)
        self.description = f"Dask cluster {self.address} ({self.workers} workers)"
        self.lost: SchedulerLost | None = None

    def _live_workers(self) -> int:
        try:
            return len(self.client.scheduler_info().get("workers", {}))
        except Exception:  # noqa: BLE001 - no answer: none known
            return 0

    def current(self) -> dict:
        """The executor as a record's ``executor`` and ``workers`` fields, now."""
        n = self._live_workers()
        if n == self.started_with or n == 0:
            return {"executor": self.description, "workers": self.workers}
        change = f"{self.started_with - n} lost" if n < self.started_with else f"{n - self.started_with} joined"
        return {"executor": f"Dask cluster {self.address} ({n} workers; {change} since the start)", "workers": n}

    def run(self, fn: Callable, payloads: Sequence) -> Iterator[Outcome]:
        from distributed import as_completed

        if not payloads:
            return
        if self.lost is not None:  # the scheduler is gone: nothing more can run
            for i in range(len(payloads)):
                yield i, None, self.lost
            return
        returned: set[int] = set()
        futures = []
        try:
            # tasks render and time: never let Dask skip one as a duplicate of a pure call
            futures = [self.client.submit(fn, *p, pure=False) for p in payloads]
            index = {f.key: i for i, f in enumerate(futures)}
            for future in as_completed(futures):
                i = index[future.key]
                if future.status == "cancelled":
                    raise SchedulerLost("its task was cancelled")
                if future.status == "error":
                    outcome = (i, None, future.exception())
                else:
                    outcome = (i, future.result(), None)
                returned.add(i)
                yield outcome
                future.release()
        except (KeyboardInterrupt, SystemExit):
            with _quietly():
                self.client.cancel(futures)  # the cluster stops computing cells nobody will write
            raise
        except GeneratorExit:  # the caller stopped reading
            raise
        except BaseException as exc:  # noqa: BLE001 - a lost connection comes in many classes
            if self.client.status == "running" and not isinstance(exc, SchedulerLost) and self._live_workers():
                raise  # the cluster is fine: not ours to hide
            self.lost = SchedulerLost(f"the Dask scheduler at {self.address} was lost during the sweep "
                                      f"({type(exc).__name__}: {str(exc) or 'connection closed'}); finished cells "
                                      "are kept, rerun the sweep when it is back")
            for i in range(len(payloads)):
                if i not in returned:
                    yield i, None, self.lost

    def close(self) -> None:
        if self._own:
            close_quietly(self.client)


class _quietly:
    """Ignore any error (closing a client whose scheduler is gone)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return exc[0] is not None and not issubclass(exc[0], (KeyboardInterrupt, SystemExit))


def close_quietly(client: Any, timeout: float = 5) -> None:
    """Close a Dask client, ignoring any error (its scheduler may be gone)."""
    with _quietly():
        client.close(timeout=timeout)


def make_executor(workers: int | None = None, scheduler: Any = None):
    """``scheduler`` (an address or a Client) wins; else ``workers`` local processes
    (default: every core), run in this process when that is one."""
    if scheduler is not None:
        return DaskExecutor(scheduler)
    n = workers or os.cpu_count() or 1
    return SerialExecutor() if n == 1 else ProcessExecutor(n)
