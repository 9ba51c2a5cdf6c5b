"""Running a sweep's tasks on this machine: in this process, or on local worker processes.

Each executor has one method, ``run(fn, payloads)``, yielding ``(index, result, error)`` as
tasks finish (:data:`~aaeval.sweeps.task_failures.Outcome`). A local worker that dies or runs
past the time limit is its task's failure (:class:`~aaeval.sweeps.task_failures.WorkerDied`,
:class:`~aaeval.sweeps.task_failures.TaskTimedOut`); it is replaced and the other tasks go on.
A task's time limit counts from when its worker has started: a slow start is not the task's.

A local worker loads the registries (:func:`aaeval.registries.load`) when it starts, before
its first task, so the method specs its tasks carry are parsed against the same methods and
plugins as in the sweep's process.

An interrupt (Ctrl-C, or SIGTERM/SIGHUP, which the command line turns into one) ends the
workers before it goes on: none outlives the sweep. Workers also watch their parent and exit
when it is gone, so even a ``kill -9`` of the sweep leaves no orphan computing.
"""

from __future__ import annotations

import atexit
import math
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections import deque
from contextlib import contextmanager as contextlib_contextmanager
from multiprocessing.connection import wait as wait_ready
from typing import Callable, Iterator, Sequence

from aaeval import registries
from aaeval.sweeps.task_failures import (NO_MAIN_GUARD, Outcome, WorkersCannotStart, task_limit, timed_out,
                                         worker_died)

__all__ = ["SerialExecutor", "ProcessExecutor"]

#: What a local worker sends once it is ready (its registries loaded), before any answer.
_READY = "aaeval-worker-ready"

#: Seconds a local worker may take to start (import aaeval, load the registries and plugins)
#: before the sweep gives up on its workers: a start takes about a second, a loaded
#: machine's a few; one that hangs (a plugin waiting on something only workers see) must not
#: hang the sweep, now that a task's own limit counts from the worker's start.
START_SECONDS = 120.0


class _Alarm(BaseException):
    """Raised in this process by SIGALRM when a serial task is past its limit. A
    BaseException, so that the task's own ``except Exception`` (a cell records its failures)
    does not take it for the method's error."""


class SerialExecutor:
    """Runs every task in this process, one after the other (``--workers 1``).

    The time limit is a SIGALRM in the main thread: it stops Python code (a sleeping or
    looping method) but not native code that never returns to the interpreter, and a method
    that kills its process ends the sweep; ``--workers 2`` or more isolates both.
    """

    workers = 1
    description = "this process"

    def __init__(self, max_seconds: float | None = None):
        self.max_seconds = task_limit(max_seconds)

    def run(self, fn: Callable, payloads: Sequence) -> Iterator[Outcome]:
        for i, payload in enumerate(payloads):
            try:
                with self._limit():
                    result = fn(*payload)
            except _Alarm:
                yield i, None, timed_out(self.max_seconds)
                continue
            yield i, result, None

    @contextlib_contextmanager
    def _limit(self):
        usable = (hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()
                  and math.isfinite(self.max_seconds))
        if not usable:
            yield
            return

        def ring(signum, frame):
            raise _Alarm()

        previous = signal.signal(signal.SIGALRM, ring)
        signal.setitimer(signal.ITIMER_REAL, self.max_seconds)
        try:
            yield
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)

    def close(self) -> None:
        pass


def _exit_with_parent(parent: int) -> None:
    """Worker initializer: exit as soon as the sweep process that started us is gone."""

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.1)  # a killed sweep's workers stop within a tenth of a second; a getppid costs nothing
        os._exit(1)  # no cleanup to wait for: results go back to the parent, which is gone

    threading.Thread(target=watch, name="aaeval-parent-watch", daemon=True).start()


def _exit_now(code: int) -> None:
    """End this worker without the interpreter's teardown (a tenth of a second or more of
    freeing modules, which the sweep waits for): its answers went back over the pipe and it
    owns nothing that needs freeing. Its exit handlers still run (a coverage run saves its
    data there) and what a method printed is flushed."""
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except Exception:  # noqa: BLE001 - a closed or broken stream: nothing to keep
            pass
    os._exit(code)


def _worker_main(conn, parent: int) -> None:
    """A local worker: run ``(fn, args)`` messages one at a time, answer ``(ok, value)``."""
    # Ctrl-C reaches the whole process group: the sweep decides, and ends its workers itself
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _exit_with_parent(parent)
    registries.load()  # before the first message: its specs are parsed as it is received
    conn.send(_READY)
    while True:
        try:
            message = conn.recv()
        except (EOFError, OSError):
            return
        if message is None:
            _exit_now(0)
        fn, args = message
        try:
            answer = (True, fn(*args))
        except BaseException as exc:  # noqa: BLE001 - every task's failure goes back to the sweep
            answer = (False, exc)
        try:
            conn.send(answer)
        except Exception as exc:  # noqa: BLE001 - a result or exception that cannot be pickled
            conn.send((False, RuntimeError(f"the task's answer cannot be sent back ({type(exc).__name__}: {exc})")))


class _Worker:
    def __init__(self, context, parent: int):
        self.conn, child = context.Pipe()
        self.process = context.Process(target=_worker_main, args=(child, parent), daemon=True,
                                       name="aaeval-sweep-worker")
        self.process.start()
        child.close()
        # (index, when its clock started): None until the worker is ready, so that a slow
        # start (importing aaeval, loading the registries and plugins) is not the task's time
        self.task: tuple[int, float | None] | None = None
        self.ready = False  # it said so: it got past its start (importing, loading the registries)
        self.spawned = time.monotonic()

    def stop(self) -> None:
        if self.process.is_alive():
            self.process.terminate()
            self.process.join(5)
            if self.process.is_alive():
                self.process.kill()
        self.process.join(5)
        self.conn.close()


