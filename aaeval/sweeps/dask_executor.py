"""Running a sweep's tasks on a Dask distributed cluster, and connecting to one.

:class:`DaskExecutor` runs the same tasks as the local executors (``run(fn, payloads)``,
yielding ``(index, result, error)`` as tasks finish) with ``client.submit`` and
``as_completed``. Every Dask worker loads the registries (:func:`aaeval.registries.load`)
when it joins the cluster (a setup callback), before its first task. A task past its time
limit is cancelled and its worker restarted; a scheduler that goes away, or a cluster left
without workers, ends the run: every task not yet returned comes back as
:class:`~aaeval.sweeps.task_failures.SchedulerLost`, and distributed's own logging of it is
silenced (the sweep says it in one line).
"""

from __future__ import annotations

import threading
import time
from typing import Any, Callable, Iterator, Sequence

from aaeval import registries
from aaeval.limits import env_seconds
from aaeval.sweeps.task_failures import (Outcome, SchedulerLost, WorkerDied, WorkersLost, task_limit,
                                         timed_out)

__all__ = ["DaskExecutor", "connect", "close_quietly", "quiet_distributed", "scheduler_workers",
           "CONNECT_TIMEOUT", "WORKER_TIMEOUT"]

# Seconds to wait for the scheduler to answer, and for a scheduler with no workers to get
# one, before the sweep is refused (AAEVAL_DASK_TIMEOUT, AAEVAL_DASK_WORKER_TIMEOUT).
CONNECT_TIMEOUT = 20.0
WORKER_TIMEOUT = 60.0

#: Seconds a count of the cluster's workers stands for the records written after it.
RECOUNT_SECONDS = 1.0

#: Seconds between two looks at the cluster while a sweep waits (:class:`_ClusterWatch`): a
#: task past its time limit, or a cluster left without workers, is seen within this.
CHECK_SECONDS = 0.5


