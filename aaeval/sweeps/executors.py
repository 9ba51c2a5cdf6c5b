"""Where a sweep's tasks run: this process, local worker processes, or a Dask cluster.

Each executor has one method, ``run(fn, payloads)``, yielding ``(index, result, error)``
as tasks finish, in any order. ``error`` is set only when the task could not finish: a
:class:`WorkerDied` (the process running it died: a segfault, ``os._exit``, the OOM
killer) or :class:`TaskTimedOut` (it ran past the time limit and its worker was killed) is
the task's own doing, and the sweep records the cell as failed with that reason (a rerun
tries it again); anything else (the cluster went away) leaves the cell unrecorded.

Every task has a time limit: ``max_seconds`` (an experiment's ``max_seconds``), else the
environment's ``AAEVAL_MAX_SECONDS``, else :data:`MAX_SECONDS`. A local worker that dies
or runs past it is replaced and the other tasks go on.

Every worker loads the registries (:func:`aaeval.registries.load`) before its first task:
a local worker when it starts, a Dask worker when it joins the cluster (a setup callback),
so the method specs its tasks carry are parsed against the same methods and plugins as in
the sweep's process.

An interrupt (Ctrl-C, or SIGTERM/SIGHUP, which the command line turns into one) ends the
workers before it goes on: none outlives the sweep. Local workers also watch their parent
and exit when it is gone, so even a ``kill -9`` of the sweep leaves no orphan computing.
"""

from __future__ import annotations

import math
import multiprocessing
import os
import signal
import threading
import time
from collections import deque
from contextlib import contextmanager as contextlib_contextmanager
from multiprocessing.connection import wait as wait_ready
from typing import Any, Callable, Iterator, Sequence

from aaeval import registries

__all__ = ["SerialExecutor", "ProcessExecutor", "DaskExecutor", "SchedulerLost", "WorkerDied", "TaskTimedOut",
           "WorkersCannotStart", "NO_MAIN_GUARD",
           "connect", "make_executor", "close_quietly", "quiet_distributed", "scheduler_workers", "task_limit",
           "MAX_SECONDS"]

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


#: What a local worker sends once it is ready (its registries loaded), before any answer.
_READY = "aaeval-worker-ready"

NO_MAIN_GUARD = ("a script that runs a sweep on local worker processes must start it under "
                 "'if __name__ == \"__main__\":' (each worker imports the script: without the guard it starts the "
                 "sweep again); or run it with workers=1")


# the recorded errors of cells that a rerun runs again without --retry-failed: the cell did
# not fail by its method's answer but by how it ended (its worker died or was stopped)
def task_limit(configured: float | None = None) -> float:
    """The time limit of one task: ``configured`` (the experiment's ``max_seconds``), else
    ``AAEVAL_MAX_SECONDS``, else :data:`MAX_SECONDS`."""
    if configured is not None:
        return float(configured)
    return _seconds("AAEVAL_MAX_SECONDS", MAX_SECONDS)


def _died(exitcode: int | None) -> WorkerDied:
    if exitcode is not None and exitcode < 0:
        try:
            name = f" ({signal.Signals(-exitcode).name})"
        except ValueError:
            name = ""
        return WorkerDied(f"worker died: signal {-exitcode}{name}")
    return WorkerDied(f"worker died: exit {exitcode}")