class ProcessExecutor:
    """Local worker processes; each warms its JIT once, on its first task of a method.

    A pool of its own rather than ``concurrent.futures``: there, one worker that dies breaks
    the whole pool (``BrokenProcessPool``) and nothing says which task killed it. Here each
    worker runs one task at a time, so a worker that dies or runs past the time limit is
    its task's failure: that task comes back as :class:`WorkerDied` or
    :class:`TaskTimedOut`, the worker is replaced and the other tasks go on.
    """

    def __init__(self, workers: int, max_seconds: float | None = None):
        self.workers = workers
        self.description = f"{workers} local worker processes"
        self.max_seconds = task_limit(max_seconds)
        self._context = multiprocessing.get_context("spawn")  # spawn: Dr.Jit's threads do not survive fork
        self._parent = os.getpid()
        self._pool: list[_Worker] = []
        self.broken: WorkersCannotStart | None = None

    def _spawn(self) -> _Worker:
        worker = _Worker(self._context, self._parent)
        self._pool.append(worker)
        return worker

    def _retire(self, worker: _Worker) -> None:
        self._pool.remove(worker)
        worker.stop()

    def run(self, fn: Callable, payloads: Sequence) -> Iterator[Outcome]:
        todo = deque(enumerate(payloads))
        if self.broken is not None:  # its workers cannot start: nothing more can run
            for i, _ in todo:
                yield i, None, self.broken
            return
        try:
            while todo or any(w.task for w in self._pool):
                busy_now = sum(w.task is not None for w in self._pool)
                while len(self._pool) < min(self.workers, busy_now + len(todo)):
                    self._spawn()  # at the start, and in place of one that died or was stopped
                for worker in list(self._pool):
                    if worker.task is None and todo:
                        i, payload = todo.popleft()
                        try:
                            worker.conn.send((fn, payload))
                        except (BrokenPipeError, EOFError, OSError):  # it died idle: not this task's doing
                            todo.appendleft((i, payload))
                            self._retire(worker)
                            continue
                        worker.task = (i, time.monotonic() if worker.ready else None)
                busy = [w for w in self._pool if w.task is not None]
                if not busy:
                    continue
                deadline = min([w.task[1] + self.max_seconds for w in busy if w.task[1] is not None]
                               + [w.spawned + START_SECONDS for w in busy if not w.ready])
                ready = wait_ready([w.conn for w in busy] + [w.process.sentinel for w in busy],
                                   timeout=max(0.0, min(deadline - time.monotonic(), 3600.0)))
                now = time.monotonic()
                for worker in busy:
                    i, started = worker.task
                    if worker.conn in ready or worker.process.sentinel in ready:
                        answer = None
                        try:
                            if worker.conn.poll():
                                answer = worker.conn.recv()
                        except (EOFError, OSError):
                            answer = None
                        if answer == _READY:  # its task (sent ahead, waiting in the pipe) starts now
                            worker.ready = True
                            worker.task = (i, time.monotonic())
                            continue
                        if answer is None and not worker.ready:  # it never started: no task's doing
                            worker.process.join(5)
                            died = worker_died(worker.process.exitcode)
                            yield from self._cannot_start(todo, f"end before their first task ({died}): {NO_MAIN_GUARD}")
                            return
                        if answer is None:  # the process ended without answering
                            worker.process.join(5)
                            exc = worker_died(worker.process.exitcode)
                            self._retire(worker)
                            yield i, None, exc
                            continue
                        worker.task = None
                        ok, value = answer
                        yield (i, value, None) if ok else (i, None, value)
                    elif not worker.ready and now - worker.spawned >= START_SECONDS:
                        yield from self._cannot_start(todo, f"did not start within {START_SECONDS:g} s "
                                                            "(importing aaeval and loading its plugins)")
                        return
                    elif started is not None and now - started >= self.max_seconds:
                        self._retire(worker)  # killed: its native code cannot be interrupted otherwise
                        yield i, None, timed_out(self.max_seconds)
        except (KeyboardInterrupt, SystemExit):
            self.terminate()  # do not wait for cells in flight: the user asked to stop
            raise
        except GeneratorExit:  # the caller stopped reading: tasks in flight are abandoned
            self.terminate()
            raise

    def _cannot_start(self, todo: deque, why: str) -> Iterator[Outcome]:
        """Every task not answered, back as :class:`WorkersCannotStart` (the workers ``why``);
        the pool ended."""
        self.broken = WorkersCannotStart(f"local worker processes {why}")
        in_flight = [w.task[0] for w in self._pool if w.task is not None]
        self.terminate()
        for i in [*in_flight, *(i for i, _ in todo)]:
            yield i, None, self.broken

    def terminate(self) -> None:
        """End the workers now; their cells in flight are lost (and rerun next time)."""
        for worker in self._pool:
            if worker.process.is_alive():
                worker.process.terminate()
        for worker in list(self._pool):
            self._retire(worker)

    def close(self) -> None:
        for worker in self._pool:
            if worker.task is None:
                try:
                    worker.conn.send(None)  # finish: the worker returns and exits
                except (BrokenPipeError, OSError):
                    pass
        for worker in list(self._pool):
            worker.process.join(10)
            self._retire(worker)
