"""Workers that die and cells past the time limit: a plugin method that sleeps, calls
``os._exit``, or kills itself with a signal takes only its own cells down. Each such cell is
recorded as failed with the reason ("timed out: ...", "worker died: exit N / signal N"), the
worker is replaced, every other cell is done, and a plain rerun tries those cells again.

The plugins are "installed" as in tests/plugins/test_plugins.py (a dist-info folder on PYTHONPATH),
and aaeval runs in subprocesses, as a user's sweep would.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.helpers.plugin_util import fake_install

ROOT = Path(__file__).resolve().parents[2]

PLUGIN = '''
import os
import signal
import time

import numpy as np
from aaeval.renderers import register_method


@register_method("sleepy", summary="test plugin: sleeps for five minutes")
def render_sleepy(scene):
    time.sleep(300)
    return np.zeros(scene.shape)


@register_method("exits", summary="test plugin: ends its process with os._exit(3)")
def render_exits(scene):
    os._exit(3)


@register_method("segv", summary="test plugin: kills its process with SIGSEGV")
def render_segv(scene):
    os.kill(os.getpid(), signal.SIGSEGV)
    time.sleep(5)


@register_method("huge", summary="test plugin: -1e300 everywhere (an infinite RMSE)")
def render_huge(scene):
    return np.full(scene.shape, -1e300)


@register_method("objects", summary="test plugin: an object array")
def render_objects(scene):
    return np.full(scene.shape, None, dtype=object)


@register_method("flaky", summary="test plugin: dies unless FLAKY_OK is set")
def render_flaky(scene):
    if not os.environ.get("FLAKY_OK"):
        os._exit(9)
    return np.full(scene.shape, 0.5)
'''

METRIC = '''
from aaeval.metrics.registry import register_metric

register_metric("infinite", lambda reference, image: float("inf"), kind="image", title="always inf", fmt=".3g")
'''

CONFIG = """
[experiment]
name = "death"
reference = "catmull"
metrics = {metrics}
temporal = []
fail_above = 0.5

