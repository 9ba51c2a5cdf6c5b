"""The summary tables of a sweep: every table the report shows, aggregated once by the sweep.

When a sweep writes its tables (:func:`aaeval.sweeps.report_files.write_sweep_files`, and again
after its speed pass, :func:`~aaeval.sweeps.report_files.write_summary_tables`) it reduces them with :mod:`aaeval.sweeps.aggregate` and stores
each summary as ``DIR/summaries/<name>.parquet`` (:data:`SUMMARIES`). The report reads these
and draws; each number on its page names the stored table, row and column it shows
(``data-source``, ``data-row``, ``data-column``), which the tests look up.

- ``specs``: one row per (group, spec): cells, failures, times, mean / best / worst primary
  error and the mean of every other metric (also the overview, pivoted by the report).
- ``references``: one row per (group, reference): what it is, spp, seed, its measured noise
  (mean, min, max over its frames) and whether it is, or is cross-checked against, the
  Mitsuba ground truth.
- ``validation``: exact methods against a Mitsuba ground truth, per (group, method).
- ``speed``: one row per (pass, scene, spec) of the speed pass.
- ``specular`` and ``filters``: the tables of those two studies, one row per (group, spec).
- ``findings``, ``findings_questions``, ``findings_per_scene``: the ranked table of each
  question of :data:`QUESTIONS` in every group that measured it (with the truth it is judged
  against), which groups answer it, and its values per scene.
- ``space_time``: the image row each animated group's space-time figure slices.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from aaeval.sweeps.aggregate import (failed_cells, is_ground_truth, per_spec, ranked, spec_summary,
                                          speed_summary)
from aaeval.sweeps.record import agreement_column, noise_column
from aaeval.metrics.agreement import agrees, truth_of
from aaeval.metrics.info import MetricInfo

__all__ = ["SUMMARIES", "SUMMARY_FOLDER", "Question", "QUESTIONS", "summarize", "cross_check",
           "agreement_text", "FILTER_GROUP_PREFIX", "FILTER_ORDER", "SPECULAR_COLUMNS", "VALIDATION_RATIO",
           "speed_groups", "shaded_groups", "changing_row", "per_scene_values", "frame_noise", "group_truth",
           "measured_noise"]

SUMMARY_FOLDER = "summaries"
SUMMARIES = ("specs", "references", "validation", "speed", "specular", "filters", "findings", "findings_questions",
             "findings_per_scene", "space_time")
#: An exact method "matches" the ground truth when its error is within this factor of the noise.
VALIDATION_RATIO = 1.5
#: The specular study's columns: registered metric names (error, bias, flicker).
SPECULAR_COLUMNS = ("highlight_rmse", "highlight_bias", "highlight_profile_flicker")
FILTER_GROUP_PREFIX = "filters"
FILTER_ORDER = ("box", "tent", "bspline", "mitchell", "catmullrom", "gaussian")
_FILTER_RESULTS = ("rmse",)
_FILTER_TEMPORAL = ("temporal_bias", "flicker", "image_flicker")


@dataclass(frozen=True)
class Question:
    """One question of the findings: which column of which table answers it, where."""

    key: str
    title: str
    table: str  # "results" or "temporal" (or "speed": the speed pass)
    column: str
    groups: tuple[str, ...]  # groups that answer it, first present wins
    extra: tuple[tuple[str, str], ...] = ()  # further columns beside it: (table, column)
    what: str = ""
    noise: str = "reference_noise_rmse"  # the ground truth's own value of this kind, beside each number
    per_scene: bool = False  # also a table of each scene's values: a mean over unlike scenes hides them


QUESTIONS = (
    Question("edges", "Edge aliasing", "results", "edge_rmse", ("edge-aliasing", "khan-figures-moving"),
             what="error over the pixels a visible edge crosses, mean over scenes and frames"),
    Question("highlights", "Highlight aliasing", "results", "highlight_rmse", ("specular-thin", "specular"),
             extra=(("temporal", "highlight_bias"), ("temporal", "highlight_profile_flicker")),
             what="error over the highlight pixels, mean over scenes and frames; beside it the highlight's bias "
                  "(time-average of its energy error) and flicker (what is left, frame to frame)"),
    Question("temporal", "Temporal stability", "temporal", "flicker", ("edge-aliasing", "khan-figures-moving"),
             extra=(("temporal", "temporal_bias"), ("temporal", "cvvdp")),
             what="flicker of the error over each animation (the error minus its time-average), mean over "
                  "animations; beside it the bias (the time-average) and, where the group measures it, "
                  "ColorVideoVDP's JOD (10: no visible difference)"),
    Question("highlight-flicker", "Temporal stability of highlights", "temporal", "highlight_profile_flicker",
             ("specular-thin", "specular"), extra=(("temporal", "highlight_bias"),),
             what="spread over frames of each highlight cross-section's energy error, relative, mean over animations; "
                  "beside it the highlight's bias"),
    Question("sums", "Sum invariance", "temporal", "sum_variation", ("invariance", "edge-aliasing"),
             extra=(("temporal", "sum_bias"),), per_scene=True,
             what="(max - min) / mean of the image's intensity sum while the scene moves, mean over animations; "
                  "beside it the sum's bias against the exact sum in the typical frame (median over frames), and "
                  "the ground truth's own variation", noise="reference_sum_variation"),
    Question("cost", "Cost", "speed", "ms_per_mpix", ("speed",),
             what="render time per megapixel in the speed pass (one worker, interleaved repeats after a "
                  "warm-up), median over its scenes and rounds"),
    Question("cost-shading", "Cost of specular anti-aliasing", "speed", "ms_per_mpix", ("speed-1",),
             what="render time per megapixel of every specular method in the speed pass's second table, median "
                  "over its scenes and rounds"),
)


def agreement_text(fraction: float) -> str:
    """The z-test verdict of a mean pass fraction as the page writes it ("" when untested)."""
    verdict = agrees(fraction)
    if verdict is None:
        return ""
    return f"{'agrees' if verdict else 'differs'} ({fraction:.2%} pass)"


def frame_noise(rows: pd.DataFrame) -> pd.Series:
    """The ground truth's measured noise of each scene frame of ``rows`` (once per frame)."""
    return rows.drop_duplicates(["scene", "frame"])["reference_noise_rmse"].astype(float)