def _timed_out(limit: float) -> TaskTimedOut:
    return TaskTimedOut(f"timed out: stopped after {limit:g} s (the limit: max_seconds in the config or "
                        "AAEVAL_MAX_SECONDS)")


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
                yield i, None, _timed_out(self.max_seconds)
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
            time.sleep(0.5)
        os._exit(1)  # no cleanup to wait for: results go back to the parent, which is gone

    threading.Thread(target=watch, name="aaeval-parent-watch", daemon=True).start()


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
            return
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
        self.task: tuple[int, float] | None = None  # (index, when it was sent)
        self.ready = False  # it said so: it got past its start (importing, loading the registries)

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
                        worker.task = (i, time.monotonic())
                busy = [w for w in self._pool if w.task is not None]
                if not busy:
                    continue
                deadline = min(w.task[1] for w in busy) + self.max_seconds
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
                        if answer == _READY:
                            worker.ready = True
                            continue
                        if answer is None and not worker.ready:  # it never started: no task's doing
                            worker.process.join(5)
                            yield from self._cannot_start(worker.process.exitcode, todo)
                            return
                        if answer is None:  # the process ended without answering
                            worker.process.join(5)
                            exc = _died(worker.process.exitcode)
                            self._retire(worker)
                            yield i, None, exc
                            continue
                        worker.task = None
                        ok, value = answer
                        yield (i, value, None) if ok else (i, None, value)
                    elif now - started >= self.max_seconds:
                        self._retire(worker)  # killed: its native code cannot be interrupted otherwise
                        yield i, None, _timed_out(self.max_seconds)
        except (KeyboardInterrupt, SystemExit):
            self.terminate()  # do not wait for cells in flight: the user asked to stop
            raise
        except GeneratorExit:  # the caller stopped reading: tasks in flight are abandoned
            self.terminate()
            raise

    def _cannot_start(self, exitcode: int | None, todo: deque) -> Iterator[Outcome]:
        """Every task not answered, back as :class:`WorkersCannotStart`; the pool ended."""
        self.broken = WorkersCannotStart(f"local worker processes end before their first task ({_died(exitcode)}): "
                                         f"{NO_MAIN_GUARD}")
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


# Seconds to wait for the scheduler to answer, and for a scheduler with no workers to get
# one, before the sweep is refused (AAEVAL_DASK_TIMEOUT, AAEVAL_DASK_WORKER_TIMEOUT).
CONNECT_TIMEOUT = 20.0
WORKER_TIMEOUT = 60.0


class SchedulerLost(ConnectionError):
    """The Dask scheduler went away during the sweep: the cells it had not returned are lost
    (not recorded) and run on the next sweep."""


class WorkersLost(SchedulerLost):
    """Every worker of the Dask cluster died and none joined in time: lost like
    :class:`SchedulerLost` (its tasks would wait forever)."""


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

    timeout = _seconds("AAEVAL_DASK_TIMEOUT", CONNECT_TIMEOUT)
    with quiet_distributed():
        client = address if isinstance(address, Client) else _client_within(Client, address, timeout)
        try:
            workers = scheduler_workers(client, timeout)
        except SchedulerLost as exc:
            if client is not address:
                close_quietly(client)
            raise ConnectionError(str(exc)) from None
    if not workers:
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


def scheduler_workers(client, timeout: float) -> dict:
    """The scheduler's workers (address -> info), asked with an answer due within ``timeout``
    seconds: :class:`SchedulerLost` when none comes (a scheduler that is stopped, SIGSTOP or
    a frozen host, keeps its connections open and never answers; distributed's own calls
    wait for it forever)."""
    try:
        identity = client.sync(client.scheduler.identity, n_workers=-1, callback_timeout=timeout)
    except (TimeoutError, OSError) as exc:
        raise _no_answer(client, timeout, exc) from None
    return dict(identity.get("workers") or {})


def _no_answer(client, timeout: float, exc: BaseException) -> SchedulerLost:
    return SchedulerLost(f"the Dask scheduler at {_address(client)} did not answer within {timeout:g} s "
                         f"({type(exc).__name__}; AAEVAL_DASK_TIMEOUT sets the wait); finished cells are kept, "
                         "rerun the sweep when it answers")


def _address(client) -> str:
    return str(getattr(client.scheduler, "address", None) or "?")


class quiet_distributed:
    """distributed's loggers silenced while it is entered: a scheduler that goes away makes
    them print tens of lines of tracebacks and retries, where the sweep says what happened
    in one line (:class:`SchedulerLost`). Their levels are restored on exit."""

    def __enter__(self):
        import logging

        names = ["distributed", *(n for n in logging.root.manager.loggerDict if n.startswith("distributed."))]
        self.saved = {name: logging.getLogger(name).level for name in names}
        for name in names:
            logging.getLogger(name).setLevel(logging.CRITICAL + 1)
        return self

    def __exit__(self, *exc):
        import logging

        for name, level in self.saved.items():
            logging.getLogger(name).setLevel(level)
        return False


