"""Where a sweep keeps its results, so that a crash loses nothing finished.

Layout of a sweep folder ``DIR``::

    DIR/experiment.toml          the config as run
    DIR/manifest.json            every cell of the config (key, group, scene, method, frame)
    DIR/cells/<key>.json         one finished cell: its record (metrics, time, host, error)
    DIR/images/<key>.npy         the cell's rendered image (float64 linear RGB)
    DIR/flip/<key>.npy           the cell's per-pixel FLIP error against its reference (float32)
    DIR/references/<key>.npy     reference images the cells were compared against
    DIR/results.parquet          one tidy table, rebuilt from the cell files

Also ``DIR/sweep.lock`` (the PID of the sweep writing the folder, empty when none),
``DIR/quarantine/<time>/`` (damaged files set aside, never deleted) and
``DIR/history/<time>/`` (earlier configs run into this folder).

A cell's key hashes its full configuration and the code version, so a changed scene,
option or source file gives new cells instead of stale results. Every file is written
atomically (temporary file, synced, then ``os.replace``) and the record last, so a cell file
that exists is complete. Cells are written in batches (:meth:`SweepStore.write_cells`: the
syncs shared by the batch), so a killed sweep loses at most the cells in flight: those still
computing and those waiting for their batch.

Every file is checked when read: a cell record that is not JSON of its key, or an image
or reference ``.npy`` whose header and size disagree (what a power cut or a full disk
leaves), is named, moved to the quarantine folder and counted as not done, so the next
sweep runs that cell again. One folder holds one experiment and has one writer: a second
sweep into it is refused while the first runs, and another experiment only with ``force``.

A sweep reads, writes, truncates and moves only files inside its folder: every file of the
folder is opened without following symbolic links (``O_NOFOLLOW``) and must be a regular
file, and every subfolder it writes into (``cells/``, ``images/``, ``flip/``, ``references/``,
``quarantine/``, ``history/``) must be a real folder, not a link. A planted link is refused
by name (``sweep.lock``, a subfolder) or treated as a damaged file (a cell record or an
image that is a link: set aside, the link itself moved, its target untouched).
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import hashlib
import json
import math
import os
import socket
import stat
import sys
import time
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator

import numpy as np

import aaeval
from aaeval.sweeps.typed_json import dumps
from aaeval.fileio import atomic_write, atomic_write_many

__all__ = ["code_version", "read_table", "SCHEMA_KEY", "cell_key", "reference_key", "SweepStore",
           "StoreError", "FolderInUse", "npy_problem"]

#: The key of ``results.parquet``'s and ``temporal.parquet``'s metadata naming their schema version.
SCHEMA_KEY = b"aaeval_schema_version"


def read_table(path: str | Path):
    """Read ``results.parquet`` or ``temporal.parquet`` (a pandas DataFrame), refusing
    another schema version (:class:`~aaeval.sweeps.record.RecordError`)."""
    import pandas as pd
    import pyarrow.parquet as pq

    from aaeval.sweeps.record import SCHEMA_VERSION, RecordError

    path = Path(path)
    meta = pq.read_schema(path).metadata or {}
    version = meta.get(SCHEMA_KEY, b"").decode() or None
    if version != str(SCHEMA_VERSION):
        raise RecordError(f"{path}: results schema version {version}, this aaeval reads {SCHEMA_VERSION}; "
                          "run the sweep again to rebuild it ('aaeval sweep' resumes: finished cells are kept)")
    return pd.read_parquet(path)


# Packages whose source cannot change a cell's result: editing them keeps old results.
_PRESENTATION = ("cli", "report", "studies")
# Modules that only aggregate the stored tables (the summaries the report draws): the same.
_AGGREGATION = ("sweeps/aggregate.py", "sweeps/summaries.py")


def _package_digest() -> str:
    root = Path(aaeval.__file__).parent
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        if rel.parts[0] in _PRESENTATION or rel.as_posix() in _AGGREGATION:
            continue
        h.update(str(rel).encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()[:12]


_CODE_VERSION: str | None = None


def code_version() -> str:
    """``aaeval`` version plus a hash of the package source that computes results."""
    global _CODE_VERSION
    if _CODE_VERSION is None:
        _CODE_VERSION = f"{aaeval.__version__}+{_package_digest()}"
    return _CODE_VERSION


def _digest(obj: Any) -> str:
    return hashlib.sha256(json.dumps(obj, sort_keys=True, separators=(",", ":")).encode()).hexdigest()[:24]


def cell_key(identity: dict, version: str | None = None) -> str:
    return _digest({**identity, "code": version or code_version()})


def reference_key(scene_digest: str, frame: int, spec: str, version: str | None = None) -> str:
    return _digest({"scene": scene_digest, "frame": frame, "reference": spec, "code": version or code_version()})


class StoreError(ValueError):
    """A sweep folder that cannot be used as asked: in use, another experiment, a damaged file."""


class FolderInUse(StoreError):
    """Another process (a sweep, or a report rebuilding the tables) holds the folder's lock."""


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
    readers = {(1, 0): np.lib.format.read_array_header_1_0, (2, 0): np.lib.format.read_array_header_2_0}
    try:
        size = os.stat(path).st_size
        with open(path, "rb") as f:
            version = np.lib.format.read_magic(f)
            if version not in readers:
                return f"unsupported .npy version {version}"
            stored, _, dtype = readers[version](f)
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