def measured_noise(rows: pd.DataFrame) -> pd.Series:
    """Each row's reference noise where its reference is a seeded truth, NaN where it is
    noise-free (:func:`aaeval.metrics.agreement.truth_of`): an exact truth's error bound is no
    noise to draw as a band or to set an axis by."""
    level = rows["reference_noise_rmse"].astype(float)
    if "reference_kind" not in rows:
        return level
    seeded = [truth_of(str(k), v).kind == "seeded" for k, v in zip(rows["reference_kind"], level)]
    return level.where(pd.Series(seeded, index=rows.index, dtype=bool))


def cross_check(rows: pd.DataFrame) -> tuple[str, bool] | None:
    """For a group judged against an exact truth: its Mitsuba row of the most samples and
    that row's z-test verdict against the truth (within the row's own noise,
    :mod:`aaeval.sweeps.measure`), on the highlight pixels where the group measures them
    (what the exact shading is for), with the whole image's pass fraction beside it, and
    whether it agrees; None without such a row."""
    mitsuba = rows[rows["method"] == "mitsuba"]
    if mitsuba.empty:
        return None
    spp = mitsuba["spp"].fillna(0)
    best = mitsuba[spp == spp.max()]

    def passed(metric: str) -> float:
        column = agreement_column(metric)
        return pd.to_numeric(best[column], errors="coerce").mean() if column in best else math.nan

    judged, where = (passed("highlight_rmse"), "highlight pixels")
    if not math.isfinite(judged):
        judged, where = (passed("rmse"), "whole image")
    if not math.isfinite(judged):
        return None
    verdict = "agrees" if agrees(judged) else "DIFFERS"
    whole = passed("rmse")
    beside = f"; whole image {whole:.2%}" if where != "whole image" and math.isfinite(whole) else ""
    return (f"exact, cross-checked by {best['label_plain'].iloc[0]} on {where}: {verdict} ({judged:.2%} pass{beside})",
            agrees(judged))


def _references(results: pd.DataFrame) -> pd.DataFrame:
    out = []
    for group, rows in results.groupby("group", sort=False):
        for spec, refs in rows.groupby("reference", sort=False):
            noise = frame_noise(refs)
            truth = bool(is_ground_truth(refs).iloc[0])
            checked = None if truth else cross_check(rows)
            out.append({"group": group, "reference": spec, "reference_label": refs["reference_label"].iloc[0],
                        "kind": str(refs["reference_kind"].iloc[0]), "is_ground_truth": truth,
                        "Mitsuba ground truth": "yes" if truth else checked[0] if checked else "NO (unvalidated)",
                        # judged against the Mitsuba truth, or an exact one its Mitsuba row agrees with
                        "validated": truth or bool(checked and checked[1]),
                        "spp": refs["reference_spp"].iloc[0], "seed": refs["reference_seed"].iloc[0],
                        "noise_mean": noise.mean(), "noise_min": noise.min(), "noise_max": noise.max(),
                        "noise_frames": int(noise.notna().sum()), "noise_positive": bool(noise.fillna(0).gt(0).any())})
    return pd.DataFrame(out)


