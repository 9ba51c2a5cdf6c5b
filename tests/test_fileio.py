"""Files written whole or not at all (:mod:`aaeval.fileio`): the umask, the syncs around the
rename, the user's path in every error, a full disk, several files at once; outputs refused
before any work; the sRGB transfer function against colour-science's."""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

import numpy as np
import pytest

from aaeval.fileio import (OutputError, atomic_write, atomic_write_many, check_outputs, linear_to_srgb,
                           linear_to_srgb8, srgb_to_linear)


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


def test_atomic_write_names_the_users_path_not_its_temporary_file(tmp_path):
    with pytest.raises(OSError) as info:
        atomic_write("/proc/aaeval-out.json", lambda tmp: Path(tmp).write_text("x"))
    assert info.value.filename == "/proc/aaeval-out.json"
    target = tmp_path / "out.json"

    def fail(tmp):
        raise PermissionError(13, "Permission denied", tmp)

    with pytest.raises(OSError) as info:
        atomic_write(target, fail)
    assert info.value.filename == str(target) and not target.exists()
    assert not [p for p in tmp_path.iterdir()]  # no temporary file left


def test_a_full_disk_says_so_and_keeps_the_old_file(tmp_path, capsys):
    target = tmp_path / "kept.json"
    target.write_text("earlier")

    def fill(tmp):  # a real ENOSPC from the kernel: /dev/full is always full
        with open("/dev/full", "w") as full:
            full.write("x" * 65536)

    with pytest.raises(OSError, match="no space left on device") as info:
        atomic_write(target, fill)
    assert info.value.errno == errno.ENOSPC and info.value.filename == str(target)
    assert target.read_text() == "earlier" and [p.name for p in tmp_path.iterdir()] == ["kept.json"]


def test_several_files_are_all_written_or_none_when_one_write_fails(tmp_path):
    first, second = tmp_path / "a.txt", tmp_path / "sub" / "b.txt"
    first.write_text("old a")
    assert atomic_write_many([(first, lambda tmp: Path(tmp).write_text("new a")),
                              (second, lambda tmp: Path(tmp).write_text("new b"))]) == [first, second]
    assert (first.read_text(), second.read_text()) == ("new a", "new b")

    def fail(tmp):
        raise RuntimeError("the second write fails")

    with pytest.raises(RuntimeError, match="second write"):
        atomic_write_many([(first, lambda tmp: Path(tmp).write_text("newer a")), (second, fail)])
    assert (first.read_text(), second.read_text()) == ("new a", "new b")  # the first was not renamed either
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["a.txt", "b.txt", "sub"]  # no temporary file left


def test_outputs_that_cannot_be_written_are_refused_naming_the_option(tmp_path):
    check_outputs({"-o": tmp_path / "new" / "image.png", "--json": None})  # a folder to be made is fine
    with pytest.raises(OutputError, match="-o .*is a directory"):
        check_outputs({"-o": tmp_path})
    with pytest.raises(OutputError, match="-o and --stats both name"):
        check_outputs({"-o": tmp_path / "x.json", "--stats": tmp_path / "." / "x.json"})
    afile = tmp_path / "afile"
    afile.write_text("")
    with pytest.raises(OutputError, match="--out .*not a directory"):
        check_outputs({"--out": afile}, folders=True)
    with pytest.raises(OutputError, match="-o .*afile is not a directory"):
        check_outputs({"-o": afile / "x.png"})
    with pytest.raises(OutputError, match="-o /proc/x.png: cannot write in /proc"):
        check_outputs({"-o": "/proc/x.png"})


def test_srgb_transfer_agrees_with_colour_science_and_inverts():
    import colour

    linear = np.concatenate([np.linspace(0.0, 0.01, 1001), np.linspace(0.0, 1.0, 1001)])  # the knee and the range
    np.testing.assert_allclose(linear_to_srgb(linear), colour.cctf_encoding(linear, function="sRGB"), rtol=0, atol=1e-12)
    np.testing.assert_allclose(srgb_to_linear(linear), colour.cctf_decoding(linear, function="sRGB"), rtol=0, atol=1e-12)
    np.testing.assert_allclose(srgb_to_linear(linear_to_srgb(linear)), linear, rtol=0, atol=1e-12)
    np.testing.assert_allclose(linear_to_srgb([-1.0, 2.0]), [0.0, 1.0], rtol=0, atol=1e-15)  # out-of-range light is clipped
    codes = np.arange(256)
    np.testing.assert_array_equal(linear_to_srgb8(srgb_to_linear(codes / 255.0)), codes)  # every 8-bit code survives
