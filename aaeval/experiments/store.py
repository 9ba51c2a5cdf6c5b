"""Where a sweep keeps its results, so that a crash loses nothing finished.

Layout of a sweep folder ``DIR``::

    DIR/experiment.toml          the config as run
    DIR/manifest.json            every cell of the config (key, group, scene, method, frame)
    DIR/cells/<key>.json         one finished cell: its record (metrics, time, host, error)
    DIR/images/<key>.npy         the cell's rendered image (float64 linear RGB)
    DIR/references/<key>.npy     reference images the cells were compared against
    DIR/results.parquet          one tidy table, rebuilt from the cell files

A cell's key hashes its full configuration and the code version, so a changed scene,
option or source file gives new cells instead of stale results. Every file is written
atomically (temporary file, then ``os.replace``) and the record last, so a cell file that
exists is complete, and a killed sweep loses at most the cells in flight.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import Any, Iterable

import numpy as np

import aaeval
from aaeval.imageio import atomic_write

__all__ = ["code_version", "cell_key", "reference_key", "SweepStore", "ReferenceCache", "default_cache_dir"]

# Packages whose source cannot change a cell's result: editing them keeps old results.
_PRESENTATION = ("cli", "reports")


def _package_digest() -> str:
    root = Path(aaeval.__file__).parent
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        if rel.parts[0] in _PRESENTATION:
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


def default_cache_dir() -> Path:
    """Shared reference cache: ``$AAEVAL_CACHE_DIR`` or ``~/.cache/aaeval``."""
    env = os.environ.get("AAEVAL_CACHE_DIR")
    return Path(env) if env else Path.home() / ".cache" / "aaeval"


def _save_npy(path: Path, array: np.ndarray, dtype) -> None:
    atomic_write(path, lambda tmp: np.save(tmp, np.asarray(array, dtype=dtype)))


class ReferenceCache:
    """Reference images on disk, shared by every cell and every sweep of this machine."""

    def __init__(self, root: str | Path | None = None):
        self.root = Path(root) if root is not None else default_cache_dir() / "references"

    def path(self, key: str) -> Path:
        return self.root / f"{key}.npy"

    def get(self, key: str) -> tuple[np.ndarray, dict] | None:
        p, meta = self.path(key), self.root / f"{key}.json"
        if not (p.is_file() and meta.is_file()):
            return None
        try:
            return np.load(p), json.loads(meta.read_text())
        except (OSError, ValueError):
            return None  # unreadable: render it again

    def put(self, key: str, image: np.ndarray, meta: dict) -> None:
        _save_npy(self.path(key), image, np.float64)
        atomic_write(self.root / f"{key}.json", lambda tmp: Path(tmp).write_text(json.dumps(meta)))


class SweepStore:
    """The files of one sweep folder."""

    def __init__(self, root: str | Path):
        self.root = Path(root)
        self.cells_dir = self.root / "cells"
        self.images_dir = self.root / "images"
        self.refs_dir = self.root / "references"

    def cell_path(self, key: str) -> Path:
        return self.cells_dir / f"{key}.json"

    def image_path(self, key: str) -> Path:
        return self.images_dir / f"{key}.npy"

    def reference_path(self, key: str) -> Path:
        return self.refs_dir / f"{key}.npy"

    def finished(self) -> set[str]:
        """Keys of every complete cell file (temporary files start with a dot)."""
        if not self.cells_dir.is_dir():
            return set()
        return {p.stem for p in self.cells_dir.glob("*.json") if not p.name.startswith(".")}

    def read_cell(self, key: str) -> dict:
        return json.loads(self.cell_path(key).read_text())

    def write_cell(self, record: dict, image: np.ndarray | None) -> None:
        # image first: a record that exists always has its image
        if image is not None:
            # float64: a float32 copy would show rounding as error against an exact reference
            _save_npy(self.image_path(record["key"]), image, np.float64)
        text = json.dumps(record, indent=1, default=_jsonable) + "\n"
        atomic_write(self.cell_path(record["key"]), lambda tmp: Path(tmp).write_text(text))

    def write_reference(self, key: str, image: np.ndarray) -> None:
        if not self.reference_path(key).is_file():
            _save_npy(self.reference_path(key), image, np.float64)

    def load_image(self, key: str) -> np.ndarray | None:
        p = self.image_path(key)
        return np.load(p) if p.is_file() else None

    def load_reference(self, key: str) -> np.ndarray | None:
        p = self.reference_path(key)
        return np.load(p) if p.is_file() else None

    def write_manifest(self, experiment_text: str, manifest: dict) -> None:
        atomic_write(self.root / "experiment.toml", lambda tmp: Path(tmp).write_text(experiment_text))
        text = json.dumps(manifest, indent=1, default=_jsonable) + "\n"
        atomic_write(self.root / "manifest.json", lambda tmp: Path(tmp).write_text(text))

    def read_manifest(self) -> dict:
        p = self.root / "manifest.json"
        if not p.is_file():
            raise FileNotFoundError(f"{self.root}: no manifest.json; is this a sweep folder (aaeval sweep CONFIG --out DIR)?")
        return json.loads(p.read_text())

    def records(self, keys: Iterable[str]) -> dict[str, dict]:
        done = self.finished()
        return {k: self.read_cell(k) for k in keys if k in done}


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"cannot store {type(obj).__name__} in a cell record")
