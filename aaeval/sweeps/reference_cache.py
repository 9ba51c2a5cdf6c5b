"""The reference cache: every reference frame a sweep rendered, shared by every sweep of
the machine (``$AAEVAL_CACHE_DIR/references/``, default ``~/.cache/aaeval/references/``).

An entry is two files named by the reference key
(:func:`aaeval.sweeps.cache_keys.reference_key`): ``KEY.npy``, the image (float64 linear
RGB), and ``KEY.json``, its :class:`ReferenceInfo` in typed JSON
(:mod:`aaeval.sweeps.typed_json`), so a noise that was not measured (NaN) comes back
as NaN and never as ``None``.

The cache is an input like any other: a file someone else's sweep wrote, a disk that
filled up, an edit by hand. Every entry is checked before use (regular files only, the
image's shape and size from its header before its data, finite pixels, every field of its
type and within what the image allows); a damaged entry is named once on stderr and
rendered again, and the new render replaces it.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import stat
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from aaeval.sweeps.typed_json import TypedJSONError, decode_float, encode
from aaeval.fileio import atomic_write_many
from aaeval.groundtruth.cache import cache_root

__all__ = ["ReferenceInfo", "ReferenceCache", "CacheEntryError", "cache_folder_problem"]

# An entry's note is a few hundred bytes; a larger one is damage, never read whole.
_MAX_NOTE_BYTES = 1 << 20
# A noise level is at most the largest difference two renders of the image could have;
# twice the brightest value (or 1) leaves room for a twin brighter than the image.
_NOISE_HEADROOM = 2.0
# The edge scale divides the noise by a relative weight that may be small.
_SCALE_HEADROOM = 1e6


def cache_folder_problem(root: str | Path | None = None) -> str | None:
    """Why the cache folder (``root``, default :func:`aaeval.groundtruth.cache.cache_root`) cannot be used, or
    None: it must be a folder, or not exist yet with a folder to create it in."""
    root = Path(root) if root is not None else cache_root()
    for place in (root, *root.parents):
        if os.path.lexists(place):
            if place.is_dir():
                return None if os.access(place, os.W_OK | os.X_OK) or place != root else (
                    f"cache folder {root} is not writable")
            return f"cache folder {root}: {place} is not a folder (set AAEVAL_CACHE_DIR to a folder)"
    return None


class CacheEntryError(ValueError):
    """A cache entry whose files are not what the cache writes."""


@dataclass(frozen=True)
class ReferenceInfo:
    """What a sweep knows of one reference frame beside its image."""

    #: the reference's method spec (canonical text)
    spec: str
    #: seconds the render took
    render_s: float
    #: the truth's RMS noise per pixel: 0 for an exact reference, the quadrature's error bound
    #: for exact shading, measured against a second seed for a seeded one, NaN when not measured
    noise_rmse: float
    #: the spec of the second render that measured the noise, None when none did
    noise_spec: str | None
    #: per RMS metric, its noise strata (:func:`aaeval.metrics.agreement.noise_strata`); None
    #: when not measured
    noise_by_metric: dict[str, tuple[float, float, float]] | None
    #: the image's intensity sum (:func:`aaeval.metrics.temporal.intensity_sum`)
    intensity_sum: float
    #: the machine that rendered it
    host: str

    def to_json(self) -> dict:
        """Typed-JSON-ready fields (NaN and infinities as their tags, ``None`` as null)."""
        return encode(dataclasses.asdict(self))

    def as_meta(self) -> dict[str, Any]:
        """The fields as a plain dict (the sweep's view of a reference)."""
        meta = dataclasses.asdict(self)
        if self.noise_by_metric is not None:
            meta["noise_by_metric"] = {k: list(v) for k, v in self.noise_by_metric.items()}
        return meta

    @classmethod
    def of(cls, spec: str, result: Mapping[str, Any]) -> "ReferenceInfo":
        """The info of a fresh render (:func:`aaeval.sweeps.tasks.run_reference`'s result)."""
        strata = result.get("noise_by_metric")
        return cls(spec=str(spec), render_s=float(result["render_s"]), noise_rmse=float(result["noise_rmse"]),
                   noise_spec=None if result.get("noise_spec") is None else str(result["noise_spec"]),
                   noise_by_metric=None if strata is None else {
                       str(k): tuple(float(x) for x in v) for k, v in strata.items()},
                   intensity_sum=float(result["intensity_sum"]), host=str(result["host"]))

    @classmethod
    def from_json(cls, data: Any, image: np.ndarray) -> "ReferenceInfo":
        """Read a stored note, checked against its schema and against ``image`` (the entry's
        pixels): :class:`CacheEntryError` naming the field that is wrong."""
        if not isinstance(data, dict):
            raise CacheEntryError(f"the note is not a JSON object ({type(data).__name__})")
        fields = {f.name for f in dataclasses.fields(cls)}
        if set(data) != fields:
            raise CacheEntryError(f"fields missing {sorted(fields - set(data))}, unknown {sorted(set(data) - fields)}")
        for name in ("spec", "host"):
            if not isinstance(data[name], str):
                raise CacheEntryError(f"field {name!r} must be text")
        if data["noise_spec"] is not None and not isinstance(data["noise_spec"], str):
            raise CacheEntryError("field 'noise_spec' must be text or null")
        try:
            values = {name: decode_float(data[name], where=f"field {name!r}")
                      for name in ("render_s", "noise_rmse", "intensity_sum")}
            strata = _strata(data["noise_by_metric"])
        except TypedJSONError as exc:
            raise CacheEntryError(str(exc)) from None
        info = cls(spec=data["spec"], noise_spec=data["noise_spec"], noise_by_metric=strata, host=data["host"],
                   **values)
        info.check_against(image)
        return info

    def check_against(self, image: np.ndarray) -> None:
        """:class:`CacheEntryError` when a number is out of what ``image`` allows."""
        from aaeval.metrics.temporal import intensity_sum

        if not (math.isfinite(self.render_s) and self.render_s >= 0):
            raise CacheEntryError(f"render_s {self.render_s} is not a time")
        expected = intensity_sum(image)
        if not math.isclose(self.intensity_sum, expected, rel_tol=1e-9, abs_tol=1e-9):
            raise CacheEntryError(f"intensity_sum {self.intensity_sum} is not its image's ({expected})")
        brightest = max(1.0, float(np.max(np.abs(image)))) if image.size else 1.0
        noise_cap = _NOISE_HEADROOM * brightest
        _check_noise("noise_rmse", self.noise_rmse, noise_cap)
        for metric, (noise, scale, other) in (self.noise_by_metric or {}).items():
            _check_noise(f"noise_by_metric[{metric!r}]", noise, noise_cap)
            _check_noise(f"noise_by_metric[{metric!r}] scale", scale, _SCALE_HEADROOM * brightest)
            _check_noise(f"noise_by_metric[{metric!r}]", other, noise_cap)


def _strata(value: Any) -> dict[str, tuple[float, float, float]] | None:
    if value is None:
        return None
    if not isinstance(value, dict):
        raise CacheEntryError("field 'noise_by_metric' must be a table of metric = [noise, scale, other] or null")
    out = {}
    for metric, strata in value.items():
        if not (isinstance(strata, list) and len(strata) == 3):
            raise CacheEntryError(f"noise_by_metric[{metric!r}] must be three numbers")
        out[metric] = tuple(decode_float(v, where=f"noise_by_metric[{metric!r}]") for v in strata)
    return out


def _check_noise(name: str, value: float, cap: float) -> None:
    """A noise level is NaN (not measured) or between 0 and ``cap``: an infinite or huge
    one would make every method, point sampling included, agree with the truth."""
    if not math.isnan(value) and not 0.0 <= value <= cap:
        raise CacheEntryError(f"{name} {value!r} is not a noise level of this image (0 to {cap:g}, or NaN)")


def _regular_size(path: Path) -> int | None:
    """The size of ``path`` if it is a regular file (not a link, FIFO or folder), else None."""
    try:
        st = os.lstat(path)
    except OSError:
        return None
    return st.st_size if stat.S_ISREG(st.st_mode) else None


class ReferenceCache:
    """Reference images on disk, shared by every cell and every sweep of this machine."""

    def __init__(self, root: str | Path | None = None):
        self.root = Path(root) if root is not None else cache_root() / "references"
        self._warned: set[Path] = set()

    def path(self, key: str) -> Path:
        return self.root / f"{key}.npy"

    def note_path(self, key: str) -> Path:
        return self.root / f"{key}.json"

    def get(self, key: str, shape: tuple[int, ...] | None = None) -> tuple[np.ndarray, ReferenceInfo] | None:
        """The cached image (of ``shape``, when given) and its info, or None: missing or
        damaged (named once on stderr), it is rendered again and replaces the entry."""
        from aaeval.sweeps.folder_files import npy_problem

        image_path, note_path = self.path(key), self.note_path(key)
        if not os.path.lexists(image_path) and not os.path.lexists(note_path):
            return None
        try:
            note_size = _regular_size(note_path)
            if _regular_size(image_path) is None or note_size is None:
                raise CacheEntryError("not a pair of regular files")
            if note_size > _MAX_NOTE_BYTES:
                raise CacheEntryError(f"its note is {note_size} bytes")
            problem = npy_problem(image_path, shape)
            if problem:
                raise CacheEntryError(problem)
            image = np.load(image_path, allow_pickle=False)
            if image.dtype != np.float64 or not np.isfinite(image).all():
                raise CacheEntryError("its image is not finite float64 pixels")
            data = json.loads(note_path.read_bytes().decode("utf-8"))
            info = ReferenceInfo.from_json(data, image)
        except (CacheEntryError, OSError, ValueError) as exc:
            self._damaged(image_path, exc)
            return None
        return image, info

    def put(self, key: str, image: np.ndarray, info: ReferenceInfo) -> None:
        """Store ``image`` and ``info`` (each file atomically; a damaged entry is replaced)."""
        self.root.mkdir(parents=True, exist_ok=True)
        for path in (self.path(key), self.note_path(key)):
            if os.path.lexists(path) and _regular_size(path) is None and not (path.is_dir() and not path.is_symlink()):
                os.unlink(path)  # a link or a FIFO in its place: replaced, never written through
        text = json.dumps(info.to_json(), allow_nan=False)
        # one shared sync; the image is renamed into place before its note
        atomic_write_many([(self.path(key), lambda tmp: np.save(tmp, np.asarray(image, dtype=np.float64))),
                           (self.note_path(key), lambda tmp: Path(tmp).write_text(text))])

    def _damaged(self, path: Path, exc: Exception) -> None:
        if path not in self._warned:
            self._warned.add(path)
            print(f"aaeval: warning: damaged reference cache entry {path} ({exc}); rendering it again",
                  file=sys.stderr)
