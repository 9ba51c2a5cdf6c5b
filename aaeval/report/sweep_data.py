"""What the report reads: the files the sweep stored in its folder, and nothing else.

The sweep measured every number and wrote it beside its cells
(:func:`aaeval.sweeps.report_files.write_sweep_files`): ``results.parquet``, ``temporal.parquet``,
``speed.parquet``, ``metrics.json`` (each metric's title, format and direction),
``specs.json`` (each spec's options, each method's choices and speed baseline),
``controls.json``, ``specular_detection.npz`` and, in ``summaries/``, every table the page
shows, aggregated by the sweep (:mod:`aaeval.sweeps.summaries`). :func:`read_sweep`
loads them once;
:data:`METRICS` then describes the sweep's metrics (:class:`~aaeval.metrics.info.MetricInfo`)
for every section that formats or labels a value.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from aaeval.sweeps.record import RecordError
from aaeval.sweeps.store import SweepStore, read_table
from aaeval.sweeps.summaries import SUMMARIES, SUMMARY_FOLDER
from aaeval.metrics.info import MetricInfo

__all__ = ["SweepData", "read_sweep", "use_metrics", "METRICS"]

#: The metrics of the sweep being drawn, by name (filled by :func:`use_metrics`).
METRICS: dict[str, MetricInfo] = {}


def use_metrics(root: str | Path) -> dict[str, MetricInfo]:
    """Describe the metrics by the sweep folder ``root``'s ``metrics.json``."""
    found = _json(Path(root) / "metrics.json")
    METRICS.clear()
    METRICS.update({name: MetricInfo.from_dict(entry) for name, entry in found.items()})
    return METRICS


@dataclass
class SweepData:
    """Everything one report draws from."""

    store: SweepStore
    manifest: dict
    results: pd.DataFrame
    temporal: pd.DataFrame
    speed: pd.DataFrame
    specs: dict = field(default_factory=dict)
    controls: dict = field(default_factory=dict)
    detection: dict | None = None
    summaries: dict[str, pd.DataFrame] = field(default_factory=dict)

    def summary(self, name: str) -> pd.DataFrame:
        """The stored summary ``name`` (:data:`~aaeval.sweeps.summaries.SUMMARIES`);
        its index is the stored row."""
        return self.summaries[name]


def _json(path: Path):
    if not path.is_file():
        raise RecordError(f"{path.parent} has no {path.name}: the sweep writes it with its tables when it ends; "
                          "run 'aaeval sweep CONFIG --out DIR' again (it resumes: finished cells are kept)")
    return json.loads(path.read_text())


def _table(path: Path) -> pd.DataFrame:
    return read_table(path) if path.is_file() else pd.DataFrame()


def read_sweep(directory: str | Path) -> SweepData:
    """The stored files of a sweep folder (:class:`RecordError` naming a missing one)."""
    store = SweepStore(directory)
    root = store.root
    manifest = store.read_manifest()  # first: a folder that is no sweep is named as such
    if not (root / "results.parquet").is_file():
        _json(root / "results.parquet")  # the one message for a table the sweep has not written
    use_metrics(root)
    detection = None
    if (root / "specular_detection.npz").is_file():
        with np.load(root / "specular_detection.npz") as found:
            detection = {k: found[k] for k in found.files}
    speed = pd.read_parquet(root / "speed.parquet") if (root / "speed.parquet").is_file() else pd.DataFrame()
    summaries = {}
    for name in SUMMARIES:
        path = root / SUMMARY_FOLDER / f"{name}.parquet"
        if not path.is_file():
            _json(path)  # the one message for a table the sweep has not written
        summaries[name] = pd.read_parquet(path).reset_index(drop=True)
    return SweepData(store, manifest, read_table(root / "results.parquet"), _table(root / "temporal.parquet"),
                     speed, _json(root / "specs.json"), _json(root / "controls.json"), detection, summaries)
