"""Experiments built on the renderers and metrics: comparisons (``compare``) and sweeps:
configs of scenes x methods x options x frames, run locally or on a Dask cluster into a
folder of crash-proof results, summarised in ``results.parquet``. Both measure through one
engine (:mod:`aaeval.experiments.measure`) into one record
(:class:`aaeval.experiments.record.CellRecord`)."""

from aaeval.experiments.config import ConfigError, Experiment, load_experiment, parse_experiment
from aaeval.experiments.provenance import read_provenance
from aaeval.experiments.record import SCHEMA_VERSION, CellRecord, RecordError
from aaeval.experiments.runner import SweepSummary, plan, run_sweep
from aaeval.experiments.store import SweepStore, code_version
from aaeval.experiments.table import rebuild_results, write_results

__all__ = [
    "CellRecord",
    "ConfigError",
    "RecordError",
    "SCHEMA_VERSION",
    "read_provenance",
    "Experiment",
    "SweepStore",
    "SweepSummary",
    "code_version",
    "load_experiment",
    "rebuild_results",
    "parse_experiment",
    "plan",
    "run_sweep",
    "write_results",
]
