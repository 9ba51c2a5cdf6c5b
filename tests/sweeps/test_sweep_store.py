"""A sweep folder heals or says exactly what is wrong; one folder, one config, one writer."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from aaeval.cli import main
from aaeval.sweeps import SweepStore
from tests.helpers.sweep_util import SMALL, first_file, quarantined, run_small_sweep, write_config

OTHER = SMALL.replace('name = "small"', 'name = "other"').replace("difficulty = [3, 6, 12]", "difficulty = [4]")


@pytest.mark.parametrize("damage", ["empty cell", "truncated cell", "truncated image", "empty image",
                                    "truncated reference"])
@pytest.mark.slow
def test_a_damaged_file_is_named_set_aside_and_run_again(tmp_path, capsys, damage):
    run_small_sweep(tmp_path)
    out = tmp_path / "out"
    folder = {"cell": "cells", "image": "images", "reference": "references"}[damage.split()[1]]
    victim = first_file(out / folder)
    data = victim.read_bytes()
    damaged = b"" if damage.startswith("empty") else data[: len(data) // 2]
    victim.write_bytes(damaged)
    capsys.readouterr()
    again = run_small_sweep(tmp_path)
    err = capsys.readouterr().err
    assert str(victim) in err  # named by path
    assert victim.name in quarantined(out)  # set aside, not deleted
    assert next((out / "quarantine").rglob(victim.name)).read_bytes() == damaged
    assert again.ran >= 1 and not again.lost
    store = SweepStore(out)
    assert len(store.finished()) == 9
    assert len(pd.read_parquet(out / "results.parquet")) == 9
    # the rebuilt files are sound again
    for key in store.finished():
        assert store.read_cell(key)["key"] == key


def test_dry_run_counts_only_sound_cells_and_moves_nothing(tmp_path, capsys):
    config = write_config(tmp_path)
    run_small_sweep(tmp_path)
    out = tmp_path / "out"
    victim = first_file(out / "cells")
    victim.write_text("{")
    capsys.readouterr()
    assert main(["sweep", str(config), "--out", str(out), "--dry-run"]) == 0
    captured = capsys.readouterr()
    assert "8 done" in captured.out
    assert str(victim) in captured.err
    assert victim.exists() and not quarantined(out)


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
    summary = run_small_sweep(tmp_path)
    assert summary.ran == 9
    assert "stale lock" in capsys.readouterr().err
    assert not json.loads((out / "sweep.lock").read_text() or "{}").get("pid")  # released


def test_another_config_is_refused_and_nothing_is_replaced(tmp_path, capsys):
    run_small_sweep(tmp_path)
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
    run_small_sweep(tmp_path)
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
    run_small_sweep(tmp_path)
    capsys.readouterr()
    smaller = SMALL.replace("difficulty = [3, 6, 12]", "difficulty = [3]")
    summary = run_small_sweep(tmp_path, smaller)
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
