"""The HTML report of a sweep folder: one self-contained ``index.html`` (inline CSS, no
scripts, nothing fetched) with its figures as PNG files in ``DIR/figures/``.

Every comparison says what it compares against: the reference spec, whether it is exact
or how noisy it is (measured), and the spp and seed of sampled methods.
"""

from __future__ import annotations

import html
import json
import math
import time
from pathlib import Path

import numpy as np
import pandas as pd

from aaeval.experiments.store import SweepStore
from aaeval.experiments.table import load_results, short_label, varying_options
from aaeval.report.names import figure_stem
from aaeval.imageio import atomic_write
from aaeval.report import figures

__all__ = ["write_report", "reference_statement", "spec_summary"]

_CSS = """
body{font-family:system-ui,sans-serif;max-width:1250px;margin:1.5em auto;padding:0 1em;color:#222}
h1{margin-bottom:.2em} h2{border-bottom:2px solid #ccc;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;font-size:12px;margin:.6em 0;display:block;overflow-x:auto;max-width:100%} td,th{border:1px solid #ccc;padding:2px 6px}
th{background:#f0f0f0} td.num{text-align:right;font-family:monospace}
.note{background:#f6f8fa;border-left:4px solid #888;padding:.4em .8em;font-size:13px}
.ref{background:#fff8e0;border-left:4px solid #d9a400;padding:.4em .8em;font-size:13px}
figure{margin:1em 0} figcaption{font-size:12px;color:#444;max-width:1000px} img{max-width:100%}
.bad{color:#b00}
"""


def _fmt(value) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, (float, np.floating)):
        return f"{value:.4g}"
    return html.escape(str(value))


def _table(frame: pd.DataFrame) -> str:
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in frame.columns)
    body = []
    for _, row in frame.iterrows():
        cells = "".join(
            f"<td class='num'>{_fmt(v)}</td>" if isinstance(v, (int, float, np.number)) and not isinstance(v, bool)
            else f"<td>{_fmt(v)}</td>" for v in row)
        body.append(f"<tr>{cells}</tr>")
    return f"<table><tr>{head}</tr>{''.join(body)}</table>"


def reference_statement(rows: pd.DataFrame) -> str:
    """What the cells in ``rows`` were compared against, with its noise level."""
    parts = []
    for spec, refs in rows.groupby("reference", sort=False):
        kind = refs["reference_kind"].iloc[0]
        spp, seed = refs["reference_spp"].iloc[0], refs["reference_seed"].iloc[0]
        noise = refs["reference_noise_rmse"].astype(float)
        if kind == "exact":
            level = "noise 0"
        elif noise.notna().any():
            level = (f"noise RMS {noise.mean():.3g} per pixel channel (measured against a second render with "
                     f"the next seed; mean over {noise.notna().sum()} frames)")
        else:
            level = "deterministic but not exact: its own error is unknown"
        extra = ", ".join(f"{k} {int(v)}" for k, v in (("spp", spp), ("seed", seed)) if pd.notna(v))
        parts.append(f"<b>{html.escape(short_label(spec))}</b> ({kind}{'; ' + extra if extra else ''}; {level})")
    return "Reference: " + "; ".join(parts) + "."


def _ladder_labels(summary: pd.DataFrame) -> pd.Series:
    """Point labels for a chart whose legend names the method: the options that vary."""
    labels = pd.Series("", index=summary.index, dtype=object)
    for _, rows in summary.groupby("method"):
        keys = varying_options(rows["options"])
        for idx, options in zip(rows.index, rows["options"]):
            o = json.loads(options)
            labels[idx] = ",".join(f"{k}={o[k]}" for k in keys)
    return labels


def spec_summary(rows: pd.DataFrame, metrics: list[str], primary: str) -> pd.DataFrame:
    """One row per spec: cells, failures, median time, mean (and worst) error, noise context."""
    out = []
    for spec, r in rows.groupby("spec", sort=False):
        ok = r[r["error"].isna()]
        row = {"label": r["label"].iloc[0], "method": r["method"].iloc[0], "options": r["options"].iloc[0],
               "cells": len(r), "failed": int(r["error"].notna().sum()),
               "render_s (median)": ok["render_s"].median(),
               "spp": r["spp"].iloc[0], "seed": r["seed"].iloc[0]}
        for m in metrics:
            row[f"{m} (mean)"] = ok[m].mean() if m in ok else math.nan
        row[f"{primary} (worst)"] = ok[primary].max() if primary in ok else math.nan
        noise = r["reference_noise_rmse"].astype(float).mean()
        row["reference"] = short_label(r["reference"].iloc[0])
        row["ref noise RMS"] = noise
        if primary == "rmse" and noise > 0:
            # an error this close to the reference's own noise is not a measured difference
            row["rmse / ref noise"] = row["rmse (mean)"] / noise
        out.append(row)
    return pd.DataFrame(out)


def _figure(path: Path, root: Path, caption: str) -> str:
    rel = path.relative_to(root).as_posix()
    return f"<figure><img src='{html.escape(rel)}' alt='{html.escape(path.stem)}'><figcaption>{caption}</figcaption></figure>"