def _client_within(Client, address: Any, timeout: float):
    """``Client(address)`` or a ConnectionError after ``timeout`` seconds.

    Client's own ``timeout`` bounds the TCP connect, not the handshake after it: a peer that
    accepts the connection and never answers (a wrong port, a stalled scheduler) held it
    forever. So the Client is built in a thread the sweep waits for at most ``timeout`` (plus
    a little for its own timeout to fire first); a thread still waiting is abandoned (a
    daemon: it ends with the process)."""
    box: dict = {}

    def build() -> None:
        try:
            box["client"] = Client(address, timeout=f"{timeout}s")
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting thread
            box["error"] = exc

    thread = threading.Thread(target=build, name="aaeval-dask-connect", daemon=True)
    thread.start()
    thread.join(timeout + 2)
    if "client" in box:
        return box["client"]
    exc = box.get("error")
    if exc is None:
        raise ConnectionError(f"the Dask scheduler at {address} accepted the connection but did not answer within "
                              f"{timeout:g} s (AAEVAL_DASK_TIMEOUT sets the wait); is it a Dask scheduler?")
    if isinstance(exc, (KeyboardInterrupt, SystemExit)):
        raise exc
    text = " ".join(str(exc).split())[:300]
    raise ConnectionError(f"cannot reach the Dask scheduler at {address} within {timeout:g} s: "
                          f"{type(exc).__name__}: {text}")


class DaskExecutor:
    """The same tasks on a Dask distributed cluster: ``Client(address)``, ``client.map``,
    ``as_completed``.

    ``description`` and ``workers`` follow the cluster: a worker that dies during the sweep
    is seen in the records written after it (:meth:`current`). A scheduler that goes away
    ends the run: every task not yet returned comes back as :class:`SchedulerLost`.
    """

    def __init__(self, address: Any, max_seconds: float | None = None):
        from distributed import Client

        self.max_seconds = task_limit(max_seconds)
        self.answer_within = _seconds("AAEVAL_DASK_TIMEOUT", CONNECT_TIMEOUT)
        self._own = not isinstance(address, Client)
        self.client = connect(address)
        self._quiet = quiet_distributed().__enter__()  # until close(): a lost scheduler is said in one line
        # every worker, and any that joins later, loads the registries before its first task
        self.client.register_worker_callbacks(setup=registries.load)
        self.address = self.client.scheduler.address
        self.started_with = self._live_workers()
        self.workers = max(1, self.started_with)
        self.description = f"Dask cluster {self.address} ({self.workers} workers)"
        self.lost: SchedulerLost | None = None

    def _live_workers(self) -> int:
        try:
            return len(scheduler_workers(self.client, self.answer_within))
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
            finished = as_completed(futures)
            watch = _ClusterWatch(self)
            while not finished.is_empty():
                batch = finished.next_batch(block=False)
                for future in batch:
                    i = index[future.key]
                    if i in returned:  # cancelled here at its time limit: already answered
                        continue
                    if future.status == "cancelled":
                        raise self._lost("a task was cancelled")
                    if future.status == "error":
                        exc = future.exception()
                        if type(exc).__name__ == "KilledWorker":  # it took down every worker it was given
                            exc = WorkerDied(f"worker died: every worker that ran it died ({_short(exc)})")
                        outcome = (i, None, exc)
                    else:
                        try:  # the result comes through the scheduler: it may have stopped since
                            outcome = (i, future.result(timeout=self.answer_within), None)
                        except TimeoutError as exc:
                            raise _no_answer(self.client, self.answer_within, exc) from None
                    returned.add(i)
                    yield outcome
                    future.release()
                if not batch:
                    for i in watch.overdue(futures, index, returned):
                        returned.add(i)
                        yield i, None, _timed_out(self.max_seconds)
                    time.sleep(0.05)
        except (KeyboardInterrupt, SystemExit):
            with _quietly():
                self.client.cancel(futures)  # the cluster stops computing cells nobody will write
            raise
        except GeneratorExit:  # the caller stopped reading
            raise
        except BaseException as exc:  # noqa: BLE001 - a lost connection comes in many classes
            if self.client.status == "running" and not isinstance(exc, SchedulerLost) and self._live_workers():
                raise  # the cluster is fine: not ours to hide
            if isinstance(exc, SchedulerLost):  # said already: which and why
                self.lost = exc
            else:
                self.lost = self._lost(f"{type(exc).__name__}: {_short(exc) or 'connection closed'}")
            for i in range(len(payloads)):
                if i not in returned:
                    yield i, None, self.lost

    def _lost(self, why: str) -> SchedulerLost:
        return SchedulerLost(f"the Dask scheduler at {self.address} was lost during the sweep ({why}); finished "
                             "cells are kept, rerun the sweep when it is back")

    def close(self) -> None:
        if self._own:
            close_quietly(self.client)
        self._quiet.__exit__(None, None, None)


