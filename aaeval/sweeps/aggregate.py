"""The aggregations of a sweep's tables: a group's cells of one spec reduced to one value.

Plain pandas functions of ``results.parquet`` (one row per cell), ``temporal.parquet`` (one
row per animation) and ``speed.parquet`` (one row per timed round). The sweep runs them once
when its tables are written (:mod:`aaeval.sweeps.summaries`) and stores what they give;
the report draws those stored tables and aggregates nothing itself.

Nothing here renders or measures, and nothing imports a registry: a metric's direction
comes in as its :class:`~aaeval.metrics.info.MetricInfo`.
"""

from __future__ import annotations

import math
from typing import Mapping

import pandas as pd

from aaeval.sweeps.record import agreement_column
from aaeval.metrics.info import MetricInfo

__all__ = ["per_spec", "ranked", "failure_definition", "failed_cells", "is_ground_truth", "spec_summary",
           "speed_summary", "megapixels"]


def per_spec(frame: pd.DataFrame, group: str, column: str, *, how: str = "mean",
             noise: str = "reference_noise_rmse") -> pd.DataFrame:
    """One row per spec of ``group``: ``column`` aggregated over its rows (``how``: mean or
    median) with the ground truth's noise beside it; columns spec, label, method, options,
    value, noise, rows, agreement (the mean z-test pass fraction of an RMS metric against
    the truth, :mod:`aaeval.metrics.agreement`; NaN for other columns). The one
    aggregation behind every ranking of the page."""
    columns = ["spec", "label", "method", "options", "ladder", "value", "noise", "rows", "agreement"]
    rows = frame[(frame["group"] == group)] if "group" in frame else frame.iloc[:0]
    if "error" in rows:
        rows = rows[rows["error"].isna()]
    if column not in rows or rows.empty:
        return pd.DataFrame(columns=columns)
    out = []
    for spec, r in rows.groupby("spec", sort=False):
        values = pd.to_numeric(r[column], errors="coerce")
        if not values.notna().any():
            continue
        value = float(values.median() if how == "median" else values.mean())
        truth = pd.to_numeric(r[noise], errors="coerce") if noise in r else pd.Series(dtype=float)
        passed = pd.to_numeric(r[agreement_column(column)], errors="coerce") \
            if agreement_column(column) in r else pd.Series(dtype=float)
        out.append({"spec": spec, "label": r["label"].iloc[0], "method": r["method"].iloc[0],
                    "options": r["options"].iloc[0] if "options" in r else "{}",
                    "ladder": r["ladder"].iloc[0] if "ladder" in r else spec, "value": value,
                    "noise": float(truth.mean()) if truth.notna().any() else math.nan, "rows": int(values.notna().sum()),
                    "agreement": float(passed.mean()) if passed.notna().any() else math.nan})
    return pd.DataFrame(out, columns=columns)


def _better_first(metric: MetricInfo | None):
    if metric is not None and metric.target is not None:
        return lambda v: abs(v - metric.target)
    if metric is not None and metric.higher_is_better:
        return lambda v: -v
    return lambda v: v


def ranked(frame: pd.DataFrame, group: str, column: str, metrics: Mapping[str, MetricInfo], *, how: str = "mean",
           noise: str = "reference_noise_rmse") -> pd.DataFrame:
    """:func:`per_spec`, best first (by the direction of ``metrics[column]``), ties kept in
    spec order."""
    table = per_spec(frame, group, column, how=how, noise=noise)
    if table.empty:
        return table
    key = _better_first(metrics.get(column))
    return table.assign(_k=table["value"].map(key)).sort_values("_k", kind="stable").drop(columns="_k") \
        .reset_index(drop=True)


def failure_definition(primary: str, fail_above) -> str:
    """The one definition of a failed cell, as written on the page."""
    crit = "its render raised an error or gave non-finite pixels"
    if fail_above:
        crit += (f", or, on a flat-coloured scene, its {primary} against its own ground truth (the Mitsuba render "
                 f"through the same pixel filter) is above {fail_above:g}")
    text = f"A cell fails when {crit}."
    if fail_above:
        text += (" On scenes with shaded objects a specular method departs from the Phong truth by design (a clamp "
                 "widens and dims the highlight): that departure is shown as highlight bias and flicker, not counted "
                 "as a failure.")
    return text