# a cell record, manifest or config of a sweep folder is small; anything larger is damage
_MAX_RECORD_BYTES = 64 << 20
_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_CLOEXEC = getattr(os, "O_CLOEXEC", 0)


def read_own_file(path: Path, limit: int = _MAX_RECORD_BYTES) -> bytes:
    """The bytes of ``path``, a regular file that is not a symbolic link (``OSError`` or
    ``ValueError`` saying why not): a sweep never reads through a link planted in its folder,
    and never blocks on a FIFO or reads a device."""
    try:
        fd = os.open(path, os.O_RDONLY | _NOFOLLOW | _CLOEXEC | getattr(os, "O_NONBLOCK", 0))
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


def _regular_problem(path: Path) -> str | None:
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


def _warn(message: str) -> None:
    print(f"aaeval: warning: {message}", file=sys.stderr)


def _stamp() -> str:
    return time.strftime("%Y%m%dT%H%M%SZ", time.gmtime()) + f"-{os.getpid()}"


def _save_npy(path: Path, array: np.ndarray, dtype) -> None:
    atomic_write(path, _npy_writer(array, dtype))


def _npy_writer(array: np.ndarray, dtype):
    return lambda tmp: np.save(tmp, np.asarray(array, dtype=dtype))


def _text_writer(text: str):
    return lambda tmp: Path(tmp).write_text(text)


def manifest_problem(manifest: dict) -> str | None:
    """Why ``manifest`` (read from ``manifest.json``) does not have the fields the table and
    the report read, of their types, or None."""
    def strings(v):
        return isinstance(v, list) and all(isinstance(x, str) for x in v)

    if not isinstance(manifest.get("experiment"), str):
        return "'experiment' must be text"
    for name in ("description", "primary"):
        if not isinstance(manifest.get(name, ""), str):
            return f"{name!r} must be text"
    for name in ("metrics", "temporal"):
        if not strings(manifest.get(name, [])):
            return f"{name!r} must be a list of metric names"
    fail = manifest.get("fail_above")
    if fail is not None and (isinstance(fail, bool) or not isinstance(fail, (int, float)) or not math.isfinite(fail)
                             or fail <= 0):
        return "'fail_above' must be a finite positive number or null"
    group_temporal = manifest.get("group_temporal", {})
    if not isinstance(group_temporal, dict) or not all(strings(v) for v in group_temporal.values()):
        return "'group_temporal' must be a table of group = [metric names]"
    if not isinstance(manifest.get("scenes", {}), dict) or not all(
            isinstance(v, dict) and isinstance(v.get("document"), dict) for v in manifest.get("scenes", {}).values()):
        return "'scenes' must be a table of digest = {source, document}"
    for i, cell in enumerate(manifest["cells"]):
        if not (isinstance(cell, dict) and isinstance(cell.get("key"), str) and isinstance(cell.get("group"), str)
                and isinstance(cell.get("spec"), str) and isinstance(cell.get("frame"), int)
                and not isinstance(cell.get("frame"), bool) and isinstance(cell.get("scene_digest", ""), str)):
            return f"cells[{i}] must be a table with text key, group, spec and a whole-number frame"
    return None


