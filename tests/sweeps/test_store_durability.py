"""Durability of the sweep store's own writes, checked through the store (not only
``atomic_write``): every file a cell leaves is synced while still a temporary file in its
folder and then renamed onto its name, the image before the record."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from aaeval import fileio
from aaeval.sweeps.store import SweepStore

pytestmark = pytest.mark.durability  # the real os.fsync (tests/conftest.py)


@pytest.fixture
def spied(monkeypatch):
    """Every fsync'd path and every rename, in order, as ('fsync', path) / ('replace', src,
    dst); a sync of the whole file system as one ('fsync', path) per file then in the folder."""
    events = []
    real_fsync, real_replace, real_syncfs = os.fsync, os.replace, fileio._syncfs

    def fsync(fd):
        events.append(("fsync", os.readlink(f"/proc/self/fd/{fd}")))
        return real_fsync(fd)

    def syncfs(fd):
        top = Path(os.readlink(f"/proc/self/fd/{fd}")).parents[1]
        events.extend(("fsync", os.fspath(p)) for p in sorted(top.rglob("*")))
        return real_syncfs(fd)

    def replace(src, dst, *args, **kwargs):
        events.append(("replace", os.fspath(src), os.fspath(dst)))
        return real_replace(src, dst, *args, **kwargs)

    monkeypatch.setattr(os, "fsync", fsync)
    monkeypatch.setattr(os, "replace", replace)
    monkeypatch.setattr(fileio, "_syncfs", syncfs)
    return events


def _landed_atomically(events, path) -> int:
    """Index of the rename that put ``path`` in place; fails unless the file renamed was a
    temporary file beside it, synced before the rename."""
    renames = [i for i, e in enumerate(events) if e[0] == "replace" and e[2] == os.fspath(path)]
    assert renames, f"{path} was not written by a rename"
    i = renames[-1]
    tmp = events[i][1]
    assert os.path.dirname(tmp) == os.path.dirname(os.fspath(path)) and tmp != os.fspath(path)
    assert ("fsync", tmp) in events[:i], f"{tmp} was not synced before it became {path}"
    return i


def test_write_cell_syncs_and_renames_the_image_then_the_record(tmp_path, spied):
    store = SweepStore(tmp_path / "out")
    store.write_cell({"key": "k0", "value": 1.5}, np.ones((3, 4, 3)))
    image_at = _landed_atomically(spied, store.image_path("k0"))
    record_at = _landed_atomically(spied, store.cell_path("k0"))
    assert image_at < record_at  # a record that exists always has its image


def test_write_reference_syncs_and_renames(tmp_path, spied):
    store = SweepStore(tmp_path / "out")
    store.write_reference("r0", np.zeros((2, 2, 3)))
    _landed_atomically(spied, store.reference_path("r0"))


def test_a_batch_of_cells_is_synced_once_before_any_rename_and_records_land_last(tmp_path, spied, monkeypatch):
    """Many cells written together: one sync of the file system for all their files and one
    fsync per folder for the renames (not one per file and folder), every file whole before
    it is renamed, and every image and map in place before the first record."""
    calls, fsyncs = [], []
    monkeypatch.setattr(fileio, "_syncfs", lambda fd, real=fileio._syncfs: calls.append(fd) or real(fd))
    monkeypatch.setattr(os, "fsync", lambda fd, real=os.fsync: fsyncs.append(fd) or real(fd))
    store = SweepStore(tmp_path / "out")
    cells = [({"key": f"k{i}", "value": i}, np.full((3, 4, 3), i, float), np.zeros((3, 4), np.float32))
             for i in range(20)]
    del spied[:]
    store.write_cells(cells)
    assert len(calls) == 1 and len(fsyncs) == 3  # images/, flip/, cells/
    images = [_landed_atomically(spied, store.image_path(f"k{i}")) for i in range(20)]
    flips = [_landed_atomically(spied, store.flip_path(f"k{i}")) for i in range(20)]
    records = [_landed_atomically(spied, store.cell_path(f"k{i}")) for i in range(20)]
    assert max(images + flips) < min(records)
    assert all(np.array_equal(store.load_image(f"k{i}"), cells[i][1]) for i in range(20))
