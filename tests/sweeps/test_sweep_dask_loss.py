"""Dask losses say what was lost: an unreachable scheduler or one with no
workers is refused before the sweep folder is touched (no empty ``sweep.lock``), after a
stated timeout; a scheduler that dies mid-sweep is named, the sweep exits 1 and a rerun
finishes; the executor column follows dead workers."""

from __future__ import annotations

import threading
import time

import pytest

from aaeval.cli import main
from tests.helpers.sweep_util import MANY, wait_for_cells, write_config

import distributed
import dask  # noqa: E402  (installed with distributed)

def local_cluster(n_workers):
    """An in-process cluster. Connect attempts give up after 3 s (not Dask's 30): closing a
    cluster whose scheduler a test killed otherwise waits 30 s for it to answer. Its
    dashboard on a free port (None still starts it on 8787: two clusters at once warned of
    the taken port on the sweep's stderr)."""
    with dask.config.set({"distributed.comm.timeouts.connect": "3s"}):
        return _Quick(n_workers=n_workers, threads_per_worker=1, processes=False, protocol="tcp",
                      host="127.0.0.1", dashboard_address=":0")


class _Quick(distributed.LocalCluster):
    def close(self, *args, **kwargs):
        # a scheduler a test closed refuses every connection: asking it to terminate is
        # retried until the connect timeout, for nothing
        gone = self.scheduler.status == distributed.core.Status.closed
        with dask.config.set({"distributed.comm.timeouts.connect": "0.1s" if gone else "3s"}):
            return super().close(*args, **kwargs)


