"""Summaries read from the sweep's tables alone: the intensity sum per frame against the
reference's (``sums``) and the temporal metrics over an animation (``temporal``)."""

from __future__ import annotations

import math
from typing import Mapping

import numpy as np

from aaeval.studies.fields import expected_labels, group_rows, labels_in, method_rows, name_list, number_field
from aaeval.studies.folder import Study, StudyError
from aaeval.studies.markdown import fmt, md_code, md_table, quoted, verdict

def write_sums(sweep, item: Mapping, study: Study, where: str, checks: list[bool]) -> list[str]:
    """Per scene and method: the intensity sum's min, max and mean over the frames against
    the reference's sum, its bias and its relative variation."""
    tol = number_field(item, "tolerance", 1e-9, where)
    rows = group_rows(sweep.results, item, where)
    want_steady, want_moving = expected_labels(item, "steady", rows, where), expected_labels(item, "unsteady", rows, where)
    out: list[str] = []
    steady_per_scene: list[set] = []
    for scene, of_scene in rows.groupby("scene", sort=False):
        ref = of_scene.groupby("frame")["reference_intensity_sum"].first()
        ref_label = of_scene["reference"].iloc[0]
        table, steady, worst = [], [], None
        for label in labels_in(of_scene):
            s = of_scene[of_scene["label"] == label].sort_values("frame")
            sums = s["intensity_sum"].to_numpy(float)
            truth = ref.loc[s["frame"]].to_numpy(float)
            with np.errstate(divide="ignore", invalid="ignore"):  # a black scene: any sum but 0 is off
                dev = np.where(truth == 0, np.abs(sums), np.abs(sums - truth) / np.abs(truth))
            variation = _relative_variation(sums)
            bias = float(sums.mean() / truth.mean() - 1.0) if truth.mean() else math.nan  # no scale: a black truth
            table.append([f"{md_code(label)}", str(len(sums)), fmt(sums.min()), fmt(sums.max()), fmt(sums.mean()),
                          fmt(bias, "+.2%"), fmt(variation, ".2e")])
            if dev.max() <= tol:
                steady.append(label)
            if worst is None or variation > worst[1] or math.isnan(worst[1]):
                worst = (label, variation, sums.min(), sums.max())
        ref_sums = ref.to_numpy(float)
        out += [f"Scene {md_code(scene)}, reference {md_code(ref_label)}: its sum is {fmt(ref_sums.min())} to {fmt(ref_sums.max())} "
                f"over {len(ref_sums)} frames (relative variation "
                f"{fmt(_relative_variation(ref_sums), '.1e')}).", ""]
        out += md_table(["method", "frames", "sum min", "sum max", "sum mean", "bias of the mean", "(max-min)/mean"], table)
        swing = (f" Widest swing: {md_code(worst[0])}, from {fmt(worst[2])} to {fmt(worst[3])} (relative variation "
                 f"{fmt(worst[1], '.3g')})." if worst[0] not in steady else "")
        out += ["", f"Within {tol:g} (relative) of the reference's sum in every frame: "
                f"{quoted(steady) or 'no method'}.{swing}", ""]
        steady_per_scene.append(set(steady))
    if want_steady or want_moving:
        ok = all(set(want_steady) <= got and not set(want_moving) & got for got in steady_per_scene)
        parts = [f"{quoted(want_steady)} within {tol:g} of the reference's sum in every frame" if want_steady else "",
                 f"{quoted(want_moving)} not" if want_moving else ""]
        out += verdict(checks, ", ".join(p for p in parts if p), ok) + [""]
    return out


def _relative_variation(sums: np.ndarray) -> float:
    """(max - min) / |mean| of a sum over frames; 0 for a sum that never moves (a black image
    too), NaN where the sum moves around a mean of 0 (no scale to be relative to)."""
    spread, mean = float(np.ptp(sums)), float(np.mean(sums))
    if spread == 0:
        return 0.0
    return spread / abs(mean) if mean else math.nan


def write_temporal(sweep, item: Mapping, study: Study, where: str, checks: list[bool]) -> list[str]:
    """Per scene and method: temporal metrics from ``temporal.parquet``; with ``ratio = [A, B]``
    the ratio metric(A) / metric(B) per scene for the first metric."""
    metrics = name_list(item, "metrics", where)
    if sweep.temporal.empty:
        raise StudyError(f"{study.results}: no temporal.parquet (the group's animations have not all finished)")
    rows = group_rows(sweep.temporal, item, where)
    missing = [m for m in metrics if m not in rows]
    if missing:
        raise StudyError(f"{where}.metrics: {missing} not measured in the results (temporal columns: "
                         f"{sorted(c for c in rows.columns if rows[c].dtype.kind == 'f')})")
    from aaeval.metrics import METRICS

    titles = [METRICS.get_entry(m).title if m in METRICS else m for m in metrics]
    labels = labels_in(rows)
    scenes = list(dict.fromkeys(rows["scene"]))
    table = []
    for scene in scenes:
        for label in labels:
            r = rows[(rows["scene"] == scene) & (rows["label"] == label)]
            if r.empty:
                continue
            table.append([f"{md_code(scene)}", f"{md_code(label)}", str(int(r["frames"].iloc[0])),
                          *(fmt(r[m].iloc[0], ".3e") for m in metrics)])
    out = md_table(["scene", "method", "frames", *titles], table)
    ratio = item.get("ratio")  # checked by check_temporal
    if ratio is not None:
        m = metrics[0]
        first, second = (method_rows(rows, r, f"{where}.ratio") for r in ratio)
        parts, values = [], []
        for scene in scenes:
            a = first[first["scene"] == scene][m]
            b = second[second["scene"] == scene][m]
            if a.empty or b.empty:
                continue
            value = float(a.iloc[0]) / float(b.iloc[0]) if float(b.iloc[0]) else float("inf")
            values.append(value)
            parts.append(f"{md_code(scene)} {fmt(value, '.3g')}x")
        if values:
            spread = f" (from {fmt(min(values), '.3g')}x to {fmt(max(values), '.3g')}x)" if len(values) > 1 else ""
            out += ["", f"{titles[0]} of {md_code(first['label'].iloc[0])} over that of {md_code(second['label'].iloc[0])}: "
                    f"{', '.join(parts)}{spread}."]
            if "ratio_above" in item:
                bound = number_field(item, "ratio_above", 0, where)
                out += verdict(checks, f"the ratio above {bound:g}x on every scene", min(values) > bound,
                                f" (smallest {fmt(min(values), '.3g')}x)")
            if "ratio_below" in item:
                bound = number_field(item, "ratio_below", 0, where)
                out += verdict(checks, f"the ratio below {bound:g}x on every scene", max(values) < bound,
                                f" (largest {fmt(max(values), '.3g')}x)")
    return out + [""]
