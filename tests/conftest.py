"""Shared test set-up."""

import os
import shutil
import tempfile
from pathlib import Path

import pytest

from aaeval import fileio, registries

# the tests are a program: they load the registries once, first, as the command line does
# (test modules parametrise over them when they are collected)
registries.load()


@pytest.fixture(autouse=True)
def _no_fsync(request, monkeypatch):
    """``os.fsync`` and the store's ``syncfs`` do nothing in this process unless the test is
    marked ``durability``.

    An fsync costs about 11 ms on ext4 (a syncfs of a batch of cells more): most of the time of
    the tests that run every shipped config through the engine, which test what is
    written, not that it survives a power cut. The durability tests
    (tests/sweeps/test_store_durability.py, the atomic-write test) keep the real one and spy on it.
    """
    if request.node.get_closest_marker("durability") is None:
        monkeypatch.setattr(os, "fsync", _skip_fsync)
        monkeypatch.setattr(fileio, "_syncfs", _skip_fsync)  # the batched writes' one sync


def _skip_fsync(fd: int) -> None:
    os.fstat(fd)  # a bad descriptor still fails, as the real fsync would


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory):
    """Ground-truth and reference caches go to a temporary folder, never the user's."""
    old = os.environ.get("AAEVAL_CACHE_DIR")
    os.environ["AAEVAL_CACHE_DIR"] = str(tmp_path_factory.mktemp("aaeval-cache"))
    yield
    if old is None:
        os.environ.pop("AAEVAL_CACHE_DIR", None)
    else:
        os.environ["AAEVAL_CACHE_DIR"] = old


#: Linux's memory file system, where :func:`memory_tmp_path` makes its folders
MEMORY_FS = Path("/dev/shm")
MEMORY_FS_FREE = 2 << 30  # bytes it must have free (a container's default /dev/shm is 64 MiB)


@pytest.fixture
def memory_tmp_path(tmp_path):
    """An empty folder on a memory file system (/dev/shm) where the machine has one with room,
    else ``tmp_path``; removed after the test.

    For tests that write thousands of small files and check what is written, not how a disk
    keeps it: creating, writing and renaming them on the ext4 /tmp cost the table test of the
    shipped configs 15.2 s of system CPU, 1.6 s in memory (the same files, the same calls).
    """
    if not (MEMORY_FS.is_dir() and os.access(MEMORY_FS, os.W_OK)
            and shutil.disk_usage(MEMORY_FS).free > MEMORY_FS_FREE):
        yield tmp_path
        return
    folder = Path(tempfile.mkdtemp(prefix="aaeval-test-", dir=MEMORY_FS))
    try:
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture
def world(tmp_path):
    """A tiny sweep's config with files outside its folder (tests that plant links)."""
    from tests.helpers.links_util import world_of

    return world_of(tmp_path)


@pytest.fixture(autouse=True)
def _report_metrics():
    """Report functions called on hand-made tables describe metrics as a sweep folder would
    (``metrics.json``); ``write_report`` replaces this with the folder's own."""
    from aaeval.metrics import METRICS
    from aaeval.report.sweep_data import METRICS as SHOWN

    SHOWN.clear()
    SHOWN.update({name: metric.info() for name, metric in METRICS.items()})
    yield