[[groups]]
name = "edges"
scenes = [{{generator = "edges", difficulty = [0.1], frames = {frames}, size = 8}}]
methods = {methods}
"""


@pytest.fixture
def site(tmp_path) -> Path:
    site = tmp_path / "site"
    site.mkdir()
    (site / "aaeval_death_plugin.py").write_text(PLUGIN)
    fake_install(site, "aaeval-death-plugin", {
        "aaeval.methods": {name: "aaeval_death_plugin" for name in ("sleepy", "exits", "segv", "flaky", "huge",
                                                                    "objects")},
        "aaeval.metrics": {"infinite": "aaeval_death_metric"}})
    (site / "aaeval_death_metric.py").write_text(METRIC)
    return site


def sweep(site: Path, tmp_path: Path, methods: list[str], *, frames: int = 1, workers: int = 2, metrics=("rmse",),
          env: dict | None = None, timeout: float = 300, more: str = "") -> tuple[subprocess.CompletedProcess, float, Path]:
    """The config of ``methods`` (``more``: further groups) swept in a process of its own."""
    config = tmp_path / "death.toml"
    config.write_text(CONFIG.format(frames=frames, methods=json.dumps(methods), metrics=json.dumps(list(metrics))) + more)
    out = tmp_path / "out"
    full = {**os.environ, **(env or {}),
            "PYTHONPATH": os.pathsep.join([str(site), str(ROOT), os.environ.get("PYTHONPATH", "")])}
    start = time.monotonic()
    done = subprocess.run([sys.executable, "-m", "aaeval", "sweep", str(config), "--out", str(out), "--workers",
                           str(workers), "--quiet"], env=full, capture_output=True, text=True, timeout=timeout)
    return done, time.monotonic() - start, out


def cells(out: Path, group: str = "edges") -> dict[tuple[str, int], dict]:
    records = [json.loads(p.read_text()) for p in (out / "cells").glob("*.json")]
    return {(r["spec"], r["frame"]): r for r in records if r["group"] == group}


@pytest.mark.slow
def test_a_cell_past_the_time_limit_is_stopped_and_the_sweep_goes_on(site, tmp_path):
    """A cell past its time limit (a user would set AAEVAL_MAX_SECONDS=15; 1 here, the same path in less
    time: a worker's start does not count, and a point cell takes milliseconds): a method that
    sleeps 300 s: the sweep ends well before, that cell is recorded as failed, the other
    method's cell is done."""
    done, seconds, out = sweep(site, tmp_path, ["sleepy", "point"], env={"AAEVAL_MAX_SECONDS": "1"}, timeout=200)
    assert seconds < 100, seconds
    assert "Traceback" not in done.stderr + done.stdout, done.stderr
    assert done.returncode == 3, done.stderr + done.stdout  # cells failed
    assert "1 x timed out: stopped after 1 s" in done.stderr, done.stderr
    found = cells(out)
    assert found[("sleepy", 0)]["error"].startswith("timed out: stopped after 1 s"), found[("sleepy", 0)]
    assert found[("point", 0)]["error"] is None
    assert "(1 failed)" in done.stdout, done.stdout


@pytest.mark.slow
def test_a_method_that_calls_os_exit_fails_its_cells_only(site, tmp_path):
    """os._exit in a 2-worker sweep: no traceback, every other cell
    done; the cells that killed a worker say how it died. Two frames a method: each death
    kind twice (counted once in the summary), a worker replaced after each."""
    done, _, out = sweep(site, tmp_path, ["exits", "segv", "point"], frames=2)
    assert "Traceback" not in done.stderr + done.stdout, done.stderr
    assert done.returncode == 3, done.stderr + done.stdout  # cells failed
    assert "2 x worker died: exit 3" in done.stderr and "2 x worker died: signal 11" in done.stderr, done.stderr
    found = cells(out)
    assert len(found) == 6
    for frame in range(2):
        assert found[("point", frame)]["error"] is None
        assert found[("exits", frame)]["error"] == "worker died: exit 3"
        assert found[("segv", frame)]["error"] == "worker died: signal 11 (SIGSEGV)"
    assert "(4 failed)" in done.stdout, done.stdout


@pytest.mark.slow
def test_a_rerun_retries_the_cells_whose_worker_died(site, tmp_path):
    # one frame: the cell whose worker died is retried and the done one is not, as with more
    first, _, out = sweep(site, tmp_path, ["flaky", "point"])
    assert first.returncode == 3 and "(1 failed)" in first.stdout, first.stdout + first.stderr
    again, _, out = sweep(site, tmp_path, ["flaky", "point"], env={"FLAKY_OK": "1"})
    assert again.returncode == 0, again.stderr
    assert "2 cells, 1 already done, 1 run (0 failed)" in again.stdout, again.stdout
    assert all(r["error"] is None for r in cells(out).values())


# The same scene and a plain method measured with the plugin metric that answers inf
INFINITE_GROUP = """
[[groups]]
name = "infinite"
scenes = [{generator = "edges", difficulty = [0.1], frames = 1, size = 8}]
methods = ["point"]
metrics = ["rmse", "infinite"]
"""


@pytest.mark.slow
def test_images_and_metrics_that_cannot_be_measured_fail_their_cells(site, tmp_path):
    """-1e300 (an infinite RMSE: no threshold could judge it) and an object array (write_cell raised in the parent) fail
    their cells; a metric that answers inf fails the cell too (a group of its own, in the same sweep). The report counts
    them."""
    done, _, out = sweep(site, tmp_path, ["huge", "objects", "point"], workers=1, more=INFINITE_GROUP)
    assert done.returncode == 3 and "Traceback" not in done.stderr, done.stderr
    assert "(3 failed)" in done.stdout, done.stdout
    found = cells(out)
    assert found[("point", 0)]["error"] is None
    assert "huge" in found[("huge", 0)]["error"] and "objects" in found[("objects", 0)]["error"]
    record = cells(out, "infinite")[("point", 0)]
    assert "infinite=inf" in record["error"]


# A plugin that takes its time to load, in sweep workers only (spawned: they have a parent)
SLOW_START = """
import multiprocessing
import time

if multiprocessing.parent_process() is not None:
    time.sleep(1.0)
"""


@pytest.mark.slow
def test_a_task_s_clock_starts_when_its_worker_has_started(tmp_path, monkeypatch):
    """A worker whose start (importing aaeval, loading the registries and a slow plugin) takes
    longer than the time limit still runs its first task: the limit is the task's time, not
    the worker's start. A task past the limit is still stopped."""
    from aaeval import registries
    from aaeval.sweeps.local_workers import ProcessExecutor
    from aaeval.sweeps.task_failures import TaskTimedOut

    registries.load()  # this process's registries as they are: the slow plugin is for the worker
    (tmp_path / "aaeval_slow_start.py").write_text(SLOW_START)
    fake_install(tmp_path, "aaeval-slow-start", {"aaeval.metrics": {"slow-start": "aaeval_slow_start"}})
    monkeypatch.syspath_prepend(str(tmp_path))  # a spawned worker starts with this process's sys.path
    executor = ProcessExecutor(1, max_seconds=0.5)
    try:
        out = list(executor.run(time.sleep, [(0,), (30,)]))
    finally:
        executor.close()
    assert out[0] == (0, None, None)
    assert out[1][0] == 1 and isinstance(out[1][2], TaskTimedOut), out


@pytest.mark.slow
def test_a_worker_that_never_finishes_starting_ends_the_run_instead_of_hanging(tmp_path, monkeypatch):
    """A task's clock waits for its worker's start, so a start that hangs has its own limit
    (here 0.5 s against a 1 s plugin load): every task comes back as WorkersCannotStart
    naming it, and the run ends."""
    from aaeval import registries
    from aaeval.sweeps import local_workers
    from aaeval.sweeps.task_failures import WorkersCannotStart

    registries.load()
    (tmp_path / "aaeval_slow_start.py").write_text(SLOW_START)
    fake_install(tmp_path, "aaeval-slow-start", {"aaeval.metrics": {"slow-start": "aaeval_slow_start"}})
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(local_workers, "START_SECONDS", 0.5)
    executor = local_workers.ProcessExecutor(1, max_seconds=30)
    start = time.monotonic()
    try:
        out = list(executor.run(time.sleep, [(0,), (0,)]))
    finally:
        executor.close()
    assert time.monotonic() - start < 10
    assert sorted(i for i, _, _ in out) == [0, 1]
    assert all(isinstance(exc, WorkersCannotStart) and "did not start within 0.5 s" in str(exc) for _, _, exc in out)


def test_the_serial_executor_stops_a_cell_past_its_limit():
    """--workers 1 runs in this process: its limit is a SIGALRM that stops Python code."""
    from aaeval.sweeps.local_workers import SerialExecutor
    from aaeval.sweeps.task_failures import TaskTimedOut

    def slow(seconds):
        try:
            time.sleep(seconds)
        except Exception:  # noqa: BLE001 - a method's own handler must not swallow the limit
            return "swallowed"
        return "slept"

    start = time.monotonic()
    out = list(SerialExecutor(max_seconds=0.5).run(slow, [(30,), (0,)]))
    assert time.monotonic() - start < 10
    assert isinstance(out[0][2], TaskTimedOut) and out[0][1] is None
    assert out[1] == (1, "slept", None)


def test_max_seconds_is_a_config_key():
    from aaeval.sweeps.config import parse_experiment
    from aaeval.sweeps.config_keys import ConfigError

    def parsed(value):
        return parse_experiment({"experiment": {"name": "t", "reference": "catmull", "max_seconds": value},
                                 "groups": [{"name": "g", "methods": ["point"],
                                             "scenes": [{"generator": "edges", "difficulty": [0.1], "size": 8}]}]})

    assert parsed(30).max_seconds == 30.0
    for bad in (0, -1, float("nan"), float("inf"), True, "60", 1e9):
        with pytest.raises(ConfigError, match="max_seconds"):
            parsed(bad)
