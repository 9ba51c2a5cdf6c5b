"""The one record of a measured cell: written by the measuring engine, stored as a cell
file, read back by the results table and the report.

:class:`CellRecord` is the only definition of its fields. Reading a record checks it: a
field missing or unknown, or another schema version, is a :class:`RecordError` naming the
field, never a silent column of None. The results table (``results.parquet``) has one
column per field (``options`` and ``metric_errors`` as JSON text) and one per metric
(:data:`aaeval.metrics.METRICS`), and carries :data:`SCHEMA_VERSION` in its metadata.

JSON written here is typed strict JSON (:mod:`aaeval.sweeps.typed_json`): NaN and
the infinities are written as ``"NaN"``, ``"Infinity"`` and ``"-Infinity"`` and read back
as themselves, ``null`` as ``None`` (in a float field that always has a value, a ``null``
that an older aaeval wrote for a value that was not finite reads as NaN).

Timing fields: ``render_s`` is the median of ``repeats`` timed renders (after an untimed
warm-up), ``render_s_min``/``render_s_max`` their spread, ``megapixels`` the image size
(width x height / 1e6) and ``ms_per_mpix`` = ``render_s`` x 1000 / ``megapixels``.
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass, field
from enum import Enum
from typing import Any, Mapping

from aaeval.sweeps.typed_json import decode_float, encode, is_float_value

__all__ = ["SCHEMA_VERSION", "CellRecord", "Failure", "RecordError", "RECORD_FIELDS", "TABLE_FIELDS", "TIMING_FIELDS",
           "noise_column", "agreement_column"]

#: Bump when a field is added, removed or changes meaning.
SCHEMA_VERSION = 4

#: Timing fields, in the record and the results table.
TIMING_FIELDS = ("render_s", "render_s_min", "render_s_max", "repeats", "megapixels", "ms_per_mpix")


class Failure(str, Enum):
    """Why a cell has no result: decisions read this, never the error's text."""

    #: the method raised, or its image or metrics could not be measured: a result; run again
    #: only when asked (``--retry-failed``)
    METHOD = "method"
    #: the cell's reference failed to render
    REFERENCE = "reference"
    #: the worker process died under the cell (a crash, ``os._exit``, the OOM killer)
    WORKER_DIED = "worker died"
    #: stopped at the time limit
    TIMED_OUT = "timed out"

    @property
    def retried(self) -> bool:
        """Whether a plain rerun runs the cell again (the cause may have been the machine's)."""
        return self in (Failure.WORKER_DIED, Failure.TIMED_OUT)


class RecordError(ValueError):
    """A stored record or results table that this version of aaeval cannot read."""