@pytest.mark.slow
def test_an_unreachable_scheduler_leaves_no_folder(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("AAEVAL_DASK_TIMEOUT", "1")
    config = write_config(tmp_path, MANY)
    code = main(["sweep", str(config), "--out", str(tmp_path / "out"), "--scheduler", "tcp://127.0.0.1:9", "-q"])
    err = capsys.readouterr().err
    assert code == 2 and "cannot reach the Dask scheduler" in err and "1 s" in err
    assert not (tmp_path / "out").exists()  # no empty sweep.lock left behind


@pytest.mark.slow
def test_a_scheduler_without_workers_is_refused_after_the_stated_wait(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("AAEVAL_DASK_WORKER_TIMEOUT", "0.5")
    config = write_config(tmp_path, MANY)
    with local_cluster(0) as cluster:
        start = time.monotonic()
        code = main(["sweep", str(config), "--out", str(tmp_path / "out"), "--scheduler",
                     cluster.scheduler_address, "-q"])
        waited = time.monotonic() - start
    err = capsys.readouterr().err
    assert code == 2 and "has no workers" in err and "0.5 s" in err, err
    assert waited < 120  # a hang guard, not a timing claim
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_a_scheduler_killed_mid_sweep_is_named_and_the_rerun_finishes(tmp_path, capsys):
    config = write_config(tmp_path, MANY)
    out = tmp_path / "out"
    with local_cluster(1) as cluster:
        def kill_after_first_cells():
            wait_for_cells(out, 3)
            cluster.loop.add_callback(cluster.scheduler.close)

        killer = threading.Thread(target=kill_after_first_cells, daemon=True)
        killer.start()
        code = main(["sweep", str(config), "--out", str(out), "--scheduler", cluster.scheduler_address, "-q"])
        killer.join()
    captured = capsys.readouterr()
    assert code == 1, captured.err
    assert "scheduler" in captured.err and "was lost" in captured.err and captured.err.count("\n") == 1
    done = len(list((out / "cells").glob("*.json")))
    assert 3 <= done < 120
    # the folder is sound and a rerun (here, locally) runs only what was lost
    assert main(["sweep", str(config), "--out", str(out), "--workers", "1", "-q"]) == 0
    assert len(list((out / "cells").glob("*.json"))) == 120


def test_the_executor_column_follows_a_dead_worker(tmp_path):
    from aaeval.sweeps.dask_executor import DaskExecutor

    with local_cluster(2) as cluster:
        executor = DaskExecutor(cluster.scheduler_address)
        try:
            assert executor.current() == {"executor": executor.description, "workers": 2}
            assert "(2 workers)" in executor.description
            name = next(iter(cluster.workers))
            cluster.sync(cluster.workers[name].close)
            deadline = time.monotonic() + 60
            while executor._live_workers() != 1 and time.monotonic() < deadline:
                time.sleep(0.1)
            now = executor.current()
            assert now["workers"] == 1 and "1 workers; 1 lost" in now["executor"]
        finally:
            executor.close()


def _nap(seconds):
    time.sleep(seconds)
    return seconds


# Holds _held's task until the test has its answer: the in-process cluster's close waits for
# a task's thread, which no time limit can stop
RELEASE = threading.Event()


def _held(seconds):
    RELEASE.wait(seconds)
    return seconds


@pytest.mark.slow
def test_a_dask_task_past_the_time_limit_is_answered_as_timed_out(monkeypatch):
    """A per-task time limit on Dask too (measured from when the scheduler shows the
    task processing); the other tasks still answer."""
    from aaeval.sweeps.dask_executor import DaskExecutor
    from aaeval.sweeps.task_failures import TaskTimedOut

    RELEASE.clear()
    with local_cluster(2) as cluster:
        executor = DaskExecutor(cluster.scheduler_address, max_seconds=1)
        try:
            start = time.monotonic()
            out = {i: (result, exc) for i, result, exc in executor.run(_held, [(60,), (0.1,)])}
            took = time.monotonic() - start
        finally:
            RELEASE.set()
            executor.close()
    assert isinstance(out[0][1], TaskTimedOut) and "1 s" in str(out[0][1])
    assert out[1] == (0.1, None)
    assert took < 6


@pytest.mark.slow
def test_a_dask_sweep_whose_last_worker_died_stops_naming_it(monkeypatch):
    """The only worker dies mid-run; after AAEVAL_DASK_WORKER_TIMEOUT seconds with
    none, every task not returned comes back as WorkersLost naming the cluster (no hang)."""
    from aaeval.sweeps.dask_executor import DaskExecutor
    from aaeval.sweeps.task_failures import WorkersLost

    monkeypatch.setenv("AAEVAL_DASK_WORKER_TIMEOUT", "0.5")
    # connect attempts give up after 3 s during the run too: a result fetched just as its worker
    # died is asked of that worker until then (30 s by default, past the 20 s the sweep waits
    # for an answer: "the scheduler did not answer")
    with dask.config.set({"distributed.comm.timeouts.connect": "3s"}), local_cluster(1) as cluster:
        executor = DaskExecutor(cluster.scheduler_address)
        try:
            name = next(iter(cluster.workers))
            killer = threading.Timer(0.3, lambda: cluster.sync(cluster.workers[name].close))
            killer.start()
            start = time.monotonic()
            out = list(executor.run(_nap, [(0.3,)] * 20))
            took = time.monotonic() - start
            killer.join()
        finally:
            executor.close()
    lost = [exc for _, _, exc in out if exc is not None]
    assert lost and all(isinstance(exc, WorkersLost) for exc in lost)
    assert "the last worker of the Dask cluster at" in str(lost[0]) and "0.5 s" in str(lost[0])
    assert len(out) == 20 and took < 60


@pytest.mark.slow
def test_a_result_lost_with_the_last_worker_is_not_a_silent_scheduler(monkeypatch):
    """Two tasks finish together; the only worker dies before the second's result is fetched:
    the cluster would compute it again if it had a worker, so it ends as WorkersLost after
    AAEVAL_DASK_WORKER_TIMEOUT, not as a scheduler that "did not answer" within
    AAEVAL_DASK_TIMEOUT (20 s: the scheduler answers; the result is gone)."""
    from aaeval.sweeps.dask_executor import DaskExecutor
    from aaeval.sweeps.task_failures import WorkersLost

    monkeypatch.setenv("AAEVAL_DASK_WORKER_TIMEOUT", "0.5")
    RELEASE.clear()
    with dask.config.set({"distributed.comm.timeouts.connect": "3s"}), \
            _Quick(n_workers=1, threads_per_worker=2, processes=False, protocol="tcp", host="127.0.0.1",
                   dashboard_address=":0") as cluster:
        executor = DaskExecutor(cluster.scheduler_address)
        try:
            def release_both():
                deadline = time.monotonic() + 60
                while time.monotonic() < deadline and sum(
                        t.state == "processing" for t in cluster.scheduler.tasks.values()) < 2:
                    time.sleep(0.01)
                RELEASE.set()

            releaser = threading.Thread(target=release_both, daemon=True)
            releaser.start()
            out = []
            for outcome in executor.run(_held, [(30,), (30,)]):
                if not out:
                    time.sleep(0.2)  # the other task has finished too: its result is on the worker
                    cluster.sync(cluster.workers[next(iter(cluster.workers))].close)
                out.append(outcome)
            releaser.join()
        finally:
            RELEASE.set()
            executor.close()
    assert out[0][1:] == (30, None), out
    assert isinstance(out[1][2], WorkersLost) and "the last worker" in str(out[1][2]), out


@pytest.mark.slow
def test_a_peer_that_never_answers_is_refused_after_the_stated_wait(tmp_path, capsys, monkeypatch):
    """A peer that accepts the connection and never answers held Client() forever."""
    import socket

    monkeypatch.setenv("AAEVAL_DASK_TIMEOUT", "0.5")
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    held = []
    stop = threading.Event()

    def accept():
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                held.append(server.accept()[0])
            except OSError:
                pass

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    try:
        config = write_config(tmp_path, MANY)
        start = time.monotonic()
        code = main(["sweep", str(config), "--out", str(tmp_path / "out"), "--scheduler",
                     f"tcp://127.0.0.1:{server.getsockname()[1]}", "-q"])
        waited = time.monotonic() - start
    finally:
        stop.set()
        thread.join()
        for c in held:
            c.close()
        server.close()
    err = capsys.readouterr().err
    assert code == 2 and "did not answer within 0.5 s" in err and err.count("\n") == 1, err
    assert waited < 30
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("address", ["", "   "])
def test_an_empty_scheduler_address_is_refused_not_run_locally(tmp_path, capsys, address):
    """``--scheduler "$UNSET"`` ran the sweep locally without a word; it is refused before work."""
    config = write_config(tmp_path, MANY)
    code = main(["sweep", str(config), "--out", str(tmp_path / "out"), "--scheduler", address, "-q"])
    err = capsys.readouterr().err
    assert code == 2 and "--scheduler: empty address" in err and err.count("\n") == 1, err
    assert not (tmp_path / "out").exists()