def validation_rows(rows: pd.DataFrame, shaded: set[str]) -> pd.DataFrame:
    """Exact methods against a Mitsuba ground truth: one row per scene frame and spec, on
    flat scenes only (``shaded``: digests of scenes with smooth-shaded objects, where an
    exact method's coverage is exact but its shading is one Phong shade per visible piece)."""
    ok = rows[rows["error"].isna() & is_ground_truth(rows)]
    if "scene_digest" in ok:
        ok = ok[~ok["scene_digest"].isin(shaded)]
    exact = ok[ok["exact"].astype(bool)]
    if exact.empty:
        return pd.DataFrame()
    # an exact render with another pixel filter (catmull:filter=tent) is exact for that
    # filter, not for the box-filtered ground truth: it is no check of the ground truth
    exact = exact[exact["reference_filter"] == exact["filter"]]
    if exact.empty or "rmse" not in exact:
        return pd.DataFrame()
    return pd.DataFrame({"group": exact["group"], "scene": exact["scene"], "frame": exact["frame"],
                         "method": exact["method"], "options": exact["options"], "label": exact["label"],
                         "rmse": pd.to_numeric(exact["rmse"], errors="coerce"),
                         "noise_rmse": exact["reference_noise_rmse"].astype(float)})


def _validation(results: pd.DataFrame, shaded: set[str]) -> pd.DataFrame:
    check = validation_rows(results, shaded)
    if check.empty:
        return pd.DataFrame()
    table = (check.assign(ratio=check["rmse"] / check["noise_rmse"])
             .groupby(["group", "label"], sort=False)
             .agg(frames=("frame", "size"), rmse_mean=("rmse", "mean"), noise_mean=("noise_rmse", "mean"),
                  ratio_max=("ratio", "max")).reset_index())
    table["agrees within noise"] = np.where(table["ratio_max"] <= VALIDATION_RATIO, "yes", "no")
    return table


def _specs(results: pd.DataFrame, manifest: dict, failed: pd.Series) -> pd.DataFrame:
    primary = manifest.get("primary", "rmse")
    metrics = [m for m in manifest.get("metrics", []) if m in results.columns]
    parts = [spec_summary(rows, metrics, primary, failed).assign(group=group)
             for group, rows in results.groupby("group", sort=False)]
    table = pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()
    if table.empty:
        return table
    table["failed_of_cells"] = table["failed"].astype(str) + " / " + table["cells"].astype(str)
    return table[["group", *[c for c in table.columns if c != "group"]]]


def shaded_groups(results: pd.DataFrame) -> list[str]:
    """Groups whose cells render scenes with shaded objects, in page order."""
    if results.empty or "shaded" not in results:
        return []
    return list(dict.fromkeys(results.loc[results["shaded"].astype(bool), "group"]))


def _specular(results: pd.DataFrame, temporal: pd.DataFrame, infos) -> pd.DataFrame:
    """One row per spec of each shaded group, ranked by highlight flicker (best first)."""
    error, bias, flicker = SPECULAR_COLUMNS
    parts = []
    for group in shaded_groups(results):
        base = ranked(temporal, group, flicker, infos) if not temporal.empty and flicker in temporal else None
        if base is None or base.empty:
            continue
        errors = per_spec(results, group, error).set_index("spec")
        biases = per_spec(temporal, group, bias).set_index("spec")["value"]
        parts.append(pd.DataFrame({"group": group, "spec": base["spec"], "method": base["method"],
                                   "options": base["options"], "label": base["label"],
                                   error: base["spec"].map(errors["value"]), bias: base["spec"].map(biases),
                                   flicker: base["value"], "noise": base["spec"].map(errors["noise"])}))
    return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()


