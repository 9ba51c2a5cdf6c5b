"""The tidy results tables, rebuilt from the cell files at any time.

``results.parquet``: one row per (group, cell) of the manifest that has finished: scene,
method, options, frame, every metric, render_s, host, error, and what the comparison was
against (reference, its spp, seed and noise level).
``temporal.parquet``: one row per (group, scene, method) animation whose frames have all
finished: the temporal metrics (``sum_variation``, ``flicker``) over its frames.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd

from aaeval.experiments.metrics import temporal_metric
from aaeval.experiments.store import SweepStore
from aaeval.imageio import atomic_write

__all__ = ["results_frame", "temporal_frame", "write_results", "load_results", "short_label", "varying_options"]

_COLUMNS = ["group", "scene", "method", "spec", "options", "frame", "difficulty", "difficulty_label",
            "render_s", "intensity_sum", "reference", "reference_kind", "reference_spp", "reference_seed",
            "reference_noise_rmse", "reference_intensity_sum", "spp", "seed", "host", "error", "key",
            "scene_source", "code_version", "finished_at", "width", "height", "executor", "workers"]


def results_frame(store: SweepStore) -> pd.DataFrame:
    manifest = store.read_manifest()
    rows = manifest["cells"]
    records = store.records({r["key"] for r in rows})
    out = []
    for row in rows:
        rec = records.get(row["key"])
        if rec is None:
            continue
        flat = {c: rec.get(c) for c in _COLUMNS}
        flat["group"] = row["group"]
        flat["options"] = json.dumps(rec.get("options", {}), sort_keys=True)
        flat["metric_errors"] = json.dumps(rec["metric_errors"]) if rec.get("metric_errors") else None
        for name, value in rec.get("metrics", {}).items():
            flat[name] = math.nan if value is None else value
        out.append(flat)
    frame = pd.DataFrame(out, columns=None if out else _COLUMNS)
    frame["label"] = _labels(frame) if out else pd.Series(dtype=object)
    for col in ("render_s", "intensity_sum", "reference_noise_rmse", "reference_intensity_sum", "difficulty",
                "spp", "seed", "reference_spp", "reference_seed"):
        if col in frame:
            frame[col] = pd.to_numeric(frame[col], errors="coerce")
    return frame


# Options that only say how a result was obtained, not what was rendered.
_INCIDENTAL = {"cache"}


def short_label(spec: str, keep: set[str] = frozenset()) -> str:
    """The spec with the options in ``keep`` and those that differ from the defaults."""
    from aaeval.renderers import MethodError, resolve

    try:
        method, options = resolve(spec)
    except MethodError:  # a method this checkout lacks: show the spec as stored
        return spec
    shown = {k: v for k, v in options.items()
             if k not in _INCIDENTAL and (k in keep or v != method.options[k].default)}
    # written out here: format_spec leaves defaults out, and a varying option must show
    return method.name + "".join(f"{':' if i == 0 else ','}{k}={shown[k]}" for i, k in enumerate(sorted(shown)))


def varying_options(options_json) -> list[str]:
    """The option names whose values differ between these JSON option tables."""
    opts = [json.loads(o) for o in options_json]
    return sorted(k for k in set().union(*opts) if len({json.dumps(o.get(k)) for o in opts}) > 1)


def _labels(frame: pd.DataFrame) -> pd.Series:
    """Short labels: per group and method, the options that vary or are not the default."""
    labels = pd.Series(index=frame.index, dtype=object)
    for _, rows in frame.groupby(["group", "method"], sort=False):
        varying = set(varying_options(rows["options"]))
        for idx, spec in zip(rows.index, rows["spec"]):
            labels[idx] = short_label(spec, varying)
    return labels


def temporal_frame(store: SweepStore, results: pd.DataFrame) -> pd.DataFrame:
    manifest = store.read_manifest()
    names = manifest.get("temporal", [])
    out = []
    if results.empty or not names:
        return pd.DataFrame(out)
    expected = {}
    for row in manifest["cells"]:
        expected.setdefault((row["group"], row["scene"], row["spec"]), set()).add(row["frame"])
    for (group, scene, spec), series in results.groupby(["group", "scene", "spec"], sort=False):
        frames = expected.get((group, scene, spec), set())
        if len(frames) < 2 or set(series["frame"]) != frames:
            continue  # not an animation, or not finished
        series = series.sort_values("frame")
        row = {"group": group, "scene": scene, "spec": spec, "label": series["label"].iloc[0],
               "method": series["method"].iloc[0],
               "frames": len(series), "reference": series["reference"].iloc[0],
               "reference_noise_rmse": series["reference_noise_rmse"].iloc[0],
               "failed_frames": int(series["error"].notna().sum()),
               "reference_sum_variation": _variation(series["reference_intensity_sum"])}
        ok = series[series["error"].isna()]
        tests = [store.load_image(k) for k in ok["key"]]
        refs = [store.load_reference(k) for k in _reference_keys(store, ok["key"])]
        for name in names:
            try:
                row[name] = temporal_metric(name, refs, tests) if len(ok) == len(series) else math.nan
            except (ValueError, TypeError):
                row[name] = math.nan
        out.append(row)
    return pd.DataFrame(out)


def _variation(sums: pd.Series) -> float:
    s = np.asarray(sums, dtype=float)
    if not np.all(np.isfinite(s)) or s.mean() == 0:
        return math.nan
    return float(np.ptp(s) / abs(s.mean()))


def _reference_keys(store: SweepStore, keys) -> list[str]:
    return [store.read_cell(k)["reference_key"] for k in keys]


def write_results(store: SweepStore) -> pd.DataFrame:
    """Rebuild ``results.parquet`` and ``temporal.parquet`` from the cell files."""
    results = results_frame(store)
    temporal = temporal_frame(store, results)
    atomic_write(store.root / "results.parquet", lambda tmp: results.to_parquet(tmp, index=False))
    atomic_write(store.root / "temporal.parquet", lambda tmp: temporal.to_parquet(tmp, index=False))
    return results


def load_results(store: SweepStore) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Both tables, rebuilt first so they match the cell files on disk."""
    results = write_results(store)
    temporal = pd.read_parquet(store.root / "temporal.parquet")
    return results, temporal
