"""The ground truth on the page: what each group's cells were compared against, with its noise
(:func:`reference_statement`), and the section that states the policy and checks the exact
renderers against the Mitsuba ground truth."""

from __future__ import annotations

import html

import pandas as pd

from aaeval.metrics.agreement import truth_of
from aaeval.report import figures
from aaeval.report.html_tables import Stored, shown
from aaeval.report.page import Page, figure_html
from aaeval.sweeps.summaries import validation_rows


REFS = "summaries/references.parquet"


def reference_statement(refs: pd.DataFrame) -> str:
    """What a group's cells were compared against, with its noise level (``refs``: the
    group's rows of the stored ``references`` summary, indexed by stored row)."""
    parts = []
    for i, r in refs.iterrows():
        at = lambda column, f="": Stored(REFS, i, column, f)  # noqa: E731
        frames = shown(r["noise_frames"], at("noise_frames"))
        truth = truth_of(str(r["kind"]), r["noise_mean"])
        if truth.kind == "bounded":
            level = (f"no sampling noise; its quadrature error bound, RMS {shown(r['noise_mean'], at('noise_mean', '.3g'))} "
                     f"per pixel (max {shown(r['noise_max'], at('noise_max', '.3g'))} over {frames} frames): a bound, "
                     "not noise")
        elif truth.kind == "exact":
            level = "noise 0"
        elif r["noise_frames"] > 0:
            level = (f"measured noise RMS {shown(r['noise_mean'], at('noise_mean', '.3g'))} per pixel channel, range "
                     f"{shown(r['noise_min'], at('noise_min', '.3g'))} to {shown(r['noise_max'], at('noise_max', '.3g'))} "
                     f"(seed-to-seed RMSE / sqrt 2 over {frames} frames)")
        else:
            level = "deterministic but not exact: its own error is unknown"
        what = "Mitsuba ground truth" if r["is_ground_truth"] else "NOT the Mitsuba ground truth"
        extra = ", ".join(f"{k} {shown(r[k], at(k, '.0f'))}" for k in ("spp", "seed") if pd.notna(r[k]))
        parts.append(f"<b>{html.escape(r['reference_label'])}</b> ({what}; {html.escape(str(r['kind']))}"
                     f"{'; ' + extra if extra else ''}; {level})")
    return "Reference: " + "; ".join(parts) + "."


def ground_truth_section(page: Page, results: pd.DataFrame) -> str:
    """Which ground truth every group uses, and the check that exact renderers agree with it."""
    out = ["<h2 id='ground-truth'>Ground truth</h2>",
           "<p>Policy: each group names its truth (the table below). By default a method is judged against the "
           "<b>Mitsuba 3</b> render of the same scene frame at "
           "high spp through the method's own pixel filter (the box, which converges to the exact area average, "
           "unless the method renders through another filter F: then Mitsuba with filter F), whose own noise is "
           "measured "
           "by rendering it a second time with the next seed (noise RMS = RMSE between the two / sqrt 2). An "
           "exact renderer may stand in for it only where the check below shows that, on that group's scenes, "
           "it agrees with the Mitsuba ground truth within the ground truth's noise. A noise-free truth's error "
           "bound (exact shading's quadrature) is not noise: agreeing with it means being within the bound plus "
           "float rounding.</p>"]
    refs = page.data.summary("references")
    per_group = refs[["group", "reference_label", "Mitsuba ground truth", "spp", "seed", "noise_mean", "noise_max"]]
    out.append(page.stored_table(per_group, REFS, "ground_truth_per_group", "Ground truth of every group",
                                 {"reference_label": "reference",
                                  # an exact truth has no noise: its column holds its error bound
                                  "noise_mean": "noise RMS, or an exact truth's error bound (mean)",
                                  "noise_max": "noise RMS, or error bound (max)"}))
    checked = list(refs["validated"].astype(bool)) if "validated" in refs else [False] * len(refs)
    per_group = per_group.to_dict("records")
    bad = [g["group"] for g, ok in zip(per_group, checked) if not ok]
    crossed = [g["group"] for g, ok, truth in zip(per_group, checked, refs["is_ground_truth"]) if ok and not truth]
    if crossed:
        out.append(f"<p>Groups {html.escape(', '.join(dict.fromkeys(crossed)))} are judged against an exact truth "
                   "(no sampling noise; its quadrature error bound is a bound, not noise), and their Mitsuba row of the most "
                   "samples agrees with it on the highlight pixels within that row's own noise by the per-pixel z-test "
                   "(see Findings): there the exact truth is the Mitsuba ground truth without its noise. Over the whole "
                   "image a few silhouette values fall outside the two-render noise model; the 16-seed t-test of "
                   "tests/specular/test_exact_vs_mitsuba.py passes every pixel channel.</p>")
    if bad:
        out.append(f"<p class='warn'>Groups {html.escape(', '.join(dict.fromkeys(bad)))} compare against a reference "
                   "that is not the Mitsuba ground truth, and no Mitsuba row of theirs agrees with it by the z-test "
                   "here (the table says how close it came): read their errors as agreement with that reference "
                   "only.</p>")
    check = validation_rows(results, page.shaded)
    table = page.data.summary("validation")
    if check.empty or table.empty:
        out.append("<p>No exact method was compared with a Mitsuba ground truth in this sweep.</p>")
        return "\n".join(out)
    p = figures.validation(check, page.figdir / "ground_truth_validation",
                           title="exact renderers against the Mitsuba ground truth", styles=page.styles)
    out.append(figure_html(p, page.root, "Each exact method's RMSE against the Mitsuba ground truth (one point per "
                       "scene frame) over that ground truth's own measured noise. On the diagonal the exact "
                       "method agrees with the ground truth as well as two Mitsuba renders agree with each other "
                       f"(RMSE between an exact image and a noisy one is the noise RMS); {figures.UNIT}."))
    out.append(page.stored_table(table, "summaries/validation.parquet", "ground_truth_validation",
                                 "Exact renderers against the Mitsuba ground truth, with its seed-to-seed noise",
                                 {"label": "exact method", "rmse_mean": "RMSE vs ground truth (mean)",
                                  "noise_mean": "ground truth noise RMS (mean)",
                                  "ratio_max": "RMSE / noise (worst frame)"}))
    if page.shaded:
        out.append("<p class='note'>Scenes with smooth-shaded objects are left out of this check: there the exact "
                   "methods' coverage is exact but their shading is one Phong shade per visible piece (or a "
                   "specular clamp), which the groups' own charts compare with the Mitsuba Phong ground truth.</p>")
    return "\n".join(out)