@dataclass
class CellRecord:
    """One cell: one scene frame rendered by one method spec, measured against its reference."""

    # what was measured (the cell's identity in the config)
    key: str
    group: str
    scene: str  # shown name: file stem or "generator@difficulty"
    scene_source: str
    scene_digest: str
    difficulty: float | None
    difficulty_label: str | None
    method: str
    spec: str  # canonical method spec
    options: dict[str, Any]
    frame: int
    spp: int | None
    seed: int | None
    width: int
    height: int
    # what it was measured against
    reference: str
    reference_key: str
    reference_kind: str  # exact | stochastic | deterministic
    reference_spp: int | None
    reference_seed: int | None
    reference_noise_rmse: float
    reference_intensity_sum: float
    reference_noise: dict[str, float]  # per RMS metric: the truth's noise on that metric's pixels
    # the measurement
    repeats: int
    render_s: float
    render_s_min: float
    render_s_max: float
    megapixels: float
    ms_per_mpix: float
    intensity_sum: float
    metrics: dict[str, float]
    metric_errors: dict[str, str]
    # how and where it ran
    error: str | None
    traceback: str | None
    host: str
    pid: int
    executor: str
    workers: int
    code_version: str
    finished_at: str
    # per RMS metric: fraction of its pixels passing the z-test against the truth (none measured: empty)
    agreement: dict[str, float] = field(default_factory=dict)
    #: why the cell failed (a :class:`Failure` value), None when it did not
    failure: str | None = None
    schema_version: int = field(default=SCHEMA_VERSION)

    def to_json(self) -> dict:
        """A typed-JSON-ready dict (NaN and infinities as their tags)."""
        # encode copies every dict and list, so the fields need no deep copy of their own
        return encode({name: getattr(self, name) for name in RECORD_FIELDS})

    @classmethod
    def from_json(cls, data: Mapping[str, Any], *, where: str = "record") -> "CellRecord":
        """Read a stored record; :class:`RecordError` for another schema, a missing or unknown field."""
        if not isinstance(data, Mapping):
            raise RecordError(f"{where}: a record is a JSON object, got {type(data).__name__}")
        version = data.get("schema_version")
        if version != SCHEMA_VERSION:
            raise RecordError(f"{where}: record schema version {version!r}, this aaeval reads {SCHEMA_VERSION}; "
                              "run the sweep again into a new folder")
        missing = sorted(set(RECORD_FIELDS) - set(data))
        unknown = sorted(set(data) - set(RECORD_FIELDS))
        if missing or unknown:
            raise RecordError(f"{where}: record field(s) missing {missing}, unknown {unknown}")
        problem = field_problem(data)
        if problem:
            raise RecordError(f"{where}: {problem}")
        values = dict(data)
        for name in _NUMBER:
            values[name] = _float(values[name], optional=name not in _FLOAT_FIELDS)
        values["metrics"] = {k: _float(v) for k, v in values["metrics"].items()}
        for name in ("reference_noise", "agreement"):  # null: nothing was measured
            values[name] = {k: _float(v) for k, v in (values[name] or {}).items()}
        return cls(**values)

    def table_row(self) -> dict:
        """The record as one row of ``results.parquet``: one column per field and per metric."""
        row = {name: getattr(self, name) for name in TABLE_FIELDS}
        row["options"] = json.dumps(self.options, sort_keys=True)
        row["metric_errors"] = json.dumps(self.metric_errors, sort_keys=True) if self.metric_errors else None
        for name, value in self.metrics.items():
            row[name] = value
        for name, value in self.reference_noise.items():
            row[noise_column(name)] = value
        for name, value in self.agreement.items():
            row[agreement_column(name)] = value
        return row


def noise_column(metric: str) -> str:
    """The results table's column of the truth's noise on ``metric``'s own pixels."""
    return f"{metric}__noise"


def agreement_column(metric: str) -> str:
    """The results table's column of ``metric``'s z-test pass fraction against the truth."""
    return f"{metric}__agreement"


RECORD_FIELDS = tuple(f.name for f in dataclasses.fields(CellRecord))
#: Columns of ``results.parquet`` that come from record fields (metrics add one column each,
#: RMS metrics two more: :func:`noise_column` and :func:`agreement_column`).
TABLE_FIELDS = tuple(n for n in RECORD_FIELDS if n not in ("metrics", "reference_noise", "agreement"))
_FLOAT_FIELDS = tuple(f.name for f in dataclasses.fields(CellRecord) if f.type == "float")


# The type of every field as stored (strict JSON: a float that is not finite is null).
# Checked on every read, so that a tampered or damaged record is quarantined with its reason
# instead of reaching the table or the report as a string frame, an integer group or a list
# spec (each of which stopped a report or blocked the folder for good).
_STR = ("key", "group", "scene", "scene_source", "scene_digest", "method", "spec", "reference", "reference_key",
        "reference_kind", "host", "executor", "code_version", "finished_at")
_OPTIONAL_STR = ("difficulty_label", "error", "traceback")
_INT = ("frame", "width", "height", "repeats", "pid", "workers")
_OPTIONAL_INT = ("spp", "seed", "reference_spp", "reference_seed")
_NUMBER = ("difficulty", "reference_noise_rmse", "reference_intensity_sum", "render_s", "render_s_min",
           "render_s_max", "megapixels", "ms_per_mpix", "intensity_sum")