def _metric_columns(results: pd.DataFrame, manifest: dict) -> list[str]:
    return [m for m in manifest.get("metrics", []) if m in results.columns]


def _timing_note(results: pd.DataFrame) -> str:
    execs = sorted({str(e) for e in results.get("executor", pd.Series(dtype=str)).dropna()})
    hosts = sorted({str(h) for h in results["host"].dropna()})
    return (f"Render times are per frame, JIT compilation excluded (each worker warms a method up before "
            f"timing it), measured on {', '.join(map(html.escape, hosts)) or 'unknown host'} with "
            f"{', '.join(map(html.escape, execs)) or 'unknown executor'}; workers running side by side share "
            f"the machine, so compare times within one sweep, not across machines.")


def _group_section(group: str, rows: pd.DataFrame, temporal: pd.DataFrame, store: SweepStore, figdir: Path,
                   metrics: list[str], temporal_names: list[str], primary: str, fail_above) -> str:
    out = [f"<h2 id='{html.escape(group)}'>{html.escape(group)}</h2>"]
    ref = reference_statement(rows)
    out.append(f"<p class='ref'>{ref} Methods' spp and seed are in their specs and in the table.</p>")
    slug = figure_stem(group)  # unique per name: "fence a" and "fence-a" must not share files
    ok = rows[rows["error"].isna()]
    summary = spec_summary(rows, metrics, primary)

    speed = summary.dropna(subset=["render_s (median)", f"{primary} (mean)"]).reset_index(drop=True)
    if len(speed) >= 2:
        speed = speed.rename(columns={"render_s (median)": "render_s", f"{primary} (mean)": primary})
        speed["label"] = _ladder_labels(speed)
        p = figures.speed_accuracy(speed, figdir / f"{slug}_speed_accuracy.png", metric=primary,
                                   title=f"{group}: speed against accuracy")
        out.append(_figure(p, store.root, f"Speed against accuracy over {len(ok)} cells. {ref} Lines join the "
                   "option ladder of one method (Mitsuba's spp, supersampling's k); the dashed step is the Pareto "
                   f"front. Errors below {figures.ERROR_FLOOR:g} (exact methods) are drawn at that floor."))

    animated = ok[ok.groupby(["scene", "spec"])["frame"].transform("nunique") > 1]
    if not animated.empty:
        p = figures.intensity_sums(animated, figdir / f"{slug}_intensity_sum.png",
                                   title=f"{group}: intensity sum per frame")
        out.append(_figure(p, store.root, f"Intensity sum of every frame, divided by the reference's frame 0. "
                   f"{ref} Area sampling keeps the sum constant while the scene moves inside the frame."))
    temp = temporal[temporal["group"] == group] if not temporal.empty else temporal
    names = [m for m in temporal_names if m in temp.columns]
    if not temp.empty and names:
        p = figures.temporal_bars(temp, figdir / f"{slug}_temporal.png", metrics=names,
                                  title=f"{group}: {' and '.join(names)} per method")
        out.append(_figure(p, store.root, f"{', '.join(names)} per method, mean over "
                   f"{temp['scene'].nunique()} animated scene(s). {ref} Reference's own sum variation: "
                   f"{temp['reference_sum_variation'].max():.3g} (max over scenes)."))
        cols = ["scene", "label", "frames", "failed_frames", *names, "reference_sum_variation", "reference",
                "reference_noise_rmse"]
        shown = temp.assign(reference=temp["reference"].map(short_label))
        out.append(_table(shown[[c for c in cols if c in shown.columns]]))

    if rows["difficulty"].nunique() >= 3:  # a trend needs a few levels
        p = figures.stability(rows, figdir / f"{slug}_stability.png", metric=primary, fail_above=fail_above,
                              title=f"{group}: error and failures as difficulty grows")
        crit = "raised an error" + (f" or had {primary} above {fail_above:g}" if fail_above else "")
        out.append(_figure(p, store.root, f"Mean {primary} and fraction of failed cells (a cell fails when it "
                   f"{crit}) against difficulty. {ref}"))

    grid = _grid(rows, ok, store, figdir / f"{slug}_images.png", group, ref)
    if grid:
        out.append(grid)

    out.append("<h3>Numbers per method</h3>")
    out.append(_table(summary.drop(columns=["method", "options"]).rename(
        columns={"label": "method (non-default options)"})))
    spoiled = rows[rows["metric_errors"].notna()] if "metric_errors" in rows else rows.iloc[:0]
    if not spoiled.empty:
        out.append(f"<h3 class='bad'>Metrics that could not be computed ({len(spoiled)} cells)</h3>")
        out.append(_table(spoiled[["scene", "label", "frame", "metric_errors"]]))
    failed = rows[rows["error"].notna()]
    if not failed.empty:
        out.append(f"<h3 class='bad'>Failed cells ({len(failed)})</h3>")
        out.append(_table(failed[["scene", "label", "frame", "error", "host"]]))
    return "\n".join(out)