def _filters(results: pd.DataFrame, temporal: pd.DataFrame) -> pd.DataFrame:
    """One row per spec of each ``filters*`` group: its filter, its method, every measure."""
    parts = []
    for group in dict.fromkeys(results["group"]):
        if not str(group).startswith(FILTER_GROUP_PREFIX):
            continue
        base = per_spec(results, group, "rmse")
        if base.empty:
            continue
        rows = results[results["group"] == group].drop_duplicates("spec").set_index("spec")
        out = pd.DataFrame({"group": group, "filter": base["spec"].map(rows["filter"]),
                            "method": base["spec"].map(rows["label_unfiltered"]), "spec": base["spec"],
                            "style_method": base["method"], "options": base["options"], "noise": base["noise"]})
        for name in (*_FILTER_RESULTS, *_FILTER_TEMPORAL):
            frame = results if name in _FILTER_RESULTS else temporal
            values = per_spec(frame, group, name).set_index("spec")["value"] if not frame.empty else pd.Series()
            out[name] = out["spec"].map(values) if len(values) else np.nan
        order = {f: i for i, f in enumerate(FILTER_ORDER)}
        parts.append(out.assign(_o=out["filter"].map(order)).sort_values(["_o", "method"], kind="stable")
                     .drop(columns="_o"))
    return pd.concat(parts, ignore_index=True) if parts else pd.DataFrame()


def speed_groups(speed: pd.DataFrame, results: pd.DataFrame) -> pd.DataFrame:
    """The speed pass's rows with the findings' group of each (``speed``, ``speed-1``, ...:
    each ``[[speed]]`` table is its own group) and the spec's ladder."""
    ladders = dict(zip(results["spec"], results["ladder"])) if "ladder" in results else {}
    return speed.assign(group=speed["pass"].map(lambda i: "speed" if i == 0 else f"speed-{i}"),
                        ladder=[ladders.get(spec, spec) for spec in speed["spec"]])


def _answering_groups(question: Question, frame: pd.DataFrame | None) -> list[str]:
    """Every group that measured ``question``'s column, the question's own groups first (in
    their order), then the others in the order of the table: whatever a group is named, what
    it measured answers the questions of that measure."""
    if frame is None or frame.empty or question.column not in frame:
        return []
    values = pd.to_numeric(frame[question.column], errors="coerce")
    measured = list(dict.fromkeys(frame.loc[values.notna(), "group"]))
    if question.table == "speed":  # each speed pass is named by its place, and each is its own question
        return [g for g in question.groups if g in measured]
    return [g for g in question.groups if g in measured] + [g for g in measured if g not in question.groups]


def group_truth(results: pd.DataFrame, group: str) -> dict:
    """The truth ``group``'s cells are judged against: its reference's label, what kind of truth
    it is (:func:`aaeval.metrics.agreement.truth_of`: seeded, bounded, exact, unknown) and its
    noise or error bound (mean RMS over the group's scene frames). Empty values for a group
    that renders no accuracy cell (a speed pass)."""
    rows = results[results["group"] == group] if "group" in results else results.iloc[:0]
    if rows.empty:
        return {"reference": "", "truth_kind": "", "truth_level": math.nan}
    truth = truth_of(str(rows["reference_kind"].iloc[0]), frame_noise(rows).mean())
    return {"reference": str(rows["reference_label"].iloc[0]), "truth_kind": truth.kind, "truth_level": truth.level}


def _findings(tables: dict[str, pd.DataFrame], infos) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame]:
    """Per question: which groups answer it, a ranked table for each of them (each group's own
    ranking: groups measure unlike scenes, and no one of them speaks for the rest), and their
    values per scene."""
    questions, ranks, scenes = [], [], []
    for q in QUESTIONS:
        groups = _answering_groups(q, tables.get(q.table))
        questions.append({"question": q.key, "group": groups[0] if groups else None, "also": json.dumps(groups[1:])})
        for group in groups:
            table = _ranked_answer(q, group, tables, infos)
            ranks.append(table)
            if q.per_scene:
                scenes.append(per_scene_values(q, tables[q.table], group, list(table["spec"])))
    found = pd.concat(ranks, ignore_index=True) if ranks else pd.DataFrame()
    per_scene = pd.concat(scenes, ignore_index=True) if scenes else pd.DataFrame()
    return pd.DataFrame(questions), found, per_scene