def connect(address: Any):
    """A ``distributed.Client`` of the scheduler at ``address`` (or ``address`` itself if it
    is a Client) that has at least one worker.

    An unreachable scheduler is a ``ConnectionError`` after ``AAEVAL_DASK_TIMEOUT`` seconds
    (default 20); one with no worker, after ``AAEVAL_DASK_WORKER_TIMEOUT`` seconds (default
    60) of waiting for one to join. Called before a sweep touches its folder.
    """
    from distributed import Client

    timeout = env_seconds("AAEVAL_DASK_TIMEOUT", CONNECT_TIMEOUT)
    with quiet_distributed():
        client = address if isinstance(address, Client) else _client_within(Client, address, timeout)
        try:
            workers = scheduler_workers(client, timeout)
        except SchedulerLost as exc:
            if client is not address:
                close_quietly(client)
            raise ConnectionError(str(exc)) from None
    if not workers:
        wait = env_seconds("AAEVAL_DASK_WORKER_TIMEOUT", WORKER_TIMEOUT)
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
    forever. So the Client is built in a thread the sweep waits for ``timeout`` seconds, the
    stated wait, and no longer; the Client's own connect gives up a little before that (a
    quarter of the wait, at most half a second), so that its error, which says why (a refused
    connection, an unknown host), comes first where it comes at all. A thread still waiting
    is abandoned (a daemon: it ends with the process)."""
    box: dict = {}

    def build() -> None:
        try:
            box["client"] = Client(address, timeout=f"{timeout - min(0.5, timeout / 4)}s")
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting thread
            box["error"] = exc

    thread = threading.Thread(target=build, name="aaeval-dask-connect", daemon=True)
    thread.start()
    thread.join(timeout)
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
        self.answer_within = env_seconds("AAEVAL_DASK_TIMEOUT", CONNECT_TIMEOUT)
        # a scheduler that is there answers a question in milliseconds: where the sweep only
        # asks whether it is (a count for the records, after a lost connection), one that
        # does not answer within this is taken as gone, not waited for the whole timeout
        self._quick = min(1.0, self.answer_within / 3)
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

    def _live_workers(self, within: float | None = None) -> int:
        """How many workers the scheduler has, asked with an answer due within ``within``
        seconds (default ``AAEVAL_DASK_TIMEOUT``); 0 when none comes."""
        try:
            n = len(scheduler_workers(self.client, self.answer_within if within is None else within))
        except Exception:  # noqa: BLE001 - no answer: none known
            n = 0
        self._counted = (time.monotonic(), n)
        return n

    def current(self) -> dict:
        """The executor as a record's ``executor`` and ``workers`` fields, as counted at most
        :data:`RECOUNT_SECONDS` ago: the scheduler is asked once a second, not once a record
        (a round trip each on a remote cluster, and a whole ``AAEVAL_DASK_TIMEOUT`` each when
        it has stopped answering)."""
        when, n = self._counted
        if time.monotonic() - when >= RECOUNT_SECONDS:
            n = self._live_workers(self._quick)
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
                        try:
                            outcome = (i, self._result(future), None)
                        except _ResultLost:  # computed again once a worker has it (the watch ends a wait for none)
                            finished.add(future)
                            continue
                    returned.add(i)
                    yield outcome
                    future.release()
                if not batch:
                    for i in watch.overdue(futures, index, returned):
                        returned.add(i)
                        yield i, None, timed_out(self.max_seconds)
                    time.sleep(0.05)
        except (KeyboardInterrupt, SystemExit):
            with _quietly():
                self.client.cancel(futures)  # the cluster stops computing cells nobody will write
            raise
        except GeneratorExit:  # the caller stopped reading
            raise
        except BaseException as exc:  # noqa: BLE001 - a lost connection comes in many classes
            if (self.client.status == "running" and not isinstance(exc, SchedulerLost)
                    and self._live_workers(self._quick)):
                raise  # the cluster is fine: not ours to hide
            if isinstance(exc, SchedulerLost):  # said already: which and why
                self.lost = exc
            else:
                self.lost = self._lost(f"{type(exc).__name__}: {_short(exc) or 'connection closed'}")
            for i in range(len(payloads)):
                if i not in returned:
                    yield i, None, self.lost

    def _result(self, future) -> Any:
        """A finished task's result. It comes through the scheduler, which may have stopped
        since (:class:`SchedulerLost` after ``AAEVAL_DASK_TIMEOUT`` seconds); the worker that
        held it may have died since (:class:`_ResultLost`: the task is not finished any more,
        or the scheduler answers but has no worker left to fetch it from)."""
        # the last part of the wait asks whether the scheduler answers at all: all of it is
        # AAEVAL_DASK_TIMEOUT, as stated
        ask = self._quick
        deadline = time.monotonic() + self.answer_within - ask
        while True:
            try:
                return future.result(timeout=min(0.5, max(0.05, deadline - time.monotonic())))
            except TimeoutError as exc:
                if self.client.status != "running":  # the connection closed: no answer will come
                    raise self._lost("the connection to it closed") from None
                if future.status != "finished":
                    raise _ResultLost() from None
                if time.monotonic() >= deadline:
                    # the scheduler may still be asking the dead worker (Dask's connect timeout);
                    # one that does not answer at once has already had its wait
                    try:
                        workers = scheduler_workers(self.client, ask)
                    except SchedulerLost:
                        raise _no_answer(self.client, self.answer_within, exc) from None
                    if not workers:
                        raise _ResultLost() from None
                    raise _no_answer(self.client, self.answer_within, exc) from None

    def _lost(self, why: str) -> SchedulerLost:
        return SchedulerLost(f"the Dask scheduler at {self.address} was lost during the sweep ({why}); finished "
                             "cells are kept, rerun the sweep when it is back")

    def close(self) -> None:
        if self._own:
            close_quietly(self.client)
        if self.lost is None:
            self._quiet.__exit__(None, None, None)
        # else distributed stays silent for the rest of the process: the lost client's
        # background threads still log the closed connection (with a traceback) after close
        # returns, and the sweep has said what happened in one line


def _short(exc: BaseException, limit: int = 300) -> str:
    text = " ".join(str(exc).split())
    return text if len(text) <= limit else text[:limit] + "..."


class _ClusterWatch:
    """What a Dask sweep checks while it waits (every :data:`CHECK_SECONDS`): a task
    processing past the time limit is cancelled and its worker restarted where it has a
    nanny (Dask cannot stop a running task otherwise); a cluster left without any worker for
    ``AAEVAL_DASK_WORKER_TIMEOUT`` seconds ends the sweep, naming it (its tasks would wait
    forever)."""

    def __init__(self, executor: "DaskExecutor"):
        self.executor = executor
        self.grace = env_seconds("AAEVAL_DASK_WORKER_TIMEOUT", WORKER_TIMEOUT)
        self.since: dict = {}  # task key -> when it was first seen processing
        self.empty_since: float | None = None
        self.next_check = 0.0

    def overdue(self, futures, index, returned) -> list[int]:
        now = time.monotonic()
        if now < self.next_check:
            return []
        self.next_check = now + CHECK_SECONDS
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
        except Exception:  # noqa: BLE001 - no answer now: checked again at the next look
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


class _ResultLost(Exception):
    """A finished task's result went with its worker before it was fetched."""


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
