"""A sweep folder's own files, read and written so that nothing outside the folder is touched.

Every file of the folder is opened without following symbolic links (``O_NOFOLLOW``) and
must be a regular file (:func:`read_own_file`, :func:`regular_problem`); every subfolder
written into must be a real folder of the sweep folder, not a link (:func:`real_folder`). A
stored array is checked by its header before it is read (:func:`npy_problem`): what a power
cut or a full disk leaves is named, never read whole.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import io
import math
import os
import stat
from pathlib import Path

import numpy as np

from aaeval.fileio import atomic_write

__all__ = ["StoreError", "MAX_IMAGE_BYTES", "npy_problem", "read_own_file", "regular_problem", "real_folder",
           "save_npy", "npy_writer", "text_writer", "NOFOLLOW", "CLOEXEC"]


class StoreError(ValueError):
    """A sweep folder that cannot be used as asked: in use, another experiment, a damaged file."""


#: The most bytes a stored image may claim: a float64 RGB image of the largest size a record
#: may name (:data:`aaeval.sweeps.record.MAX_RECORD_PIXELS`).
MAX_IMAGE_BYTES = (1 << 28) * 3 * 8


def npy_problem(path: str | Path, shape: tuple[int, ...] | None = None) -> str | None:
    """Why ``path`` is not a complete ``.npy`` array (header and size agree), or None.

    Reads the header only: cheap enough to check every stored image on every read. With
    ``shape`` (the image its record promises), another shape or a dtype that is not floating
    point is a problem too: a sparse file whose header matches its size would otherwise be
    read whole (21 GB), and a complex or wrong-shaped image stopped the report.
    """
    try:
        size = os.stat(path).st_size
        with open(path, "rb") as f:
            version = np.lib.format.read_magic(f)
            if version not in _HEADER_LENGTH:
                return f"unsupported .npy version {version}"
            length = f.read(_HEADER_LENGTH[version])
            stored, dtype = _npy_header(version, length + f.read(min(_header_size(length), _MAX_HEADER)))
            if dtype.hasobject:
                return "holds Python objects, not numbers"
            if shape is not None and (tuple(stored) != tuple(shape)):
                return f"its header says shape {tuple(stored)}, the record {tuple(shape)}"
            if shape is not None and dtype.kind != "f":
                return f"dtype {dtype}, not floating point"
            if math.prod(stored) * dtype.itemsize > MAX_IMAGE_BYTES:
                return f"its header claims {math.prod(stored) * dtype.itemsize} bytes, more than any image a sweep writes"
            expected = f.tell() + math.prod(stored) * dtype.itemsize
    except (OSError, ValueError, EOFError) as exc:
        return f"not a .npy array ({exc or type(exc).__name__})"
    if size != expected:
        return f"{size} bytes where its header promises {expected}" + (" (truncated)" if size < expected else "")
    return None


#: The bytes of the header length field of each ``.npy`` version read.
_HEADER_LENGTH = {(1, 0): 2, (2, 0): 4}
_MAX_HEADER = 10000  # numpy's own limit: it refuses a longer header before reading it


def _header_size(length: bytes) -> int:
    return int.from_bytes(length, "little") if len(length) in (2, 4) else 0


@functools.lru_cache(maxsize=256)
def _npy_header(version: tuple[int, int], header: bytes) -> tuple[tuple[int, ...], np.dtype]:
    """The shape and dtype a ``.npy`` header (after its magic) states, read by numpy: a sweep's
    images share a few headers, and numpy parses each one as Python source."""
    readers = {(1, 0): np.lib.format.read_array_header_1_0, (2, 0): np.lib.format.read_array_header_2_0}
    shape, _, dtype = readers[version](io.BytesIO(header))
    return shape, dtype


# a cell record, manifest or config of a sweep folder is small; anything larger is damage
_MAX_RECORD_BYTES = 64 << 20
#: Flags every open of a folder's file takes: never through a link, never inherited by a child.
NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
CLOEXEC = getattr(os, "O_CLOEXEC", 0)


def read_own_file(path: Path, limit: int = _MAX_RECORD_BYTES) -> bytes:
    """The bytes of ``path``, a regular file that is not a symbolic link (``OSError`` or
    ``ValueError`` saying why not): a sweep never reads through a link planted in its folder,
    and never blocks on a FIFO or reads a device."""
    try:
        fd = os.open(path, os.O_RDONLY | NOFOLLOW | CLOEXEC | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise ValueError("a symbolic link (a sweep folder holds only its own files)") from None
        raise
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise ValueError("not a regular file")
        if st.st_size > limit:
            raise ValueError(f"{st.st_size} bytes, over {limit}")
        os.set_blocking(fd, True)
        chunks, total = [], 0
        while chunk := os.read(fd, 1 << 20):
            chunks.append(chunk)
            total += len(chunk)
            if total > limit:
                raise ValueError(f"over {limit} bytes")
        return b"".join(chunks)
    finally:
        os.close(fd)


def regular_problem(path: Path) -> str | None:
    """Why ``path`` is not a regular file of the folder itself (a link, a FIFO...), or None;
    a missing file is not a problem here."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return None
    except OSError as exc:
        return f"cannot be read ({exc.strerror})"
    if stat.S_ISLNK(st.st_mode):
        return "is a symbolic link (a sweep folder holds only its own files)"
    if not stat.S_ISREG(st.st_mode):
        return "is not a regular file"
    return None


def save_npy(path: Path, array: np.ndarray, dtype) -> None:
    atomic_write(path, npy_writer(array, dtype))


def npy_writer(array: np.ndarray, dtype):
    return lambda tmp: np.save(tmp, np.asarray(array, dtype=dtype))


def text_writer(text: str):
    return lambda tmp: Path(tmp).write_text(text)


def real_folder(root: Path, folder: Path) -> Path:
    """``folder`` (inside the sweep folder ``root``), created if missing, with no symbolic
    link and nothing but folders between ``root`` and it: whatever is written or moved into
    it stays inside the sweep folder."""
    folder = Path(folder)
    rel = folder.relative_to(root)
    root.mkdir(parents=True, exist_ok=True)
    current = root
    for part in rel.parts:
        current = current / part
        try:
            st = os.lstat(current)
        except FileNotFoundError:
            with contextlib.suppress(FileExistsError):
                os.mkdir(current)
            st = os.lstat(current)
        if stat.S_ISLNK(st.st_mode):
            raise StoreError(f"{current} is a symbolic link; a sweep writes only inside {root} "
                             "(remove the link)")
        if not stat.S_ISDIR(st.st_mode):
            raise StoreError(f"{current} is not a folder; a sweep needs it as one (move it away)")
    return folder
