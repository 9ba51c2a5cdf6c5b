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

A cell's key hashes its full configuration and the code version
(:mod:`aaeval.sweeps.cache_keys`), so a changed scene, option or source file gives new cells
instead of stale results. Every file is written
atomically (temporary file, synced, then ``os.replace``) and the record last, so a cell file
that exists is complete. Cells are written in batches (:meth:`SweepStore.write_cells`: the
syncs shared by the batch), so a killed sweep loses at most the cells in flight: those still
computing and those waiting for their batch.

Every file is checked when read: a cell record that is not JSON of its key, or an image
or reference ``.npy`` whose header and size disagree (what a power cut or a full disk
leaves), is named, moved to the quarantine folder (:mod:`aaeval.sweeps.quarantine`) and counted as
not done, so the next sweep runs that cell again. One folder holds one experiment and has one
writer (:mod:`aaeval.sweeps.folder_lock`): a second sweep into it is refused while the first
runs, and another experiment only with ``force``.

A sweep reads, writes, truncates and moves only files inside its folder
(:mod:`aaeval.sweeps.folder_files`): every file of the folder is opened without following symbolic links (``O_NOFOLLOW``) and must be a regular
file, and every subfolder it writes into (``cells/``, ``images/``, ``flip/``, ``references/``,
``quarantine/``, ``history/``) must be a real folder, not a link. A planted link is refused
by name (``sweep.lock``, a subfolder) or treated as a damaged file (a cell record or an
image that is a link: set aside, the link itself moved, its target untouched).
"""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path
from typing import Callable, Iterable

import numpy as np

from aaeval.fileio import atomic_write, atomic_write_many
from aaeval.sweeps.folder_files import (StoreError, npy_problem, npy_writer, read_own_file, real_folder,
                                        regular_problem, save_npy, text_writer)
from aaeval.sweeps.folder_lock import FolderLock
from aaeval.sweeps.quarantine import Quarantine, stamp
from aaeval.sweeps.typed_json import dumps

__all__ = ["read_table", "SCHEMA_KEY", "SweepStore", "manifest_problem"]

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


def _warn(message: str) -> None:
    print(f"aaeval: warning: {message}", file=sys.stderr)


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
        self.log = log or _warn
        self._lock = FolderLock(self.root, lambda message: self.log(message))
        self.lock_path = self._lock.path
        self._quarantine = Quarantine(self.root, lambda message: self.log(message))

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
        return {key: raw for key, (raw, _) in self._sound(heal).items()}

    def sound_records(self, heal: bool = True):
        """:meth:`check` with each record read: ``key ->``
        :class:`~aaeval.sweeps.record.CellRecord`."""
        return {key: record for key, (_, record) in self._sound(heal).items()}

    def _sound(self, heal: bool):
        for folder in (self.cells_dir, self.images_dir, self.refs_dir, self.flips_dir):
            if os.path.islink(folder):  # reading through it would read, and healing move, files elsewhere
                raise StoreError(f"{folder} is a symbolic link; a sweep reads and moves only files inside "
                                 f"{self.root} (remove the link)")
        if not self.cells_dir.is_dir():
            return {}
        sound: dict[str, tuple] = {}
        bad_refs: dict[str, str] = {}
        for path in sorted(self.cells_dir.glob("*.json")):
            if path.name.startswith("."):  # a temporary file of a write in flight
                continue
            record, parsed, problem = self._parse_cell(path)
            if problem is None and not record.get("error"):
                shape = (record["height"], record["width"], 3)
                problem = self._array_problem(self.image_path(path.stem), "its image", shape)
                ref = record.get("reference_key")
                if problem is None and isinstance(ref, str):
                    if ref not in bad_refs:
                        bad_refs[ref] = self._array_problem(self.reference_path(ref), "its reference", shape)
                    problem = bad_refs[ref]
            if problem is None:
                sound[path.stem] = record, parsed
            else:
                companions = [self.image_path(path.stem), self.flip_path(path.stem)]
                self._quarantine.set_aside(path, problem, heal, companions)
        for ref, problem in bad_refs.items():
            if problem is not None and os.path.lexists(self.reference_path(ref)):
                self._quarantine.move(self.reference_path(ref), heal)
        return sound

    def _parse_cell(self, path: Path):
        """``(stored record, CellRecord, None)``, or ``({}, None, why it is damaged)``."""
        from aaeval.sweeps.record import CellRecord, RecordError

        try:
            record = json.loads(read_own_file(path).decode("utf-8"))
        except (OSError, ValueError) as exc:  # UnicodeDecodeError and JSONDecodeError are ValueErrors
            return {}, None, f"not a cell record ({exc})"
        if not isinstance(record, dict) or record.get("key") != path.stem:
            return {}, None, "not the record of this cell's key"
        try:  # a field missing, unknown or of another schema: damaged like any other record
            parsed = CellRecord.from_json(record, where="record")
        except (RecordError, TypeError, ValueError, AttributeError) as exc:
            return {}, None, f"not a readable cell record ({str(exc).removeprefix('record: ')})"
        return record, parsed, None

    def set_aside(self, key: str, problem: str, heal: bool = True) -> None:
        """Quarantine the cell ``key`` (record and image) with ``problem``, as :meth:`check`
        does with a damaged one: for a record that reads well but disagrees with its plan."""
        path = self.cell_path(key)
        if os.path.lexists(path):
            self._quarantine.set_aside(path, problem, heal, [self.image_path(key), self.flip_path(key)])

    def _array_problem(self, path: Path, what: str, shape: tuple[int, ...] | None = None) -> str | None:
        problem = regular_problem(path)
        if problem is not None:
            return f"{what} {path} {problem}"
        if not path.is_file():
            return f"{what} {path} is missing"
        problem = npy_problem(path, shape)
        return None if problem is None else f"{what} {path} is damaged: {problem}"

    def own_folder(self, name: str) -> Path:
        """The sweep folder's subfolder ``name``, created if missing and checked to be a real
        folder (:func:`~aaeval.sweeps.folder_files.real_folder`), for other writers of the
        folder such as the report."""
        return real_folder(self.root, self.root / name)

    def writable(self, name: str) -> Path:
        """The path of the sweep folder's own file ``name`` (e.g. ``"results.parquet"``),
        its folders checked (:func:`~aaeval.sweeps.folder_files.real_folder`); it is written
        by replacing it atomically, so a link planted there is replaced, never followed."""
        path = self.root / name
        real_folder(self.root, path.parent)
        return path

    def read_cell(self, key: str) -> dict:
        record, _, problem = self._parse_cell(self.cell_path(key))
        if problem is not None:
            raise StoreError(f"{self.cell_path(key)}: {problem}")
        return record

    def _load_array(self, path: Path) -> np.ndarray | None:
        problem = regular_problem(path)
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
                checked[path] = real_folder(self.root, path)
            return checked[path]

        arrays, records = [], []
        for record, image, flip in cells:
            key = record["key"]
            if image is not None:
                # float64: a float32 copy would show rounding as error against an exact reference
                arrays.append((folder(self.images_dir) / f"{key}.npy", npy_writer(image, np.float64)))
            if flip is not None:  # float32: the viewer shows it in 1/255 steps
                arrays.append((folder(self.flips_dir) / f"{key}.npy", npy_writer(flip, np.float32)))
            text = dumps(record, indent=1) + "\n"
            records.append((folder(self.cells_dir) / f"{key}.json", text_writer(text)))
        atomic_write_many(arrays + records)

    def write_flip(self, key: str, flip: np.ndarray) -> None:
        real_folder(self.root, self.flips_dir)
        save_npy(self.flip_path(key), flip, np.float32)

    def write_reference(self, key: str, image: np.ndarray) -> None:
        path = self.reference_path(key)
        real_folder(self.root, self.refs_dir)
        if regular_problem(path) or not path.is_file() or npy_problem(path):
            save_npy(path, image, np.float64)  # replaces a planted link, never writes through it

    def write_manifest(self, experiment_text: str, manifest: dict) -> None:
        """Write the config and its cells; an earlier, different config moves to ``history/``."""
        old = self.root / "experiment.toml"
        try:
            old_text = read_own_file(old) if os.path.lexists(old) else None
        except (OSError, ValueError):
            old_text = b""  # a link or a damaged file: kept in history/ like another config
        if old_text is not None and old_text != experiment_text.encode():
            kept = real_folder(self.root, self.root / "history" / stamp())
            for name in ("experiment.toml", "manifest.json"):
                if os.path.lexists(self.root / name):
                    os.replace(self.root / name, kept / name)  # a link moves as a link
            self.log(f"the earlier config of {self.root} is kept in {kept}")
        atomic_write(self.root / "experiment.toml", lambda tmp: Path(tmp).write_text(experiment_text))
        text = dumps(manifest, indent=1) + "\n"
        atomic_write(self.root / "manifest.json", lambda tmp: Path(tmp).write_text(text))

    # --- one folder, one experiment, one writer ----------------------------------------

    def try_lock(self, command: str = "report"):
        """:meth:`FolderLock.try_lock <aaeval.sweeps.folder_lock.FolderLock.try_lock>`."""
        return self._lock.try_lock(command)

    def owner(self) -> dict:
        """:meth:`FolderLock.owner <aaeval.sweeps.folder_lock.FolderLock.owner>`."""
        return self._lock.owner()

    def lock(self, command: str = "sweep"):
        """Hold ``sweep.lock`` while writing (:class:`~aaeval.sweeps.folder_lock.FolderLock`)."""
        return self._lock.lock(command)

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
