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

__all__ = ["SerialExecutor", "ProcessExecutor", "DaskExecutor", "make_executor"]

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
        # spawn: numba and Dr.Jit threads do not survive fork
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


class DaskExecutor:
    """The same tasks on a Dask distributed cluster: ``Client(address)``, ``client.map``,
    ``as_completed``."""

    def __init__(self, address: Any):
        from distributed import Client

        if isinstance(address, Client):
            self.client = address
        else:
            try:
                self.client = Client(address, timeout="20s")
            except (OSError, TimeoutError) as exc:
                raise ConnectionError(f"cannot reach the Dask scheduler at {address}: {exc}") from None
        self._own = not isinstance(address, Client)
        info = self.client.scheduler_info()
        self.workers = max(1, len(info.get("workers", {})))
        self.description = f"Dask cluster {self.client.scheduler.address} ({self.workers} workers)"

    def run(self, fn: Callable, payloads: Sequence) -> Iterator[Outcome]:
        from distributed import as_completed

        if not payloads:
            return
        # tasks render and time: never let Dask skip one as a duplicate of a pure call
        futures = [self.client.submit(fn, *p, pure=False) for p in payloads]
        index = {f.key: i for i, f in enumerate(futures)}
        try:
            for future in as_completed(futures):
                i = index[future.key]
                if future.status == "error":
                    yield i, None, future.exception()
                else:
                    yield i, future.result(), None
                future.release()
        except (KeyboardInterrupt, SystemExit):
            self.client.cancel(futures)  # the cluster stops computing cells nobody will write
            raise

    def close(self) -> None:
        if self._own:
            self.client.close()


def make_executor(workers: int | None = None, scheduler: Any = None):
    """``scheduler`` (an address or a Client) wins; else ``workers`` local processes
    (default: every core), run in this process when that is one."""
    if scheduler is not None:
        return DaskExecutor(scheduler)
    n = workers or os.cpu_count() or 1
    return SerialExecutor() if n == 1 else ProcessExecutor(n)
