"""A sweep never reads, writes, truncates or moves anything outside its folder: a link (or a FIFO) is planted in place of each file and folder the store writes or
moves, and the files outside the folder are compared before and after. Also: a record with
an unknown field is damaged like any other (case 9), and the report leaves the tables of
a running sweep alone (case 13)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time

import pandas as pd
import pytest

from aaeval.cli import main
from aaeval.sweeps import SweepStore
from aaeval.sweeps.report_files import rebuild_results
from aaeval.sweeps.table import write_results
from tests.helpers.links_util import TINY, snapshot, sweep

@pytest.mark.slow
@pytest.mark.parametrize("name", ["sweep.lock", "quarantine", "history", "cells", "images", "references"])
def test_a_linked_lock_or_folder_is_refused_and_nothing_outside_changes(world, capsys, name):
    tmp_path, outside, config = world
    out = tmp_path / "out"
    if name in ("quarantine", "history"):  # only written on a second run
        assert sweep(tmp_path, config) == 0
    else:
        out.mkdir()
    target = outside / ("victim.txt" if name == "sweep.lock" else "dir")
    os.symlink(target, out / name)
    if name == "quarantine":  # a damaged cell to set aside
        cell = sorted((out / "cells").iterdir())[0]
        cell.write_text("{broken")
    if name == "history":  # another config of the same experiment moves the old one to history/
        config.write_text(TINY.replace('description = "link test sweep"', 'description = "changed"'))
    before = snapshot(outside)
    capsys.readouterr()
    code = sweep(tmp_path, config)
    err = capsys.readouterr().err
    assert snapshot(outside) == before, err
    assert (outside / "victim.txt").read_text() == "KEEP\n"
    assert code == 2 and str(out / name) in err and "symbolic link" in err and err.count("\n") == 1, err


def test_a_fifo_lock_is_refused_without_blocking(world, capsys):
    tmp_path, outside, config = world
    (tmp_path / "out").mkdir()
    os.mkfifo(tmp_path / "out" / "sweep.lock")
    assert sweep(tmp_path, config) == 2
    assert "sweep.lock is not a regular file" in capsys.readouterr().err


@pytest.mark.slow
@pytest.mark.parametrize("folder", ["cells", "images", "references"])
@pytest.mark.parametrize("kind", ["link", "fifo"])
def test_a_linked_cell_file_is_set_aside_as_a_link_and_its_target_untouched(world, capsys, folder, kind):
    tmp_path, outside, config = world
    out = tmp_path / "out"
    assert sweep(tmp_path, config) == 0
    victim_file = sorted((out / folder).iterdir())[0]
    victim_file.unlink()
    if kind == "link":
        os.symlink(outside / "victim.txt", victim_file)
    else:
        os.mkfifo(victim_file)  # reading it would block forever
    before = snapshot(outside)
    capsys.readouterr()
    assert sweep(tmp_path, config) == 0
    err = capsys.readouterr().err
    assert str(victim_file) in err
    assert snapshot(outside) == before
    # set aside (the link or FIFO itself), rebuilt as a regular file, every row back
    moved = [p for p in (out / "quarantine").rglob(victim_file.name)]
    assert moved and (os.path.islink(moved[0]) if kind == "link" else not moved[0].is_file())
    assert victim_file.is_file() and not victim_file.is_symlink()
    assert len(pd.read_parquet(out / "results.parquet")) == 2


@pytest.mark.parametrize("name", ["experiment.toml", "manifest.json", "results.parquet", "temporal.parquet",
                                  "provenance.json"])
@pytest.mark.slow
def test_a_linked_top_level_file_is_replaced_never_written_through(world, capsys, name):
    tmp_path, outside, config = world
    out = tmp_path / "out"
    assert sweep(tmp_path, config) == 0
    (out / name).unlink()
    os.symlink(outside / "victim.txt", out / name)
    for cell in (out / "cells").iterdir():  # cells to run again, so that every file is written
        cell.unlink()
    before = snapshot(outside)
    assert sweep(tmp_path, config) == 0, capsys.readouterr().err
    assert snapshot(outside) == before
    assert (out / name).is_file() and not (out / name).is_symlink()
    rebuild_results(SweepStore(out))  # what 'aaeval report' rebuilds
    assert snapshot(outside) == before


# --- case 9: a record with one unknown field -------------------------------------------------

@pytest.mark.slow
@pytest.mark.parametrize("command", ["sweep", "report"])
def test_a_record_with_an_unknown_field_is_set_aside_and_rerun(world, capsys, command):
    tmp_path, outside, config = world
    out = tmp_path / "out"
    assert sweep(tmp_path, config) == 0
    cell = sorted((out / "cells").iterdir())[0]
    record = json.loads(cell.read_text())
    record["x"] = 1
    cell.write_text(json.dumps(record))
    capsys.readouterr()
    if command == "report":  # the tables 'aaeval report' rebuilds first
        rebuild_results(SweepStore(out))
        err = capsys.readouterr().err
        assert len(pd.read_parquet(out / "results.parquet")) == 1  # pending, not an error for the folder
    else:
        assert sweep(tmp_path, config) == 0
        err = capsys.readouterr().err
        assert len(pd.read_parquet(out / "results.parquet")) == 2  # run again
    assert str(cell) in err and "'x'" in err
    moved = next((out / "quarantine").rglob(cell.name))
    assert json.loads(moved.read_text())["x"] == 1  # kept, not deleted


# --- case 13: report during a running sweep ---------------------------------------------------

@pytest.mark.slow
def test_report_leaves_the_tables_of_a_running_sweep_alone(world, capsys):
    from aaeval.sweeps.folder_lock import FolderInUse

    tmp_path, outside, config = world
    out = tmp_path / "out"
    assert sweep(tmp_path, config) == 0
    parquet = out / "results.parquet"
    stamp = parquet.stat().st_mtime_ns, parquet.read_bytes()
    # another process holds the folder's lock, as a running sweep does
    holder = subprocess.Popen(
        [sys.executable, "-c", "import sys, time\nfrom aaeval.sweeps import SweepStore\n"
         f"with SweepStore({str(out)!r}).lock():\n    print('held', flush=True)\n    time.sleep(60)\n"],
        stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        capsys.readouterr()
        results, _ = rebuild_results(SweepStore(out))  # what 'aaeval report' reads
        err = capsys.readouterr().err
        assert "running sweep" in err and str(holder.pid) in err
        assert len(results) == 2
        assert (parquet.stat().st_mtime_ns, parquet.read_bytes()) == stamp
        with pytest.raises(FolderInUse, match="in use by another sweep"):
            write_results(SweepStore(out))
        assert (parquet.stat().st_mtime_ns, parquet.read_bytes()) == stamp
    finally:
        holder.kill()
        holder.wait()
    time.sleep(0.1)
    rebuild_results(SweepStore(out))  # the lock is free again: rebuilt
    assert parquet.stat().st_mtime_ns != stamp[0]


@pytest.mark.slow
@pytest.mark.parametrize("name", ["figures", "tables", "viewer"])
def test_report_refuses_a_linked_output_folder(world, capsys, name):
    tmp_path, outside, config = world
    out = tmp_path / "out"
    assert sweep(tmp_path, config) == 0
    os.symlink(outside / "dir", out / name)
    before = snapshot(outside)
    capsys.readouterr()
    assert main(["report", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert str(out / name) in err and "symbolic link" in err
    assert snapshot(outside) == before
