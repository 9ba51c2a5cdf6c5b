"""Small experiment configs for the sweep and report tests (generated scenes: no files)."""

from __future__ import annotations

import time
from pathlib import Path

SMALL = """
[experiment]
name = "small"
description = "test sweep"
reference = "catmull"
metrics = ["rmse", "psnr"]
temporal = ["sum_variation", "flicker"]
fail_above = 0.1

[[groups]]
name = "edges"
scenes = [{generator = "edges", difficulty = [0.1], frames = 3, size = 12}]
methods = ["catmull", "catmull-jagged"]

[[groups]]
name = "stability"
scenes = [{generator = "fan", difficulty = [3, 6, 12], size = 5}]
methods = ["catmull-jagged"]
"""


def slow_config(name: str, frames: int) -> str:
    """One group of ``frames`` cells of the method "test-slow" (``tests/helpers/slow_sweep.py``)."""
    return f"""
[experiment]
name = "{name}"
reference = "catmull"
metrics = ["rmse"]

[[groups]]
name = "slow"
scenes = [{{generator = "edges", difficulty = [0.1], frames = {frames}, size = 8}}]
methods = ["test-slow"]
"""


def slow_sweep(config: Path, out: Path, cache: Path, *, workers: int, pause: float, **popen):
    """``tests/helpers/slow_sweep.py`` in a process (and session) of its own."""
    import os
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[2]
    env = {**os.environ, "PYTHONPATH": str(root), "SLOW_SWEEP_PAUSE": str(pause)}
    return subprocess.Popen([sys.executable, str(root / "tests" / "helpers" / "slow_sweep.py"), str(config),
                             str(out), str(cache), str(workers)], env=env, start_new_session=True, **popen)


def strict_json(text: str):
    """``text`` read as strict JSON: a bare NaN or Infinity is refused, not read as a float."""
    import json

    def refuse(constant):
        raise ValueError(f"not JSON: {constant}")

    return json.loads(text, parse_constant=refuse)


def write_config(tmp_path: Path, text: str = SMALL, name: str = "exp.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def run_small_sweep(tmp_path: Path, text: str = SMALL, **kw):
    """Run the config ``text`` (one worker, quietly) into ``tmp_path/out``; its summary."""
    from aaeval.sweeps import load_experiment, run_sweep

    exp = load_experiment(write_config(tmp_path, text))
    return run_sweep(exp, tmp_path / "out", workers=1, quiet=True, cache_dir=tmp_path / "cache", **kw)


def quarantined(out: Path) -> list[str]:
    """Names of the files the sweep folder ``out`` has set aside."""
    q = out / "quarantine"
    return sorted(p.name for p in q.rglob("*") if p.is_file()) if q.is_dir() else []


def first_file(folder: Path) -> Path:
    """The first file of ``folder`` by name, hidden files left out."""
    return sorted(p for p in folder.iterdir() if not p.name.startswith("."))[0]


# A 14x10 scene that moves over four frames, swept with two methods against catmull
MOVING = (Path(__file__).resolve().parents[1] / "data" / "scenes" / "two_triangles_14x10.toml").read_text()


def moving_config(tmp_path: Path, metrics='["rmse", "ssim", "edge_rmse"]', temporal='["sum_variation", "flicker"]',
                  repeats=1) -> Path:
    """``tmp_path/moving.toml`` (:data:`MOVING`) and a config sweeping it; the config's path."""
    (tmp_path / "moving.toml").write_text(MOVING)
    return write_config(tmp_path, f"""
[experiment]
name = "moving"
reference = "catmull"
metrics = {metrics}
temporal = {temporal}

[[groups]]
name = "moving"
scenes = ["moving.toml"]
methods = ["catmull-jagged", "supersample:k=3"]
repeats = {repeats}
""")


def run_moving_sweep(tmp_path: Path) -> Path:
    """The moving config swept (three timed repeats a cell) into ``tmp_path/out``; ``tmp_path``."""
    from aaeval.sweeps import load_experiment, run_sweep

    exp = load_experiment(moving_config(tmp_path, repeats=3))
    run_sweep(exp, tmp_path / "out", workers=1, quiet=True, cache_dir=tmp_path / "cache")
    return tmp_path


# 120 cells of about a tenth of a second: enough to stop a scheduler or a worker mid-sweep.
MANY = """
[experiment]
name = "many"
description = "enough cells to stop the scheduler in the middle"
reference = "supersample:k=2"
metrics = ["rmse"]
temporal = []

[[groups]]
name = "edges"
scenes = [{generator = "edges", difficulty = [0.1], frames = 60, size = 24}]
methods = ["point", "supersample:k=3"]
"""


def wait_for_cells(out: Path, at_least: int, limit: float = 300, running=lambda: True) -> int:
    """Wait until the sweep folder ``out`` holds ``at_least`` cell records (while
    ``running()``, at most ``limit`` seconds); the count, which may be short when it gave up."""
    deadline = time.monotonic() + limit
    n = 0
    while time.monotonic() < deadline and running():
        cells = out / "cells"
        n = len(list(cells.glob("*.json"))) if cells.is_dir() else 0
        if n >= at_least:
            break
        time.sleep(0.02)
    return n


def still_running(procs, timeout: float) -> list:
    """Those of ``procs`` (psutil processes) still running after up to ``timeout`` seconds.

    A process that exited is ended even while it is a zombie: an orphan is reaped by the
    system's init, which in some containers gets to it a second or more later (a wait on
    its pid, as ``psutil.wait_procs`` does, waits that long), and a zombie computes nothing.
    """
    import psutil

    def running(p) -> bool:
        try:
            return p.is_running() and p.status() != psutil.STATUS_ZOMBIE
        except psutil.NoSuchProcess:
            return False

    deadline = time.monotonic() + timeout
    alive = list(procs)
    while True:
        alive = [p for p in alive if running(p)]
        if not alive or time.monotonic() >= deadline:
            return alive
        time.sleep(0.02)
