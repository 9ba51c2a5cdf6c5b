"""``kill -9`` of a running sweep at random moments, again and again, then a run to the end:
the store's promises under batched writes. Every file on disk after a kill is whole (no
cell set aside as damaged), no finished cell on disk is lost by a later kill, a rerun runs
exactly the cells not on disk (none twice), and the final table has every cell once, with
the numbers of a sweep never killed. A real sweep in a subprocess with real workers and the
real ``fsync``/``syncfs`` (tests/conftest.py changes only this process).

Its metrics write a record and a FLIP map per cell, as a default sweep does; CIEDE2000 is
left out because its import (colour-science, about 1.4 s of CPU in each of the test's dozen
worker processes) is most of a worker's cost and adds nothing to what is checked here: a
metric that gives the same bits in any chunk is the same bits after a kill
(tests/metrics/test_metrics.py checks CIEDE2000 in bulk against one call per pair)."""

from __future__ import annotations

import os
import random
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import psutil
import pytest

from aaeval.sweeps import SweepStore
from tests.helpers.sweep_util import still_running

ROOT = Path(__file__).resolve().parents[2]

CONFIG = """
[experiment]
name = "kill"
reference = "catmull"
metrics = ["rmse", "flip"]

[[groups]]
name = "killed"
scenes = [{generator = "edges", difficulty = [0.1], frames = 150, size = 12}]
methods = ["point", "supersample:k=2"]
"""

CELLS = 300
IDENTITY = ["group", "scene", "difficulty", "spec", "frame"]


def _start(tmp_path: Path, out: Path) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.Popen([sys.executable, "-m", "aaeval", "sweep", str(tmp_path / "exp.toml"), "--out", str(out),
                             "--workers", "2", "--quiet", "--cache", str(tmp_path / "cache")],
                            cwd=tmp_path, env=env, start_new_session=True, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def _kill_at(proc: subprocess.Popen, seconds: float) -> bool:
    """SIGKILL the sweep (itself, as a crash would) after ``seconds``; False if it ended first.
    Its workers watch it and must exit by themselves."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            return False
        time.sleep(0.02)
    family = psutil.Process(proc.pid).children(recursive=True)
    os.kill(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=30)
    alive = still_running(family, timeout=15)
    assert not alive, f"orphaned: {[(p.pid, p.cmdline()[:3]) for p in alive]}"
    return True


def _sound(out: Path) -> dict[str, dict]:
    """The finished cells on disk; fails on any file the store would set aside as damaged."""
    problems: list[str] = []
    sound = SweepStore(out, log=problems.append).check(heal=False)
    assert problems == [], problems
    return sound


def _table(out: Path) -> pd.DataFrame:
    table = pd.read_parquet(out / "results.parquet")
    assert not table.duplicated(IDENTITY).any()
    return table.set_index(IDENTITY).sort_index()


@pytest.mark.slow
def test_kill_9_at_random_moments_loses_nothing_written_and_doubles_nothing(tmp_path):
    (tmp_path / "exp.toml").write_text(CONFIG)
    whole = tmp_path / "whole"
    done = _start(tmp_path, whole)
    started = time.monotonic()
    _, err = done.communicate(timeout=300)
    assert done.returncode == 0, err
    seconds = time.monotonic() - started

    out, rng = tmp_path / "killed", random.Random(46)
    kept: dict[str, dict] = {}
    kills = 0
    for _ in range(4):
        # within the first 60% of a whole sweep's time: a rerun finds its references cached and
        # runs faster, and a kill drawn near the end would come after it (nothing then killed)
        killed = _kill_at(_start(tmp_path, out), max(0.3, rng.uniform(0.1, 0.6) * seconds))
        kills += killed
        now = _sound(out)
        assert set(kept) <= set(now), "a finished cell on disk was lost by a later kill"
        assert all(now[k] == kept[k] for k in kept), "a finished cell was written again"
        kept = now
        if not killed:
            break
    assert kills >= 1, "every sweep ended before its kill"
    final = _start(tmp_path, out)
    stdout, err = final.communicate(timeout=300)
    assert final.returncode == 0, err
    counts = re.search(r"(\d+) cells, (\d+) already done, (\d+) run", stdout)
    assert counts, stdout
    assert (int(counts[1]), int(counts[2]), int(counts[3])) == (CELLS, len(kept), CELLS - len(kept))
    assert len(_sound(out)) == CELLS

    table, reference = _table(out), _table(whole)
    assert len(table) == CELLS and table.index.equals(reference.index)
    for metric in ("rmse", "flip", "intensity_sum"):
        pd.testing.assert_series_equal(table[metric], reference[metric], check_exact=False, rtol=1e-12)
