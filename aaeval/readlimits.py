"""One bounded reader for every input file aaeval reads: scenes, experiment configs,
``[svg].file``, ``[text].font``, SVGs and fonts given to ``aaeval import``.

:func:`read_bytes` refuses, before reading anything, a path that is not a regular file
(a FIFO would block forever, ``/dev/zero`` never ends, a folder is not a file) and a file
larger than the limit (default :data:`DEFAULT_MAX_FILE_BYTES`, 64 MiB; the environment
variable ``AAEVAL_MAX_FILE_BYTES``, e.g. ``512M``, raises or lowers it). The file is
opened once, without blocking, checked on that open descriptor (so a path swapped
between the check and the read is still checked), and read up to the limit plus one
byte, so a file that grows while being read is refused too.

Every refusal is a :class:`FileLimitError` (a ``ValueError``, which the command line
turns into one line on stderr and exit code 2) naming the file and the rule.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from aaeval.limits import env_bytes

__all__ = ["DEFAULT_MAX_FILE_BYTES", "FileLimitError", "max_file_bytes", "read_bytes", "read_text"]

# Scenes, configs, SVGs and fonts shipped or written by aaeval are well under 10 MiB.
DEFAULT_MAX_FILE_BYTES = 64 << 20


class FileLimitError(ValueError):
    """An input file that is not a regular file, is too large, or cannot be read."""


def max_file_bytes() -> int:
    """The largest input file read: ``AAEVAL_MAX_FILE_BYTES`` if set, else 64 MiB."""
    return env_bytes("AAEVAL_MAX_FILE_BYTES", DEFAULT_MAX_FILE_BYTES, FileLimitError)


def _size(n: int) -> str:
    for unit, scale in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n} bytes"


def read_bytes(path: str | os.PathLike, *, what: str, limit: int | None = None) -> bytes:
    """The bytes of ``path``, a regular file of at most ``limit`` bytes (default
    :func:`max_file_bytes`, and never more than it); ``what`` says what the file is for
    ("scene file", "SVG file", "font") in the one-line refusal."""
    path = Path(path)
    env_cap = max_file_bytes()
    cap = env_cap if limit is None else min(int(limit), env_cap)
    hint = " (AAEVAL_MAX_FILE_BYTES raises it)" if cap == env_cap else f" for a {what}"
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        before = os.stat(path)
    except OSError as exc:
        raise FileLimitError(f"{path}: cannot read {what} ({exc.strerror})") from None
    if not stat.S_ISREG(before.st_mode):
        raise FileLimitError(f"{path}: {what} is not a regular file ({_kind(before.st_mode)}); "
                             "aaeval reads only regular files")
    try:
        fd = os.open(path, flags)
    except OSError as exc:
        raise FileLimitError(f"{path}: cannot read {what} ({exc.strerror})") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise FileLimitError(f"{path}: {what} is not a regular file ({_kind(st.st_mode)}); "
                                 "aaeval reads only regular files")
        if st.st_size > cap:
            raise FileLimitError(f"{path}: {what} is {_size(st.st_size)}, over the limit of {_size(cap)}{hint}")
        os.set_blocking(fd, True)
        chunks, total = [], 0
        while True:
            chunk = os.read(fd, min(1 << 20, cap + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
            if total > cap:
                raise FileLimitError(f"{path}: {what} grew past the limit of {_size(cap)} while being read "
                                     "(AAEVAL_MAX_FILE_BYTES raises it)")
        return b"".join(chunks)
    except OSError as exc:
        raise FileLimitError(f"{path}: cannot read {what} ({exc.strerror})") from None
    finally:
        os.close(fd)


def read_text(path: str | os.PathLike, *, what: str, limit: int | None = None) -> str:
    """:func:`read_bytes` decoded as UTF-8; other bytes are refused naming the offset."""
    data = read_bytes(path, what=what, limit=limit)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise FileLimitError(f"{path}: {what} is not UTF-8 text (byte {data[exc.start]:#04x} at offset "
                             f"{exc.start})") from None


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"
