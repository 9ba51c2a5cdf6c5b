"""``kill PID`` of a running sweep: its workers end with it, finished cells stay, the exit
code says interrupted. A real sweep in a subprocess with real worker processes."""

from __future__ import annotations

import os
import signal
import subprocess
import time

import psutil
import pytest

from aaeval.sweeps import SweepStore
from tests.helpers.sweep_util import slow_config, slow_sweep, still_running, write_config


@pytest.mark.slow
@pytest.mark.parametrize("signum, code", [(signal.SIGTERM, 143), (signal.SIGHUP, 129)])
def test_kill_ends_the_workers_keeps_finished_cells_and_says_interrupted(tmp_path, signum, code):
    config, out = write_config(tmp_path, slow_config("signals", 40)), tmp_path / "out"
    proc = slow_sweep(config, out, tmp_path / "cache", workers=2, pause=0.2, cwd=tmp_path, stdout=subprocess.PIPE,
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
        alive = still_running(family, timeout=10)
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