def _short(exc: BaseException, limit: int = 300) -> str:
    text = " ".join(str(exc).split())
    return text if len(text) <= limit else text[:limit] + "..."


class _ClusterWatch:
    """What a Dask sweep checks while it waits (once a second): a task processing past the
    time limit is cancelled and its worker restarted where it has a nanny (Dask cannot stop a
    running task otherwise); a cluster left without any worker for ``AAEVAL_DASK_WORKER_TIMEOUT``
    seconds ends the sweep, naming it (its tasks would wait forever)."""

    def __init__(self, executor: "DaskExecutor"):
        self.executor = executor
        self.grace = _seconds("AAEVAL_DASK_WORKER_TIMEOUT", WORKER_TIMEOUT)
        self.since: dict = {}  # task key -> when it was first seen processing
        self.empty_since: float | None = None
        self.next_check = 0.0

    def overdue(self, futures, index, returned) -> list[int]:
        now = time.monotonic()
        if now < self.next_check:
            return []
        self.next_check = now + 1.0
        ex = self.executor
        if not scheduler_workers(ex.client, ex.answer_within):  # a scheduler that does not answer ends the sweep
            self.empty_since = self.empty_since or now
            if now - self.empty_since > self.grace:
                raise WorkersLost(f"the last worker of the Dask cluster at {ex.address} died and none joined "
                                  f"within {self.grace:g} s (AAEVAL_DASK_WORKER_TIMEOUT); finished cells are kept, "
                                  "rerun the sweep when it has workers")
            return []
        self.empty_since = None
        try:
            processing = ex.client.sync(ex.client.scheduler.processing, workers=None, callback_timeout=ex.answer_within)
        except Exception:  # noqa: BLE001 - no answer now: checked again in a second
            return []
        late, workers = [], set()
        running = {}
        for worker, keys in processing.items():
            for key in keys:
                running[key] = worker
        for key in list(self.since):
            if key not in running:
                del self.since[key]
        for key, worker in running.items():
            started = self.since.setdefault(key, now)
            i = index.get(key)
            if i is not None and i not in returned and now - started > ex.max_seconds:
                with _quietly():
                    futures[i].cancel()
                late.append(i)
                workers.add(worker)
        if workers:
            with _quietly():  # a worker without a nanny cannot be restarted: its thread runs on
                ex.client.restart_workers(list(workers), timeout=30, raise_for_error=False)
        return late


class _quietly:
    """Ignore any error (closing a client whose scheduler is gone)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return exc[0] is not None and not issubclass(exc[0], (KeyboardInterrupt, SystemExit))


def close_quietly(client: Any, timeout: float = 5) -> None:
    """Close a Dask client, ignoring any error (its scheduler may be gone)."""
    with _quietly(), quiet_distributed():
        client.close(timeout=timeout)


def make_executor(workers: int | None = None, scheduler: Any = None, max_seconds: float | None = None):
    """``scheduler`` (an address or a Client) wins; else ``workers`` local processes
    (default: every core), run in this process when that is one. ``max_seconds``: the
    limit of one task (see :func:`max_seconds`)."""
    if scheduler is not None:
        return DaskExecutor(scheduler, max_seconds=max_seconds)
    n = workers or os.cpu_count() or 1
    return SerialExecutor(max_seconds) if n == 1 else ProcessExecutor(n, max_seconds)
