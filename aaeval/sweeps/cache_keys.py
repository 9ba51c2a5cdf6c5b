"""The keys of a sweep's stored cells and references: what they hash, and the code version.

A cell's key hashes its full configuration (:meth:`aaeval.sweeps.cells.Cell.identity`) and
the code version, so a changed scene, option or source file gives new cells instead of stale
results. The code version is the ``aaeval`` version plus a hash of the package source that
computes results: editing the command line, the report, the studies or the modules that only
aggregate stored tables keeps every finished cell.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

import aaeval

__all__ = ["code_version", "cell_key", "reference_key"]

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