#: The largest image a record may name (pixels): a stored array is checked against the
#: record's size before it is read, so this bounds what a read may allocate.
MAX_RECORD_PIXELS = 1 << 28
_MAX_TEXT = 1 << 20  # one field's text: a traceback is a few kB


def _is_int(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value) -> bool:
    """A stored float that is a number or NaN (not measured); an infinite time, size or sum
    is damage."""
    return is_float_value(value) and not math.isinf(decode_float(value))


def _is_metric_value(value) -> bool:
    """A stored metric value: any float (a perfect PSNR is infinite)."""
    return is_float_value(value)


def field_problem(data: Mapping[str, Any]) -> str | None:
    """Why the fields of a stored cell record do not have their schema's types, or None."""
    for name in _STR:
        if not isinstance(data[name], str) or len(data[name]) > _MAX_TEXT:
            return f"field {name!r} must be text, got {_kind(data[name])}"
    for name in _OPTIONAL_STR:
        if data[name] is not None and (not isinstance(data[name], str) or len(data[name]) > _MAX_TEXT):
            return f"field {name!r} must be text or null, got {_kind(data[name])}"
    for name in _INT:
        if not _is_int(data[name]):
            return f"field {name!r} must be a whole number, got {_kind(data[name])}"
    for name in _OPTIONAL_INT:
        if data[name] is not None and not _is_int(data[name]):
            return f"field {name!r} must be a whole number or null, got {_kind(data[name])}"
    for name in _NUMBER:
        if data[name] is not None and not _is_number(data[name]):
            return f"field {name!r} must be a finite number, 'NaN' or null, got {_kind(data[name])}"
    if data["frame"] < 0 or data["repeats"] < 1 or data["workers"] < 1:
        return "fields 'frame' (>= 0), 'repeats' and 'workers' (>= 1) are out of range"
    if not (1 <= data["width"] and 1 <= data["height"] and data["width"] * data["height"] <= MAX_RECORD_PIXELS):
        return f"fields 'width' and 'height' ({data['width']}x{data['height']}) are not an image size a sweep writes"
    if not isinstance(data["options"], dict) or not all(
            isinstance(k, str) and (v is None or isinstance(v, (str, bool)) or _is_int(v) or isinstance(v, float))
            for k, v in data["options"].items()):
        return f"field 'options' must be a table of option = value, got {_kind(data['options'])}"
    if not isinstance(data["metrics"], dict) or not all(
            isinstance(k, str) and (v is None or _is_metric_value(v)) for k, v in data["metrics"].items()):
        return "field 'metrics' must be a table of metric = number, 'NaN', 'Infinity', '-Infinity' or null"
    if data["failure"] is not None and data["failure"] not in {f.value for f in Failure}:
        return f"field 'failure' must be null or one of {[f.value for f in Failure]}, got {_kind(data['failure'])}"
    if (data["failure"] is None) != (data["error"] is None):
        return "fields 'failure' and 'error' must both be set or both null"
    for name in ("reference_noise", "agreement"):
        if data[name] is not None and (not isinstance(data[name], dict) or not all(
                isinstance(k, str) and (v is None or _is_number(v)) for k, v in data[name].items())):
            return f"field {name!r} must be a table of metric = number or null"
    if not isinstance(data["metric_errors"], dict) or not all(
            isinstance(k, str) and isinstance(v, str) for k, v in data["metric_errors"].items()):
        return "field 'metric_errors' must be a table of metric = text"
    return None


def _kind(value) -> str:
    text = repr(value)
    return f"{type(value).__name__} {text[:40]}{'...' if len(text) > 40 else ''}"


def _float(value, optional: bool = False) -> float | None:
    """A stored float (:func:`aaeval.sweeps.typed_json.decode_float`); ``null`` is
    ``None`` where the field is optional, else NaN (what older records wrote for it)."""
    if value is None:
        return None if optional else math.nan
    return decode_float(value)
