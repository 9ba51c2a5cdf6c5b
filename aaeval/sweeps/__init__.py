"""Experiments built on the renderers and metrics: comparisons (``compare``) and sweeps:
configs of scenes x methods x options x frames, run locally or on a Dask cluster into a
folder of crash-proof results, summarised in ``results.parquet``. Both measure through one
engine (:mod:`aaeval.sweeps.measure`) into one record
(:class:`aaeval.sweeps.record.CellRecord`)."""

from aaeval._lazy import lazy_names

# Loaded on first use (PEP 562): a reader of a sweep folder (the report) imports the store
# and the record without loading the renderers the sweep runs.
_EXPORTS = {
    "ConfigError": "config_keys", "Experiment": "config", "load_experiment": "config", "parse_experiment": "config",
    "read_provenance": "provenance",
    "SCHEMA_VERSION": "record", "CellRecord": "record", "RecordError": "record",
    "SweepSummary": "runner", "plan": "runner", "run_sweep": "runner",
    "SweepStore": "store", "code_version": "cache_keys",
    "rebuild_results": "report_files", "write_results": "table",
}

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


__getattr__, __dir__ = lazy_names(__name__, _EXPORTS)
