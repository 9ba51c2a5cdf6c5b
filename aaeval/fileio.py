"""Files written whole or not at all, and the sRGB transfer function: what every writer of
aaeval needs (images, tables, the report's pages), with nothing that renders. Images by
suffix, with the EXR format Mitsuba reads, are :mod:`aaeval.imageio`.
"""

from __future__ import annotations

import contextlib
import errno
import os
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["linear_to_srgb", "linear_to_srgb8", "srgb_to_linear", "atomic_write", "check_outputs", "OutputError"]


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


def _umask() -> int:
    # read, not set-and-restore: os.umask() would race with threads creating files
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


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
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=path.suffix)
    except OSError as exc:  # name the user's path, not the temporary file's
        raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None
    try:
        try:
            os.fchmod(fd, 0o666 & ~_umask())  # mkstemp makes 0600 whatever the umask
        finally:
            os.close(fd)
        write(tmp)
        with open(tmp, "rb") as written:
            os.fsync(written.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        full = isinstance(exc, OSError) and _disk_full(exc, path.parent)  # before the unlink frees space
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if full:
            raise OSError(errno.ENOSPC, "no space left on device", str(path)) from None
        if isinstance(exc, OSError) and exc.filename is not None and str(exc.filename) == str(tmp):
            raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from None  # the user's path
        raise
    _fsync_dir(path.parent)
    return path
