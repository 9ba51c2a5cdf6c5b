"""``kill PID`` of a running sweep: its workers end with it, finished cells stay, the exit
code says interrupted. A real sweep in a subprocess with real worker processes."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import psutil
import pytest

from aaeval.sweeps import SweepStore

ROOT = Path(__file__).resolve().parents[2]

# a script file, not "python -c": spawned workers re-import it and so know "test-slow"
SLOW_SWEEP = """
import sys, time
from aaeval.renderers import register_method, render

@register_method("test-slow", summary="catmull after a pause, so a sweep can be killed mid-way")
def slow(scene):
    time.sleep(0.4)
    return render(scene, "catmull")

if __name__ == "__main__":
    from aaeval.cli import main
    sys.exit(main(["sweep", sys.argv[1], "--out", sys.argv[2], "--workers", "2", "--quiet", "--cache", sys.argv[3]]))
"""

CONFIG = """
[experiment]
name = "signals"
reference = "catmull"
metrics = ["rmse"]

[[groups]]
name = "slow"
scenes = [{generator = "edges", difficulty = [0.1], frames = 40, size = 8}]
methods = ["test-slow"]
"""


@pytest.mark.slow
@pytest.mark.parametrize("signum, code", [(signal.SIGTERM, 143), (signal.SIGHUP, 129)])
def test_kill_ends_the_workers_keeps_finished_cells_and_says_interrupted(tmp_path, signum, code):
    script, config, out = tmp_path / "sweep.py", tmp_path / "exp.toml", tmp_path / "out"
    script.write_text(SLOW_SWEEP)
    config.write_text(CONFIG)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, str(script), str(config), str(out), str(tmp_path / "cache")],
                            cwd=tmp_path, env=env, start_new_session=True, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    family: list[psutil.Process] = []
    try:
        deadline = time.monotonic() + 90
        while not (out / "cells").is_dir() or len(list((out / "cells").glob("[!.]*.json"))) < 2:
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "no cells finished in 90 s"
            time.sleep(0.05)
        family = psutil.Process(proc.pid).children(recursive=True)
        assert len(family) >= 2  # the two workers (and the resource tracker)
        os.kill(proc.pid, signum)  # the parent alone, as `kill PID` does
        _, err = proc.communicate(timeout=60)
        assert proc.returncode == code, err.decode()
        lines = err.decode().strip().splitlines()
        assert lines == [f"aaeval sweep: interrupted ({signal.Signals(signum).name})"], lines
        _, alive = psutil.wait_procs(family, timeout=10)
        assert not alive, f"orphaned: {[(p.pid, p.cmdline()[:3]) for p in alive]}"
        store = SweepStore(out)
        done = store.finished()
        assert 2 <= len(done) < 40 and all(store.read_cell(k)["error"] is None for k in done)
        with store.lock():  # released
            pass
    finally:
        for p in [psutil.Process(proc.pid)] + family if proc.poll() is None else family:
            try:
                p.kill()
            except psutil.NoSuchProcess:
                pass
