"""Files written whole or not at all, and the sRGB transfer function: what every writer of
aaeval needs (images, tables, the report's pages), with nothing that renders. Images by
suffix, with the EXR format Mitsuba reads, are :mod:`aaeval.imageio`.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import os
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["linear_to_srgb", "linear_to_srgb8", "srgb_to_linear", "atomic_write", "atomic_write_many", "check_outputs", "OutputError"]


def linear_to_srgb(image) -> np.ndarray:
    """Linear RGB, clipped to [0, 1], to sRGB-encoded values in [0, 1] (IEC 61966-2-1)."""
    x = np.clip(np.asarray(image, dtype=np.float64), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def linear_to_srgb8(image: np.ndarray) -> np.ndarray:
    """Linear RGB in [0, 1] to 8-bit sRGB (IEC 61966-2-1 transfer function)."""
    return np.round(linear_to_srgb(image) * 255.0).astype(np.uint8)


class OutputError(ValueError):
    """An output path that cannot be written: a folder, a clash, no permission."""


def check_outputs(outputs: dict[str, str | Path | None], *, folders: bool = False) -> None:
    """Refuse, before any work, outputs that cannot be written: ``{option: path}``.

    Each path must not be a folder (or, with ``folders``, must be one or not exist yet),
    no two options may name the same file, and the nearest existing folder above each must
    let us create files (probed by creating one, so read-only file systems and permissions
    are both seen, also for root).
    """
    seen: dict[Path, str] = {}
    for option, raw in outputs.items():
        if raw is None:
            continue
        path = Path(raw)
        resolved = path.resolve()
        if resolved in seen:
            raise OutputError(f"{seen[resolved]} and {option} both name {path}; give each its own file")
        seen[resolved] = option
        if folders:
            if path.exists() and not path.is_dir():
                raise OutputError(f"{option} {path}: not a directory")
        elif path.is_dir():
            raise OutputError(f"{option} {path}: is a directory; give a file name")
        _check_creatable(path if folders and path.is_dir() else path.parent, option, path)


def _check_creatable(folder: Path, option: str, path: Path) -> None:
    existing = folder
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        raise OutputError(f"{option} {path}: {existing} is not a directory")
    try:
        with tempfile.TemporaryFile(dir=existing, prefix=".aaeval-probe-"):
            pass
    except OSError as exc:
        raise OutputError(f"{option} {path}: cannot write in {existing} ({exc.strerror})") from None


def _fsync_dir(folder: Path) -> None:
    try:
        fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:  # a platform without directory descriptors: nothing more to do
        return
    try:
        os.fsync(fd)
    except OSError:
        pass  # some file systems cannot sync a directory; the rename itself is still atomic
    finally:
        os.close(fd)


def _syncfs(fd: int) -> None:
    """``syncfs(2)``: write out every file of the file system holding ``fd`` and wait;
    ``OSError`` where the C library has none (not Linux) or it fails."""
    import ctypes

    syncfs = getattr(_libc(), "syncfs", None)
    if syncfs is None:
        raise OSError(errno.ENOSYS, "no syncfs")
    if syncfs(fd) != 0:
        raise OSError(ctypes.get_errno(), "syncfs failed")


@functools.cache
def _libc():
    import ctypes

    return ctypes.CDLL(None, use_errno=True)


def _sync_files(paths: list[str]) -> None:
    """Every file of ``paths`` on disk: one ``fsync`` for one file; for several, one sync of
    their file system (one flush of the journal instead of one per file), each file's own
    ``fsync`` where that cannot be done."""
    if len(paths) > 1:
        with open(paths[0], "rb") as first:
            try:
                _syncfs(first.fileno())
                return
            except OSError:
                pass
    for path in paths:
        with open(path, "rb") as written:
            os.fsync(written.fileno())


def _sync_folders(folders: list[Path]) -> None:
    """The renames into ``folders`` on disk: each folder's ``fsync``. Once the files' data is
    synced, these commit only the renames (a few folders a batch), where a sync of the whole
    file system would write every other process's dirty pages too."""
    for folder in folders:
        _fsync_dir(folder)