def _grid(rows, ok, store, path: Path, group: str, ref: str) -> str:
    """Image grid of the hardest scene's middle frame (largest mean error)."""
    if ok.empty:
        return ""
    by_scene = ok.groupby("scene")["render_s"].size()
    scene = by_scene.index[0]
    if ok["difficulty"].notna().any():
        scene = ok.loc[ok["difficulty"].idxmax(), "scene"]
    frames = sorted(ok[ok["scene"] == scene]["frame"].unique())
    frame = frames[len(frames) // 2]
    cells = ok[(ok["scene"] == scene) & (ok["frame"] == frame)].drop_duplicates("spec").head(12)
    reference = store.load_reference(store.read_cell(cells["key"].iloc[0])["reference_key"])
    images = [(label, store.load_image(key)) for label, key in zip(cells["label"], cells["key"])]
    images = [(s, im) for s, im in images if im is not None]
    if reference is None or not images:
        return ""
    p = figures.image_grid(reference, images, path, title=f"{group}: {scene}, frame {frame}")
    return _figure(p, store.root, f"{html.escape(scene)}, frame {frame}: each method's image, the same zoomed "
                   f"crop (red box, around the largest error) and its |error| map on one colour scale. {ref}")


def _overview(results: pd.DataFrame, primary: str, fail_above) -> str:
    """Where each method fails: failed cells and mean error per method (rows) and group."""
    frame = results.assign(method_=results["method"])
    bad = frame["error"].notna()
    if fail_above:
        bad |= frame[primary].astype(float) > fail_above
    failures = frame.assign(bad=bad).pivot_table(index="method_", columns="group", values="bad", aggfunc="sum",
                                                 sort=False)
    errors = frame.pivot_table(index="method_", columns="group", values=primary, aggfunc="mean", sort=False)
    crit = "raised an error" + (f" or {primary} > {fail_above:g}" if fail_above else "")
    return (f"<h2>Overview</h2><p>Mean {html.escape(primary)} per method (all its options) and group; each "
            f"group's reference is stated in its section.</p>"
            + _table(errors.reset_index().rename(columns={"method_": "method"}))
            + f"<p>Failed cells per method and group (a cell fails when it {html.escape(crit)}).</p>"
            + _table(failures.fillna(0).astype(int).reset_index().rename(columns={"method_": "method"})))


def write_report(directory: str | Path, *, quiet: bool = True) -> Path:
    """Write ``DIR/index.html`` (and ``DIR/figures/*.png``) for the sweep folder ``DIR``."""
    from aaeval.experiments.runner import progress_bar

    store = SweepStore(directory)
    manifest = store.read_manifest()
    results, temporal = load_results(store)
    figdir = store.root / "figures"
    figdir.mkdir(parents=True, exist_ok=True)
    primary = manifest.get("primary", "rmse")
    metrics = _metric_columns(results, manifest)
    distinct = {c["key"] for c in manifest["cells"]}
    n_failed = int(results.drop_duplicates("key")["error"].notna().sum()) if not results.empty else 0
    done = results["key"].nunique() if not results.empty else 0

    parts = [f"<h1>{html.escape(manifest['experiment'])}</h1>",
             f"<p>{html.escape(manifest.get('description', ''))}</p>",
             f"<p class='note'>{done} of {len(distinct)} distinct cells finished ({n_failed} failed, "
             f"{len(distinct) - done} pending). Code version {html.escape(manifest.get('code_version', '?'))}. "
             f"Generated {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. "
             + (_timing_note(results) if not results.empty else "") + "</p>",
             "<p>Data: <a href='results.parquet'>results.parquet</a> (one row per cell), "
             "<a href='temporal.parquet'>temporal.parquet</a> (one row per animation), "
             "<a href='experiment.toml'>experiment.toml</a> (the config as run), "
             "<a href='manifest.json'>manifest.json</a>.</p>"]
    groups = list(dict.fromkeys(c["group"] for c in manifest["cells"]))
    parts.append("<p>Groups: " + ", ".join(f"<a href='#{html.escape(g)}'>{html.escape(g)}</a>" for g in groups)
                 + "</p>")
    if not results.empty:
        parts.append(_overview(results, primary, manifest.get("fail_above")))
    with progress_bar(quiet) as progress:
        task = progress.add_task("report", total=len(groups)) if progress else None
        for group in groups:
            rows = results[results["group"] == group] if not results.empty else results
            if rows.empty:
                parts.append(f"<h2 id='{html.escape(group)}'>{html.escape(group)}</h2><p>No finished cells yet.</p>")
            else:
                parts.append(_group_section(group, rows, temporal, store, figdir, metrics,
                                            manifest.get("temporal", []), primary,
                                            manifest.get("fail_above")))
            if task is not None:
                progress.advance(task)
    page = ("<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
            f"<title>{html.escape(manifest['experiment'])} — aaeval report</title><style>{_CSS}</style></head>"
            f"<body>{''.join(parts)}</body></html>\n")
    index = store.root / "index.html"
    atomic_write(index, lambda tmp: Path(tmp).write_text(page))
    return index