def failed_cells(rows: pd.DataFrame, primary: str, fail_above, shaded=frozenset()) -> pd.Series:
    """Boolean per cell, by :func:`failure_definition` (a metric that could not be computed
    is listed apart and is not a failure). ``shaded``: digests of scenes with shaded objects."""
    bad = rows["error"].notna()
    if fail_above and primary in rows:
        flat = ~rows["scene_digest"].isin(set(shaded)) if "scene_digest" in rows else True
        bad |= flat & (pd.to_numeric(rows[primary], errors="coerce") > fail_above)
    return bad


def is_ground_truth(rows: pd.DataFrame) -> pd.Series:
    """Whether each row's reference is a Mitsuba render (the ground truth's renderer)."""
    return rows["reference_method"] == "mitsuba"


def _column(rows: pd.DataFrame, name: str, fallback) -> pd.Series:
    """A results column that older sweep folders may lack."""
    if name in rows and rows[name].notna().any():
        return pd.to_numeric(rows[name], errors="coerce")
    return pd.Series(fallback, index=rows.index, dtype=float)


def megapixels(rows: pd.DataFrame) -> pd.Series:
    size = pd.to_numeric(rows.get("width"), errors="coerce") * pd.to_numeric(rows.get("height"), errors="coerce")
    return _column(rows, "megapixels", size / 1e6)


def spec_summary(rows: pd.DataFrame, metrics: list[str], primary: str, failed: pd.Series) -> pd.DataFrame:
    """One row per spec: cells, failures, times (per frame and per megapixel, with the spread
    of the repeats), mean / best / worst primary error, mean of the other metrics."""
    out = []
    mpix = megapixels(rows)
    for spec, r in rows.groupby("spec", sort=False):
        ok = r[r["error"].isna()]
        t = _column(ok, "render_s", math.nan)
        tmin, tmax = _column(ok, "render_s_min", t), _column(ok, "render_s_max", t)
        mp = mpix.loc[ok.index]
        per = _column(ok, "ms_per_mpix", t * 1e3 / mp)
        row = {"spec": spec, "label": r["label"].iloc[0], "method": r["method"].iloc[0],
               "options": r["options"].iloc[0], "cells": len(r), "failed": int(failed.loc[r.index].sum()),
               "repeats": int(_column(ok, "repeats", 1).min()) if len(ok) else 0,
               "render ms (median)": float(t.median() * 1e3) if len(ok) else math.nan,
               "ms_per_mpix": float(per.median()) if len(ok) else math.nan,
               "ms_per_mpix_min": float((tmin * 1e3 / mp).min()) if len(ok) else math.nan,
               "ms_per_mpix_max": float((tmax * 1e3 / mp).max()) if len(ok) else math.nan}
        if primary in ok:
            vals = pd.to_numeric(ok[primary], errors="coerce")
            row.update({primary: vals.mean(), f"{primary}_min": vals.min(), f"{primary}_max": vals.max()})
        for m in metrics:
            if m != primary and m in ok:
                row[m] = pd.to_numeric(ok[m], errors="coerce").mean()
        out.append(row)
    return pd.DataFrame(out)


def speed_summary(speed: pd.DataFrame) -> pd.DataFrame:
    """One row per (pass, scene, spec) of the speed pass: median, fastest and slowest ms per
    megapixel and render ms."""
    if speed.empty:
        return speed
    ok = speed[speed["error"].isna()]
    keys = ["pass", "scene", "spec"]
    agg = ok.groupby(keys, sort=False).agg(
        label=("label", "first"), method=("method", "first"), options=("options", "first"),
        width=("width", "first"), height=("height", "first"), threads=("threads", "first"),
        rounds=("round", "size"), render_ms=("render_s", lambda s: 1e3 * s.median()),
        ms_per_mpix=("ms_per_mpix", "median"), ms_per_mpix_min=("ms_per_mpix", "min"),
        ms_per_mpix_max=("ms_per_mpix", "max"), accuracy_group=("accuracy_group", "first"))
    return agg.reset_index()
