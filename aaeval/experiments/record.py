"""The one record of a measured cell: written by the measuring engine, stored as a cell
file, read back by the results table and the report.

:class:`CellRecord` is the only definition of its fields. Reading a record checks it: a
field missing or unknown, or another schema version, is a :class:`RecordError` naming the
field, never a silent column of None. The results table (``results.parquet``) has one
column per field (``options`` and ``metric_errors`` as JSON text) and one per metric
(:data:`aaeval.metrics.METRICS`), and carries :data:`SCHEMA_VERSION` in its metadata.

JSON written here is strict JSON: NaN and infinities are written as ``null`` (see
:func:`json_safe`) and read back as NaN for float fields and metric values.

Timing fields: ``render_s`` is the median of ``repeats`` timed renders (after an untimed
warm-up), ``render_s_min``/``render_s_max`` their spread, ``megapixels`` the image size
(width x height / 1e6) and ``ms_per_mpix`` = ``render_s`` x 1000 / ``megapixels``.
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass, field
from typing import Any, Mapping

__all__ = ["SCHEMA_VERSION", "CellRecord", "RecordError", "RECORD_FIELDS", "TABLE_FIELDS", "TIMING_FIELDS",
           "json_safe", "dumps", "noise_column", "agreement_column"]

#: Bump when a field is added, removed or changes meaning.
SCHEMA_VERSION = 3

#: Timing fields, in the record and the results table (issue 10's report reads these names).
TIMING_FIELDS = ("render_s", "render_s_min", "render_s_max", "repeats", "megapixels", "ms_per_mpix")


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
    schema_version: int = field(default=SCHEMA_VERSION)

    def to_json(self) -> dict:
        """A strict-JSON-ready dict (NaN and infinities as None)."""
        return json_safe(dataclasses.asdict(self))

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
        values = dict(data)
        for name in _FLOAT_FIELDS:
            values[name] = _float(values[name])
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


def _float(value) -> float:
    return math.nan if value is None else float(value)


def json_safe(obj: Any) -> Any:
    """``obj`` with every NaN or infinite float replaced by None and numpy scalars made plain.

    JSON has no NaN or Infinity (Python's ``json`` writes them, strict parsers refuse them):
    aaeval writes ``null`` for a value that is not a finite number.
    """
    import numpy as np

    if isinstance(obj, Mapping):
        return {str(k): json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return json_safe(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def dumps(obj: Any, **kwargs) -> str:
    """Strict JSON text of ``obj`` (NaN and infinities as null)."""
    return json.dumps(json_safe(obj), allow_nan=False, **kwargs)
