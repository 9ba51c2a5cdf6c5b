"""A sweep folder heals or says exactly what is wrong; one folder, one config, one writer."""

from __future__ import annotations

import contextlib
import io
import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from aaeval.cli import main
from aaeval.sweeps import SweepStore, load_experiment, run_sweep
from aaeval.sweeps.table import write_results
from aaeval.imageio import atomic_write
from tests.helpers.sweep_util import SMALL, write_config

OTHER = SMALL.replace('name = "small"', 'name = "other"').replace("difficulty = [3, 6, 12]", "difficulty = [4]")


def _sweep(tmp_path, text=SMALL, **kw):
    exp = load_experiment(write_config(tmp_path, text))
    return run_sweep(exp, tmp_path / "out", workers=1, quiet=True, cache_dir=tmp_path / "cache", **kw)


def _quarantined(out):
    q = out / "quarantine"
    return sorted(p.name for p in q.rglob("*") if p.is_file()) if q.is_dir() else []


def _one(folder):
    return sorted(p for p in folder.iterdir() if not p.name.startswith("."))[0]


@pytest.mark.parametrize("damage", ["empty cell", "truncated cell", "truncated image", "empty image",
                                    "truncated reference"])
@pytest.mark.slow
def test_a_damaged_file_is_named_set_aside_and_run_again(tmp_path, capsys, damage):
    _sweep(tmp_path)
    out = tmp_path / "out"
    folder = {"cell": "cells", "image": "images", "reference": "references"}[damage.split()[1]]
    victim = _one(out / folder)
    data = victim.read_bytes()
    damaged = b"" if damage.startswith("empty") else data[: len(data) // 2]
    victim.write_bytes(damaged)
    capsys.readouterr()
    again = _sweep(tmp_path)
    err = capsys.readouterr().err
    assert str(victim) in err  # named by path
    assert victim.name in _quarantined(out)  # set aside, not deleted
    assert next((out / "quarantine").rglob(victim.name)).read_bytes() == damaged
    assert again.ran >= 1 and not again.lost
    store = SweepStore(out)
    assert len(store.finished()) == 9
    assert len(pd.read_parquet(out / "results.parquet")) == 9
    # the rebuilt files are sound again
    for key in store.finished():
        assert store.read_cell(key)["key"] == key


def test_report_tables_heal_a_damaged_cell_instead_of_failing(tmp_path, capsys):
    _sweep(tmp_path)
    out = tmp_path / "out"
    victim = _one(out / "cells")
    victim.write_text("")
    results = write_results(SweepStore(out))
    assert len(results) == 8  # the damaged cell is pending, not an error for the whole folder
    assert str(victim) in capsys.readouterr().err
    assert victim.name in _quarantined(out)


def test_dry_run_counts_only_sound_cells_and_moves_nothing(tmp_path, capsys):
    config = write_config(tmp_path)
    _sweep(tmp_path)
    out = tmp_path / "out"
    victim = _one(out / "cells")
    victim.write_text("{")
    capsys.readouterr()
    assert main(["sweep", str(config), "--out", str(out), "--dry-run"]) == 0
    captured = capsys.readouterr()
    assert "8 done" in captured.out
    assert str(victim) in captured.err
    assert victim.exists() and not _quarantined(out)


def test_atomic_write_follows_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        path = atomic_write(tmp_path / "a.txt", lambda tmp: open(tmp, "w").write("x"))
        assert stat.S_IMODE(path.stat().st_mode) == 0o644
        os.umask(0o077)
        path = atomic_write(tmp_path / "b.txt", lambda tmp: open(tmp, "w").write("x"))
        assert stat.S_IMODE(path.stat().st_mode) == 0o600
    finally:
        os.umask(old)


@pytest.mark.durability
def test_atomic_write_syncs_the_file_and_its_folder_before_the_rename(tmp_path, monkeypatch):
    # os.fsync is the real one, only watched: which descriptors it saw, and before what
    events = []
    real_fsync, real_replace = os.fsync, os.replace

    def fsync(fd):
        events.append(("fsync", stat.S_ISDIR(os.fstat(fd).st_mode)))
        return real_fsync(fd)

    def replace(a, b):
        events.append(("replace", None))
        return real_replace(a, b)

    monkeypatch.setattr(os, "fsync", fsync)
    monkeypatch.setattr(os, "replace", replace)
    atomic_write(tmp_path / "c.txt", lambda tmp: open(tmp, "w").write("x"))
    assert events.index(("fsync", False)) < events.index(("replace", None)) < events.index(("fsync", True))


def test_a_second_sweep_into_a_locked_folder_is_refused(tmp_path, capsys):
    config = write_config(tmp_path)
    out = tmp_path / "out"
    with SweepStore(out).lock():
        assert main(["sweep", str(config), "--out", str(out), "--workers", "1", "-q"]) == 2
        err = capsys.readouterr().err
        assert f"pid {os.getpid()}" in err and "in use" in err and err.count("\n") == 1
        assert not (out / "manifest.json").exists()
    assert main(["sweep", str(config), "--out", str(out), "--workers", "1", "-q",
                 "--cache", str(tmp_path / "cache")]) == 0


def test_a_stale_lock_is_detected_and_taken_over(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    (out / "sweep.lock").write_text(json.dumps({"pid": dead.pid, "host": os.uname().nodename}))
    summary = _sweep(tmp_path)
    assert summary.ran == 9
    assert f"stale lock" in capsys.readouterr().err
    assert not json.loads((out / "sweep.lock").read_text() or "{}").get("pid")  # released


def test_another_config_is_refused_and_nothing_is_replaced(tmp_path, capsys):
    _sweep(tmp_path)
    out = tmp_path / "out"
    before = {n: (out / n).read_bytes() for n in ("manifest.json", "experiment.toml", "results.parquet")}
    other = write_config(tmp_path, OTHER, name="other.toml")
    capsys.readouterr()
    assert main(["sweep", str(other), "--out", str(out), "--workers", "1", "-q"]) == 2
    err = capsys.readouterr().err
    assert "'small'" in err and "'other'" in err and "--force" in err and err.count("\n") == 1
    assert {n: (out / n).read_bytes() for n in before} == before


@pytest.mark.slow
def test_force_keeps_the_old_config_and_says_which_rows_leave_the_table(tmp_path, capsys):
    _sweep(tmp_path)
    out = tmp_path / "out"
    old_manifest = (out / "manifest.json").read_bytes()
    other = write_config(tmp_path, OTHER, name="other.toml")
    capsys.readouterr()
    assert main(["sweep", str(other), "--out", str(out), "--workers", "1", "-q", "--force",
                 "--cache", str(tmp_path / "cache")]) == 0
    text = capsys.readouterr()
    kept = list((out / "history").rglob("manifest.json"))
    assert len(kept) == 1 and kept[0].read_bytes() == old_manifest
    assert "3 finished cells" in text.err and "not in this config" in text.err


@pytest.mark.slow
def test_a_smaller_config_of_the_same_experiment_says_which_rows_leave_the_table(tmp_path, capsys):
    _sweep(tmp_path)
    capsys.readouterr()
    smaller = SMALL.replace("difficulty = [3, 6, 12]", "difficulty = [3]")
    summary = _sweep(tmp_path, smaller)
    assert summary.ran == 0
    assert "2 finished cells" in capsys.readouterr().err
    assert len(list((tmp_path / "out" / "cells").glob("*.json"))) == 9  # their files stay


def test_editing_what_only_draws_or_aggregates_keeps_the_cells(tmp_path, monkeypatch):
    """A cell's key holds the code version: a hash of the package source that computes
    results. The report and the summaries of the stored tables compute none, so editing
    them keeps every finished cell; editing what measures does not."""
    import shutil

    import aaeval
    from aaeval.sweeps import cache_keys

    copy = tmp_path / "aaeval"
    shutil.copytree(Path(aaeval.__file__).parent, copy, ignore=shutil.ignore_patterns("__pycache__", "*.so"))
    monkeypatch.setattr(aaeval, "__file__", str(copy / "__init__.py"))
    before = cache_keys._package_digest()
    for rel in ("sweeps/summaries.py", "sweeps/aggregate.py", "report/html.py"):
        (copy / rel).write_text((copy / rel).read_text() + "\n# edited\n")
    assert cache_keys._package_digest() == before
    (copy / "sweeps/table.py").write_text((copy / "sweeps/table.py").read_text() + "\n# edited\n")
    assert cache_keys._package_digest() != before