def _disk_full(exc: OSError, folder: Path) -> bool:
    # numpy reports a short write as "N requested and M written", with no errno
    if exc.errno == errno.ENOSPC:
        return True
    if exc.errno is not None:
        return False
    try:
        fs = os.statvfs(folder)
    except OSError:
        return False
    return fs.f_bavail * fs.f_frsize < (1 << 20)


def srgb_to_linear(srgb) -> np.ndarray:
    """sRGB-encoded values in [0, 1] to linear RGB (IEC 61966-2-1 transfer function)."""
    s = np.asarray(srgb, dtype=np.float64)
    return np.where(s <= 0.04045, s / 12.92, ((s + 0.055) / 1.055) ** 2.4)


def atomic_write(path: str | Path, write) -> Path:
    """Call ``write(tmp_path)`` then move the temporary file onto ``path``.

    The file gets the mode a plain ``open`` would (0666 less the umask), and it and its
    folder are synced to disk around the rename: after a power cut ``path`` holds either
    the old content or the whole new one, never a truncated file. A full disk raises
    :class:`OSError` ``no space left on device: PATH`` and leaves ``path`` as it was.
    """
    return atomic_write_many([(path, write)])[0]


def atomic_write_many(writes) -> list[Path]:
    """:func:`atomic_write` for each ``(path, write)`` of ``writes``, with the syncs shared:
    every file is written to its temporary file, all of them are synced (one sync of the file
    system for several), then each is renamed onto its path in the order given, then each of
    their folders is synced once. A file renamed is whole; a failure before the renames leaves every
    path as it was, and one during them leaves the earlier paths written, the later ones as
    they were.
    """
    writes = [(Path(path), write) for path, write in writes]
    folders = list(dict.fromkeys(path.parent for path, _ in writes))
    pending: list[str] = []  # temporary files not yet renamed
    try:
        for folder in folders:
            try:
                folder.mkdir(parents=True, exist_ok=True)
            except OSError as exc:  # name the user's path, not the temporary file's
                path = next(path for path, _ in writes if path.parent == folder)
                raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
        for path, write in writes:
            pending.append(_temporary(path))
            try:
                write(pending[-1])
            except BaseException as exc:
                _refuse_write(exc, pending[-1], path)
        try:
            _sync_files(pending)
        except OSError as exc:  # a delayed allocation finds the disk full here
            _refuse_write(exc, None, writes[0][0])
        for (path, _), tmp in zip(writes, list(pending)):
            os.replace(tmp, path)
            pending.remove(tmp)
    except BaseException:
        for tmp in pending:
            with contextlib.suppress(OSError):
                os.unlink(tmp)
        raise
    _sync_folders(folders)
    return [path for path, _ in writes]


#: Flags of a new temporary file: created here or refused (never an existing file, never
#: through a link), not inherited by a child.
_CREATE = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
_TEMPORARY_TRIES = 100


def _temporary(path: Path) -> str:
    """A new empty temporary file beside ``path`` (in an existing folder), of the mode a plain
    ``open`` gives (0666 less the umask, applied by the kernel as it creates the file)."""
    for _ in range(_TEMPORARY_TRIES):
        # eight random characters, as mkstemp draws: a long file name still fits the file system's limit
        tmp = os.path.join(path.parent, f".{path.stem}.{os.urandom(4).hex()}{path.suffix}")
        try:
            fd = os.open(tmp, _CREATE, 0o666)
        except FileExistsError:  # another writer's temporary file of that name: draw again
            continue
        except OSError as exc:  # name the user's path, not the temporary file's
            raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
        os.close(fd)
        return tmp
    raise OSError(errno.EEXIST, "no free temporary file name", str(path))


def _refuse_write(exc: BaseException, tmp: str | None, path: Path):
    """Raise ``exc`` of writing ``tmp`` as the user's: a full disk as ``no space left on device:
    PATH``, an error naming the temporary file as one naming ``path``."""
    if isinstance(exc, OSError) and _disk_full(exc, path.parent):  # before the unlink frees space
        raise OSError(errno.ENOSPC, "no space left on device", str(path)) from None
    if isinstance(exc, OSError) and exc.filename is not None and str(exc.filename) == str(tmp):
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
    raise exc
