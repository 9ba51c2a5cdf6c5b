"""Summaries that read the stored images: error against the reference with its noise
(``errors``), the difference between two methods (``pairs``) and one pixel's values (``pixel``)."""

from __future__ import annotations

from typing import Mapping

import numpy as np

from aaeval.metrics.agreement import EXACT_ROUNDING, truth_of, within_truth
from aaeval.studies.fields import expected_labels, group_rows, labels_in, method_rows, name_list, number_field
from aaeval.studies.folder import Study, StudyError
from aaeval.studies.markdown import fmt, md_code, md_table, md_text, quoted, verdict

def write_errors(sweep, item: Mapping, study: Study, where: str, checks: list[bool]) -> list[str]:
    """Per scene and method: the mean over frames of image metrics, the largest absolute pixel
    difference from the reference (read from the stored images) and the reference's noise."""
    from aaeval.sweeps.store import SweepStore
    from aaeval.metrics import METRICS

    metrics = name_list(item, "metrics", where, ["rmse"])
    rows = group_rows(sweep.results, item, where)
    missing = [m for m in metrics if m not in rows]
    if missing:
        raise StudyError(f"{where}.metrics: {missing} not measured in the results")
    store = SweepStore(study.results)
    table, worst, errors, truths = [], {}, {}, []
    for scene, of_scene in rows.groupby("scene", sort=False):
        truth = truth_of(str(of_scene["reference_kind"].iloc[0]),
                         float(of_scene["reference_noise_rmse"].astype(float).mean()))
        truths.append(truth)
        for label in labels_in(of_scene):
            s = of_scene[of_scene["label"] == label]
            # two columns, not itertuples: a named tuple class of every column is made per call
            diff = max((_max_abs(store, key, ref) for key, ref in zip(s["key"], s["reference_key"])),
                       default=float("nan"))
            worst.setdefault(label, []).append(diff)
            first = float(s[metrics[0]].astype(float).mean())
            errors.setdefault(label, []).append((first, truth))
            ratio = [fmt(first / truth.level, ".2f")] if truth.kind == "seeded" else []
            table.append([md_code(scene), md_code(label), *(fmt(s[m].astype(float).mean(), ".3e") for m in metrics),
                          fmt(diff, ".3e"), md_text(truth.words()), *ratio])
    seeded = any(t.kind == "seeded" for t in truths)
    titles = [METRICS.get_entry(m).title if m in METRICS else m for m in metrics]
    out = md_table(["scene", "method", *(f"{t} (mean)" for t in titles), "max abs diff", "reference (its noise or bound)",
                  *([f"{titles[0]} / noise"] if seeded else [])], table)
    ranked = sorted(worst, key=lambda k: max(worst[k]))
    out += ["", "Largest absolute difference from the reference over every scene, frame, pixel and channel: "
            + ", ".join(f"{md_code(k)} {fmt(max(worst[k]), '.2e')}" for k in ranked) + "."]
    if any(t.kind == "unknown" for t in truths):  # a deterministic truth: its own error is not known
        return out + [""]
    factor = number_field(item, "noise_factor", 1.5, where)
    within = [k for k, pairs in errors.items() if all(within_truth(e, t, factor) for e, t in pairs)]
    what = (f"within {factor:g}x the truth's noise" if seeded else
            f"within the exact truth's error bound plus float rounding ({EXACT_ROUNDING:g})")
    out += ["", f"{titles[0]} {what} on every scene: {quoted(within) or 'no method'}."]
    want = expected_labels(item, "within_noise", rows, where)
    if want:
        out += verdict(checks, f"{quoted(want)} {what} on every scene", set(want) <= set(within))
    return out + [""]


def _max_abs(store, key: str, reference_key: str) -> float:
    image = store.load_image(key)
    reference = store.load_reference(reference_key)
    if image is None or reference is None:
        return float("nan")
    return float(np.max(np.abs(image - reference)))


def write_pairs(sweep, item: Mapping, study: Study, where: str, checks: list[bool]) -> list[str]:
    """The largest absolute difference between two methods' stored images, frame by frame."""
    from aaeval.sweeps.store import SweepStore

    pairs = item["pairs"]  # checked by check_pairs
    rows = group_rows(sweep.results, item, where)
    store = SweepStore(study.results)
    table, largest = [], 0.0
    for a, b in pairs:
        first, second = method_rows(rows, a, f"{where}.pairs"), method_rows(rows, b, f"{where}.pairs")
        for scene in dict.fromkeys(rows["scene"]):
            left = first[first["scene"] == scene].set_index("frame")["key"]
            right = second[second["scene"] == scene].set_index("frame")["key"]
            frames = sorted(set(left.index) & set(right.index))
            diffs = [float(np.max(np.abs(store.load_image(left[k]) - store.load_image(right[k])))) for k in frames]
            table.append([f"{md_code(first['label'].iloc[0])} vs {md_code(second['label'].iloc[0])}", f"{md_code(scene)}", str(len(frames)),
                          fmt(max(diffs), ".3e")])
            largest = max(largest, *diffs)
    out = md_table(["pair", "scene", "frames", "max abs diff"], table)
    if "below" in item:
        bound = number_field(item, "below", 0, where)
        out += verdict(checks, f"every difference below {bound:g}", largest < bound, f" (largest {largest:.2e})")
    return out + [""]


def write_pixel(sweep, item: Mapping, study: Study, where: str, checks: list[bool]) -> list[str]:
    """One pixel of one frame, every method's stored value against the reference's."""
    from aaeval.sweeps.store import SweepStore

    pixel, frame = item["pixel"], item.get("frame", 0)  # checked by check_pixel
    tol = number_field(item, "tolerance", 0.01, where)
    rows = group_rows(sweep.results, item, where)
    if not (rows["frame"] == frame).any():
        raise StudyError(f"{where}.frame: frame {frame} is not in the group's results")
    rows = rows[rows["frame"] == frame]
    store = SweepStore(study.results)
    r, c = pixel
    reference = store.load_reference(rows["reference_key"].iloc[0])
    truth = reference[r, c]
    table = [[f"{md_code(rows['reference'].iloc[0])} (reference)", *(fmt(v, ".4f") for v in truth), "0"]]
    agree, off = [], []
    for label in labels_in(rows):
        value = store.load_image(rows[rows["label"] == label]["key"].iloc[0])[r, c]
        diff = float(np.max(np.abs(value - truth)))
        table.append([f"{md_code(label)}", *(fmt(v, ".4f") for v in value), fmt(diff, ".2e")])
        (agree if diff <= tol else off).append(label)
    out = [f"Pixel (row {r}, column {c}) of frame {frame} of {md_code(rows['scene'].iloc[0])}, linear RGB.", ""]
    out += md_table(["method", "R", "G", "B", "max abs diff"], table)
    out += ["", f"Within {tol:g} of the reference in every channel: {quoted(agree) or 'none'}; "
            f"off: {quoted(off) or 'none'}."]
    want_agree, want_off = expected_labels(item, "agree", rows, where), expected_labels(item, "disagree", rows, where)
    if want_agree or want_off:
        parts = [f"{quoted(want_agree)} within {tol:g}" if want_agree else "",
                 f"{quoted(want_off)} off" if want_off else ""]
        out += verdict(checks, ", ".join(p for p in parts if p), set(want_agree) <= set(agree) and set(want_off) <= set(off))
    return out + [""]