def _ranked_answer(q: Question, group: str, tables: dict[str, pd.DataFrame], infos) -> pd.DataFrame:
    """``q``'s ranked table in ``group``, with the extras, the truth it is judged against and
    (for the speed pass) the spread of the rounds."""
    frame = tables[q.table]
    how = "median" if q.table == "speed" else "mean"
    # an RMS metric's noise is the truth's on that metric's own pixels, with the same reduction
    own = noise_column(q.column)
    noise = own if q.table == "results" and own in tables["results"] else q.noise
    table = ranked(frame, group, q.column, infos, how=how, noise=noise)
    extras = [(t, c) for t, c in q.extra if t in tables and c in tables[t]]
    for t, c in extras:
        table[c] = table["spec"].map(per_spec(tables[t], group, c).set_index("spec")["value"])
    if q.table == "speed":
        times = frame[frame["group"] == group]
        times = times.assign(ms=pd.to_numeric(times["ms_per_mpix"], errors="coerce")).dropna(subset=["ms"])
        spread = times.groupby("spec")["ms"].agg(["min", "max"])
        table["spread_min"], table["spread_max"] = table["spec"].map(spread["min"]), table["spec"].map(spread["max"])
    table["agreement_text"] = [agreement_text(a) for a in table["agreement"]]
    truth = group_truth(tables["results"], group) if q.table != "speed" else group_truth(tables["results"].iloc[:0], group)
    return table.assign(question=q.key, group=group, rank=np.arange(1, len(table) + 1), table=q.table, how=how,
                        noise_column=noise, **truth)


def per_scene_values(question: Question, frame: pd.DataFrame, group: str, order: list[str]) -> pd.DataFrame:
    """``question``'s column and extras per scene of ``group``, one row per (spec in
    ``order``, scene, column): each value one animation's (a mean over unlike scenes hides them)."""
    rows = frame[frame["group"] == group]
    columns = [question.column] + [c for t, c in question.extra if t == question.table and c in rows]
    out = []
    for spec in order:
        for scene, one in rows[rows["spec"] == spec].groupby("scene", sort=False):
            for c in columns:
                out.append({"question": question.key, "group": group, "spec": spec, "label": one["label"].iloc[0],
                            "scene": scene, "column": c, "value": pd.to_numeric(one[c], errors="coerce").mean()})
    return pd.DataFrame(out)


def changing_row(frames: np.ndarray) -> int:
    """The row that changes most over the frames (F, H, W, 3): the default space-time slice."""
    if frames.shape[0] < 2:
        return frames.shape[1] // 2
    change = np.abs(np.diff(frames, axis=0)).sum(axis=(0, 2, 3))
    return int(np.argmax(change)) if change.max() > 0 else frames.shape[1] // 2


def _space_time(results: pd.DataFrame, store) -> pd.DataFrame:
    """Per animated group: its first animated scene and the row its ground truth changes most."""
    out = []
    ok = results[results["error"].isna()]
    animated = ok[ok.groupby(["group", "scene", "spec"])["frame"].transform("nunique") > 1]
    for group, rows in animated.groupby("group", sort=False):
        scene = rows["scene"].iloc[0]
        first = rows[rows["scene"] == scene].drop_duplicates("frame").sort_values("frame")
        refs = [store.load_reference(store.read_cell(k)["reference_key"]) for k in first["key"]]
        if any(r is None for r in refs):
            continue
        out.append({"group": group, "scene": scene, "row": changing_row(np.stack(refs))})
    return pd.DataFrame(out, columns=["group", "scene", "row"])


def summarize(results: pd.DataFrame, temporal: pd.DataFrame, speed: pd.DataFrame, manifest: dict,
              infos: dict[str, MetricInfo], store=None) -> dict[str, pd.DataFrame]:
    """Every summary of :data:`SUMMARIES` from the sweep's tables (``store``: for the
    reference images the space-time rows are read from)."""
    if results.empty:
        return {name: pd.DataFrame() for name in SUMMARIES}
    shaded = set(results.loc[results["shaded"].astype(bool), "scene_digest"])
    failed = failed_cells(results, manifest.get("primary", "rmse"), manifest.get("fail_above"), shaded)
    tables = {"results": results, "temporal": temporal}
    if not speed.empty:
        tables["speed"] = speed_groups(speed, results)
    questions, found, per_scene = _findings(tables, infos)
    return {"specs": _specs(results, manifest, failed), "references": _references(results),
            "validation": _validation(results, shaded), "speed": speed_summary(speed),
            "specular": _specular(results, temporal, infos), "filters": _filters(results, temporal),
            "findings": found, "findings_questions": questions, "findings_per_scene": per_scene,
            "space_time": _space_time(results, store) if store is not None else pd.DataFrame()}