class SweepStore:
    """The files of one sweep folder.

    ``log`` receives one line per damaged file found (default: a warning on stderr).
    """

    def __init__(self, root: str | Path, log: Callable[[str], None] | None = None):
        self.root = Path(root)
        self.cells_dir = self.root / "cells"
        self.images_dir = self.root / "images"
        self.refs_dir = self.root / "references"
        self.flips_dir = self.root / "flip"
        self.lock_path = self.root / "sweep.lock"
        self.log = log or _warn
        self._quarantine: Path | None = None
        self._locked = False

    def cell_path(self, key: str) -> Path:
        return self.cells_dir / f"{key}.json"

    def image_path(self, key: str) -> Path:
        return self.images_dir / f"{key}.npy"

    def flip_path(self, key: str) -> Path:
        """The cell's per-pixel FLIP map against its reference (float32, H x W), for the viewer."""
        return self.flips_dir / f"{key}.npy"

    def reference_path(self, key: str) -> Path:
        return self.refs_dir / f"{key}.npy"

    # --- reading, checked ------------------------------------------------------------

    def finished(self) -> set[str]:
        """Keys of every sound cell; damaged ones are reported and set aside to run again."""
        return set(self.check(heal=True))

    def check(self, heal: bool = True) -> dict[str, dict]:
        """Every sound finished cell, ``key -> record``.

        A cell is sound when its record is JSON of its own key and, unless it recorded an
        error, its image and its reference are complete arrays. Each damaged file is
        named through ``log``; with ``heal`` it and the files of its cell are moved to
        ``quarantine/`` so that the next sweep runs the cell again.
        """
        for folder in (self.cells_dir, self.images_dir, self.refs_dir, self.flips_dir):
            if os.path.islink(folder):  # reading through it would read, and healing move, files elsewhere
                raise StoreError(f"{folder} is a symbolic link; a sweep reads and moves only files inside "
                                 f"{self.root} (remove the link)")
        if not self.cells_dir.is_dir():
            return {}
        sound: dict[str, dict] = {}
        bad_refs: dict[str, str] = {}
        for path in sorted(self.cells_dir.glob("*.json")):
            if path.name.startswith("."):  # a temporary file of a write in flight
                continue
            record, problem = self._parse_cell(path)
            if problem is None and not record.get("error"):
                shape = (record["height"], record["width"], 3)
                problem = self._array_problem(self.image_path(path.stem), "its image", shape)
                ref = record.get("reference_key")
                if problem is None and isinstance(ref, str):
                    if ref not in bad_refs:
                        bad_refs[ref] = self._array_problem(self.reference_path(ref), "its reference", shape)
                    problem = bad_refs[ref]
            if problem is None:
                sound[path.stem] = record
            else:
                self._set_aside(path, problem, heal, [self.image_path(path.stem), self.flip_path(path.stem)])
        for ref, problem in bad_refs.items():
            if problem is not None and os.path.lexists(self.reference_path(ref)):
                self._move(self.reference_path(ref), heal)
        return sound

    def _parse_cell(self, path: Path) -> tuple[dict, str | None]:
        from aaeval.sweeps.record import CellRecord, RecordError

        try:
            record = json.loads(read_own_file(path).decode("utf-8"))
        except (OSError, ValueError) as exc:  # UnicodeDecodeError and JSONDecodeError are ValueErrors
            return {}, f"not a cell record ({exc})"
        if not isinstance(record, dict) or record.get("key") != path.stem:
            return {}, "not the record of this cell's key"
        try:  # a field missing, unknown or of another schema: damaged like any other record
            CellRecord.from_json(record, where="record")
        except (RecordError, TypeError, ValueError, AttributeError) as exc:
            return {}, f"not a readable cell record ({str(exc).removeprefix('record: ')})"
        return record, None

    def set_aside(self, key: str, problem: str, heal: bool = True) -> None:
        """Quarantine the cell ``key`` (record and image) with ``problem``, as :meth:`check`
        does with a damaged one: for a record that reads well but disagrees with its plan."""
        path = self.cell_path(key)
        if os.path.lexists(path):
            self._set_aside(path, problem, heal, [self.image_path(key), self.flip_path(key)])

    def _array_problem(self, path: Path, what: str, shape: tuple[int, ...] | None = None) -> str | None:
        problem = _regular_problem(path)
        if problem is not None:
            return f"{what} {path} {problem}"
        if not path.is_file():
            return f"{what} {path} is missing"
        problem = npy_problem(path, shape)
        return None if problem is None else f"{what} {path} is damaged: {problem}"

    def _set_aside(self, cell: Path, problem: str, heal: bool, companions: list[Path]) -> None:
        if not heal:
            self.log(f"damaged sweep file {cell}: {problem} (left in place; the cell counts as not done)")
            return
        moved = self._move(cell, heal)
        for path in companions:
            if os.path.lexists(path):  # a link is moved itself; its target is never touched
                self._move(path, heal)
        self.log(f"damaged sweep file {cell}: {problem}; moved to {moved.parent}, the cell will run again")

    def _move(self, path: Path, heal: bool) -> Path:
        if not heal:
            return path
        if self._quarantine is None:
            self._quarantine = self.root / "quarantine" / _stamp()
        target = self._quarantine / path.relative_to(self.root)
        self._folder(target.parent)  # quarantine/ must be a real folder of this one, not a link
        os.replace(path, target)  # never deleted: the user may want to look at it (a link moves as a link)
        return target

    def _folder(self, folder: Path) -> Path:
        """``folder`` (inside the sweep folder), created if missing, with no symbolic link
        and nothing but folders between the sweep folder and it: whatever is written or
        moved into it stays inside the sweep folder."""
        folder = Path(folder)
        rel = folder.relative_to(self.root)
        self.root.mkdir(parents=True, exist_ok=True)
        current = self.root
        for part in rel.parts:
            current = current / part
            try:
                st = os.lstat(current)
            except FileNotFoundError:
                with contextlib.suppress(FileExistsError):
                    os.mkdir(current)
                st = os.lstat(current)
            if stat.S_ISLNK(st.st_mode):
                raise StoreError(f"{current} is a symbolic link; a sweep writes only inside {self.root} "
                                 "(remove the link)")
            if not stat.S_ISDIR(st.st_mode):
                raise StoreError(f"{current} is not a folder; a sweep needs it as one (move it away)")
        return folder

    def own_folder(self, name: str) -> Path:
        """The sweep folder's subfolder ``name``, created if missing and checked to be a real
        folder (:meth:`_folder`), for other writers of the folder such as the report."""
        return self._folder(self.root / name)

    def writable(self, name: str) -> Path:
        """The path of the sweep folder's own file ``name`` (e.g. ``"results.parquet"``),
        its folders checked (:meth:`_folder`); it is written by replacing it atomically,
        so a link planted there is replaced, never followed."""
        path = self.root / name
        self._folder(path.parent)
        return path

    def read_cell(self, key: str) -> dict:
        record, problem = self._parse_cell(self.cell_path(key))
        if problem is not None:
            raise StoreError(f"{self.cell_path(key)}: {problem}")
        return record

    def _load_array(self, path: Path) -> np.ndarray | None:
        problem = _regular_problem(path)
        if problem is not None:
            raise StoreError(f"{path} {problem}")
        if not path.is_file():
            return None
        problem = npy_problem(path)
        if problem is not None:
            raise StoreError(f"{path}: {problem}")
        return np.load(path, allow_pickle=False)

    def load_image(self, key: str) -> np.ndarray | None:
        return self._load_array(self.image_path(key))

    def load_flip(self, key: str) -> np.ndarray | None:
        """The cell's stored FLIP map, or None (a cell of a sweep that stored none)."""
        return self._load_array(self.flip_path(key))

    def load_reference(self, key: str) -> np.ndarray | None:
        return self._load_array(self.reference_path(key))

    def read_manifest(self) -> dict:
        p = self.root / "manifest.json"
        if not os.path.lexists(p):
            raise FileNotFoundError(f"{self.root}: no manifest.json; is this a sweep folder (aaeval sweep CONFIG --out DIR)?")
        try:
            manifest = json.loads(read_own_file(p).decode("utf-8"))
        except (OSError, ValueError) as exc:
            raise StoreError(f"{p}: damaged manifest ({exc}); run the sweep again to rewrite it") from None
        if not isinstance(manifest, dict) or not isinstance(manifest.get("cells"), list):
            raise StoreError(f"{p}: not a sweep manifest (no list of cells); run the sweep again to rewrite it")
        problem = manifest_problem(manifest)
        if problem:
            raise StoreError(f"{p}: not a sweep manifest ({problem}); run the sweep again to rewrite it")
        return manifest

    def records(self, keys: Iterable[str]) -> dict[str, dict]:
        sound = self.check(heal=True)
        return {k: sound[k] for k in keys if k in sound}

    # --- writing ---------------------------------------------------------------------

    def write_cell(self, record: dict, image: np.ndarray | None, flip: np.ndarray | None = None) -> None:
        self.write_cells([(record, image, flip)])

    def write_cells(self, cells: list[tuple[dict, np.ndarray | None, np.ndarray | None]]) -> None:
        """Write finished cells, each ``(record, image, flip map)`` (image and map may be
        None), with the syncs of the batch shared (:func:`aaeval.fileio.atomic_write_many`):
        every file of every cell is synced before any is renamed into place, every image
        and map before any record, so a record that exists always has its image."""
        checked: dict[Path, Path] = {}

        def folder(path: Path) -> Path:  # checked once a batch, and made only when written into
            if path not in checked:
                checked[path] = self._folder(path)
            return checked[path]

        arrays, records = [], []
        for record, image, flip in cells:
            key = record["key"]
            if image is not None:
                # float64: a float32 copy would show rounding as error against an exact reference
                arrays.append((folder(self.images_dir) / f"{key}.npy", _npy_writer(image, np.float64)))
            if flip is not None:  # float32: the viewer shows it in 1/255 steps
                arrays.append((folder(self.flips_dir) / f"{key}.npy", _npy_writer(flip, np.float32)))
            text = dumps(record, indent=1) + "\n"
            records.append((folder(self.cells_dir) / f"{key}.json", _text_writer(text)))
        atomic_write_many(arrays + records)

    def write_flip(self, key: str, flip: np.ndarray) -> None:
        self._folder(self.flips_dir)
        _save_npy(self.flip_path(key), flip, np.float32)

    def write_reference(self, key: str, image: np.ndarray) -> None:
        path = self.reference_path(key)
        self._folder(self.refs_dir)
        if _regular_problem(path) or not path.is_file() or npy_problem(path):
            _save_npy(path, image, np.float64)  # replaces a planted link, never writes through it

    def write_manifest(self, experiment_text: str, manifest: dict) -> None:
        """Write the config and its cells; an earlier, different config moves to ``history/``."""
        old = self.root / "experiment.toml"
        try:
            old_text = read_own_file(old) if os.path.lexists(old) else None
        except (OSError, ValueError):
            old_text = b""  # a link or a damaged file: kept in history/ like another config
        if old_text is not None and old_text != experiment_text.encode():
            kept = self._folder(self.root / "history" / _stamp())
            for name in ("experiment.toml", "manifest.json"):
                if os.path.lexists(self.root / name):
                    os.replace(self.root / name, kept / name)  # a link moves as a link
            self.log(f"the earlier config of {self.root} is kept in {kept}")
        atomic_write(self.root / "experiment.toml", lambda tmp: Path(tmp).write_text(experiment_text))
        text = dumps(manifest, indent=1) + "\n"
        atomic_write(self.root / "manifest.json", lambda tmp: Path(tmp).write_text(text))

    # --- one folder, one experiment, one writer ----------------------------------------

    @contextlib.contextmanager
    def try_lock(self, command: str = "report") -> Iterator[bool]:
        """Hold the lock if no one else does: yields True holding it, False (holding
        nothing) while another process holds it."""
        stack = contextlib.ExitStack()
        try:
            stack.enter_context(self.lock(command))
            held = True
        except FolderInUse:
            held = False
        with stack:
            yield held

    def owner(self) -> dict:
        """Who holds the lock, as it wrote itself into ``sweep.lock`` ({} if unknown)."""
        try:
            return json.loads(read_own_file(self.lock_path, 4096).decode() or "{}")
        except (OSError, ValueError):
            return {}

    @contextlib.contextmanager
    def lock(self, command: str = "sweep") -> Iterator[None]:
        """Hold ``sweep.lock`` (an advisory ``flock`` plus the owner's PID) while writing.

        The kernel drops the ``flock`` when its process ends, however it ends, so a lock
        file that names a PID but is not locked is stale and is taken over.
        """
        if self._locked:  # this store already holds it (the sweep rebuilding its tables)
            yield
            return
        self.root.mkdir(parents=True, exist_ok=True)
        try:  # never through a link: O_RDWR|O_CREAT on a link would open, then truncate, its target
            fd = os.open(self.lock_path, os.O_RDWR | os.O_CREAT | _NOFOLLOW | _CLOEXEC
                         | getattr(os, "O_NONBLOCK", 0), 0o666)
        except OSError as exc:
            if exc.errno == errno.ELOOP:
                raise StoreError(f"{self.lock_path} is a symbolic link; a sweep opens only its own files "
                                 f"inside {self.root} (remove the link)") from None
            raise
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                raise StoreError(f"{self.lock_path} is not a regular file; a sweep needs it as its lock "
                                 "(move it away)")
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                owner = _lock_owner(fd)
                raise FolderInUse(
                    f"{self.root} is in use by another {owner.get('command', 'sweep')} (pid {owner.get('pid', '?')} on "
                    f"{owner.get('host', '?')}, started {owner.get('started', '?')}); wait for it or stop it"
                ) from None
            stale = _lock_owner(fd)
            if stale.get("pid"):
                self.log(f"stale lock {self.lock_path} of pid {stale['pid']} on {stale.get('host', '?')} "
                         "(that sweep no longer runs) taken over")
            owner = {"pid": os.getpid(), "host": socket.gethostname(), "command": command,
                     "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
            os.ftruncate(fd, 0)
            os.pwrite(fd, (json.dumps(owner) + "\n").encode(), 0)
            self._locked = True
            try:
                yield
            finally:
                self._locked = False
                os.ftruncate(fd, 0)  # kept, not unlinked: unlinking a locked file races
        finally:
            os.close(fd)  # releases the flock

    def check_experiment(self, name: str, keys: set[str], *, force: bool = False) -> None:
        """Refuse another experiment's folder unless ``force``; say which finished cells
        this config leaves out of the table (their files stay)."""
        p = self.root / "manifest.json"
        if not os.path.lexists(p):
            return
        try:
            previous = json.loads(read_own_file(p).decode("utf-8")).get("experiment")
        except (OSError, ValueError, AttributeError):
            previous = None  # a damaged manifest is rewritten by this run
        if previous is not None and previous != name and not force:
            raise StoreError(f"{self.root} holds the results of experiment {previous!r}, not {name!r}; "
                             "choose another --out folder, or pass --force to run it here "
                             "(the old config goes to history/, its cell files stay)")
        left_out = set(self.check(heal=True)) - keys
        if left_out:
            self.log(f"{len(left_out)} finished cells in {self.cells_dir} are not in this config: "
                     "they leave results.parquet, their files stay (run their config again to see them)")


def _lock_owner(fd: int) -> dict:
    try:
        owner = json.loads(os.pread(fd, 4096, 0).decode() or "{}")
    except (OSError, ValueError):
        return {}
    return owner if isinstance(owner, dict) else {}
