"""A Dask cluster started the documented way: ``dask scheduler`` and ``dask worker`` as
separate processes on 127.0.0.1 (free ports), and ``aaeval sweep --scheduler tcp://...``
as a third.

Here, unlike an in-process ``LocalCluster``, every task crosses a scheduler that unpickles
it with no method registered and a worker that loaded the registries itself: the rows must
be those of a local run, with no cell failed. A scheduler frozen mid-sweep (SIGSTOP) ends
the sweep within its stated timeout, and a scheduler killed mid-sweep is said in aaeval's
one line rather than distributed's tracebacks; the cells finished before either are kept.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from aaeval.sweeps import load_experiment, run_sweep
from tests.helpers.sweep_util import MANY, wait_for_cells, write_config

import distributed  # noqa: F401 - a dependency: a broken install fails here

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]

def _env(tmp_path: Path, answer_within: float = 5) -> dict:
    return {**os.environ, "AAEVAL_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT),
            "AAEVAL_DASK_TIMEOUT": f"{answer_within:g}", "AAEVAL_DASK_WORKER_TIMEOUT": "60"}


class Deployed:
    """``dask scheduler`` and one ``dask worker`` (one thread, with its nanny), each in a
    session of its own so that teardown ends it and its children. Both start at once: the
    worker finds the scheduler's address in its scheduler file when it is written."""

    def __init__(self, tmp_path: Path):
        self.tmp_path = tmp_path
        self.file = tmp_path / "scheduler.json"
        env = _env(tmp_path)
        self.scheduler = self._start(["scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                                      "--scheduler-file", str(self.file)], env, "scheduler.log")
        self.worker = self._start(["worker", "--scheduler-file", str(self.file), "--host", "127.0.0.1", "--nthreads",
                                   "1", "--nworkers", "1", "--no-dashboard", "--death-timeout", "60"], env, "worker.log")
        self.address = self._address()

    def _start(self, args: list[str], env: dict, log: str) -> subprocess.Popen:
        with open(self.tmp_path / log, "wb") as out:
            return subprocess.Popen([sys.executable, "-m", "dask", *args], stdout=out, stderr=subprocess.STDOUT,
                                    env=env, cwd=self.tmp_path, start_new_session=True)

    def _address(self) -> str:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            if self.scheduler.poll() is not None:
                raise AssertionError((self.tmp_path / "scheduler.log").read_text())
            try:
                return json.loads(self.file.read_text())["address"]
            except (OSError, ValueError, KeyError):
                time.sleep(0.1)
        raise AssertionError("the scheduler wrote no address in 120 s")

    def stop(self) -> None:
        for process in (self.worker, self.scheduler):
            for sig in (signal.SIGCONT, signal.SIGKILL):
                try:
                    os.killpg(process.pid, sig)
                except ProcessLookupError:
                    pass
            process.wait(30)


@pytest.fixture
def deployed(tmp_path):
    cluster = Deployed(tmp_path)
    try:
        yield cluster
    finally:
        cluster.stop()


def sweep(tmp_path: Path, config: Path, out: Path, *extra: str, answer_within: float = 5) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "aaeval", "sweep", str(config), "--out", str(out), "-q", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=_env(tmp_path, answer_within), cwd=tmp_path)


def test_a_sweep_on_a_deployed_cluster_has_the_rows_of_a_local_run(tmp_path, deployed):
    assert deployed.address.startswith("tcp://127.0.0.1:")
    config = write_config(tmp_path)
    done = sweep(tmp_path, config, tmp_path / "dask", "--scheduler", deployed.address)
    out, err = done.communicate(timeout=300)
    assert done.returncode == 0, out + err
    assert "Traceback" not in err and "9 run (0 failed)" in out, out + err
    # the local run in this process, from the same reference cache: the same computation as
    # `aaeval sweep --workers 1` without another interpreter's start
    local = run_sweep(load_experiment(config), tmp_path / "local", workers=1, quiet=True, cache_dir=tmp_path / "cache")
    assert local.ran == 9 and local.failed == 0
    a = pd.read_parquet(tmp_path / "dask" / "results.parquet").sort_values("key").reset_index(drop=True)
    b = pd.read_parquet(tmp_path / "local" / "results.parquet").sort_values("key").reset_index(drop=True)
    assert len(a) == 9 and list(a["key"]) == list(b["key"])
    assert a["error"].isna().all(), a["error"].tolist()
    assert a["executor"].str.startswith(f"Dask cluster {deployed.address}").all()
    for column in ("rmse", "psnr", "intensity_sum"):
        pd.testing.assert_series_equal(a[column], b[column])


def sweep_until_cells(tmp_path: Path, deployed: Deployed, at_least: int = 3,
                      answer_within: float = 5) -> tuple[subprocess.Popen, Path]:
    """A sweep of :data:`MANY` through the cluster, once ``at_least`` of its cells are written."""
    out = tmp_path / "out"
    running = sweep(tmp_path, write_config(tmp_path, MANY), out, "--scheduler", deployed.address,
                    answer_within=answer_within)
    if wait_for_cells(out, at_least, 240, running=lambda: running.poll() is None) < at_least:
        raise AssertionError(f"fewer than {at_least} cells in 240 s: {running.communicate()}")
    return running, out


def test_a_frozen_scheduler_ends_the_sweep_within_its_timeout(tmp_path, deployed):
    running, out = sweep_until_cells(tmp_path, deployed, answer_within=2)
    os.kill(deployed.scheduler.pid, signal.SIGSTOP)
    stopped = time.monotonic()
    stdout, err = running.communicate(timeout=120)
    took = time.monotonic() - stopped
    # AAEVAL_DASK_TIMEOUT=2: a call unanswered for 2 s ends it; the rest is writing the table
    assert took < 60, took
    assert running.returncode == 1, stdout + err
    assert err.count("\n") == 1 and "did not answer within 2 s" in err, err
    kept = len(list((out / "cells").glob("*.json")))
    assert 3 <= kept < 120
    assert len(pd.read_parquet(out / "results.parquet")) == kept


def test_a_killed_scheduler_is_said_in_one_line(tmp_path, deployed):
    running, out = sweep_until_cells(tmp_path, deployed)
    os.killpg(deployed.scheduler.pid, signal.SIGKILL)
    stdout, err = running.communicate(timeout=180)
    assert running.returncode == 1, stdout + err
    assert "Traceback" not in err and err.count("\n") == 1 and "was lost" in err, err
    kept = len(list((out / "cells").glob("*.json")))
    assert 3 <= kept < 120 and len(pd.read_parquet(out / "results.parquet")) == kept
