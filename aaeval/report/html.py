"""The HTML report of a sweep folder: ``index.html`` with inline CSS and the inline
comparison viewer, its figures in ``DIR/figures/`` (PNG shown, SVG and PDF beside them),
its tables in ``DIR/tables/`` (CSV and LaTeX) and the viewer's data in ``DIR/viewer/``.
Nothing is fetched from the network; the page works from ``file://``.

Every comparison says what it compares against: the ground truth's spec, spp, seed and
measured noise. The ground-truth policy: a group's reference is the Mitsuba high-spp
render, or an exact renderer that the report has shown, on the group's own scenes, to
agree with a Mitsuba ground truth within that ground truth's noise; anything else is
flagged on the page as unvalidated.
"""

from __future__ import annotations

import html
import json
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from aaeval.sweeps.aggregate import failed_cells, failure_definition
from aaeval.sweeps.summaries import measured_noise, validation_rows
from aaeval.metrics.agreement import truth_of
from aaeval.fileio import atomic_write
from aaeval.report import figures, image_figures
from aaeval.report.names import figure_stem
from aaeval.report.filters_section import filters_section
from aaeval.report.specular_section import specular_section
from aaeval.report.sweep_data import METRICS, SweepData, read_sweep
from aaeval.report.findings import findings_section
from aaeval.report.style import Styles
from aaeval.report.html_tables import Stored, shown, stored_cells, write_table
from aaeval.report.viewer import (GROUP_BUDGET, VIEWER_CSS, scene_series, viewer_div,
                                  viewer_payload, viewer_script, write_viewer_data)

__all__ = ["write_report", "reference_statement", "SPEED_MIN_PIXELS"]

# Below 256 x 256 pixels a render's time is mostly call overhead: such groups report accuracy.
SPEED_MIN_PIXELS = 256 * 256
# The page must stay small (figures' PNG, SVG and PDF, tables and this, under 20 MB): past
# this many bytes of viewer data, a group's viewer keeps its first scene only.
VIEWER_BUDGET = 4_000_000

_CSS = """
body{font-family:system-ui,sans-serif;max-width:1250px;margin:1.5em auto;padding:0 1em;color:#222}
h1{margin-bottom:.2em} h2{border-bottom:2px solid #ccc;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;font-size:12px;margin:.6em 0;display:block;overflow-x:auto;max-width:100%}
td,th{border:1px solid #ccc;padding:2px 6px} th{background:#f0f0f0} td.num{text-align:right;font-family:monospace}
.note{background:#f6f8fa;border-left:4px solid #888;padding:.4em .8em;font-size:13px}
.ref{background:#fff8e0;border-left:4px solid #d9a400;padding:.4em .8em;font-size:13px}
.warn{background:#fdecea;border-left:4px solid #b00;padding:.4em .8em;font-size:13px}
figure{margin:1em 0} figcaption{font-size:12px;color:#444;max-width:1000px} img{max-width:100%}
.bad{color:#b00} .dl{font-size:11px;color:#555;margin-top:0} dl.prov{font-size:12px} dl.prov dt{font-weight:bold;float:left;clear:left;width:14em} dl.prov dd{margin-left:15em}
""" + VIEWER_CSS


REFS = "summaries/references.parquet"


def definition_html(definition: str, fail_above, stored_at: Stored) -> str:
    """The failure definition with its threshold marked as the value stored in the manifest."""
    text = html.escape(definition)
    if not fail_above:
        return text
    number = f"{fail_above:g}"
    i = text.rindex(f"above {number}") + len("above ")
    return text[:i] + shown(fail_above, stored_at, number) + text[i + len(number):]


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


def figure_html(path: Path, root: Path, caption: str) -> str:
    """A figure of the page: the PNG, its caption, and links to its twins in other formats."""
    rel = path.relative_to(root).as_posix()
    twins = " · ".join(f"<a href='{html.escape(Path(rel).with_suffix('.' + f).as_posix())}'>{f.upper()}</a>"
                       for f in figures.twin_formats())
    links = f" <span class='dl'>(also as {twins})</span>" if twins else ""
    return (f"<figure><img src='{html.escape(rel)}' alt='{html.escape(html.unescape(''.join(p.split('>', 1)[-1] for p in caption.split('<')))[:120])}'>"
            f"<figcaption>{caption}{links}</figcaption></figure>")


class _Page:
    """What one report build shares: folders, styles, the failure definition."""

    def __init__(self, data: SweepData):
        store, results, manifest = data.store, data.results, data.manifest
        self.store, self.root, self.data = store, store.root, data
        # real folders of the sweep folder (a planted link to a folder elsewhere is refused by name)
        self.figdir, self.tabdir, self.viewdir = (store.own_folder(d) for d in ("figures", "tables", "viewer"))
        self.primary = manifest.get("primary", "rmse")
        self.fail_above = manifest.get("fail_above")
        self.styles = Styles.from_sweep(data.specs)
        self.definition = failure_definition(self.primary, self.fail_above)
        # the definition as running text, its threshold marked as the manifest's value
        self.definition_html = definition_html(self.definition, self.fail_above,
                                               Stored("manifest.json", 0, "fail_above"))
        self.viewer_scripts: list[str] = []
        self.viewer_left = VIEWER_BUDGET  # bytes of viewer data the page may still load
        self.shaded = set(results.loc[results["shaded"].astype(bool), "scene_digest"]) if not results.empty else set()
        self.group_temporal = manifest.get("group_temporal", {})

    def table(self, frame: pd.DataFrame, name: str, caption: str = "", where: pd.DataFrame | None = None) -> str:
        # names: fixed words and figure stems
        return write_table(frame, self.tabdir, name, self.root, caption, where)

    def stored_table(self, frame: pd.DataFrame, source: str, name: str, caption: str = "",
                     renamed: dict | None = None) -> str:
        """Rows of the stored table ``source`` (``frame``'s index: their stored rows), its
        columns ``renamed`` (``{stored name: shown name}``) for the page."""
        shown_frame = frame.rename(columns=renamed or {})
        return self.table(shown_frame.reset_index(drop=True), name, caption,
                          stored_cells(shown_frame, source, frame.index, renamed).reset_index(drop=True))

    def references(self, group: str) -> pd.DataFrame:
        refs = self.data.summary("references")
        return refs[refs["group"] == group] if not refs.empty else refs


def _noise(rows: pd.DataFrame) -> np.ndarray:
    """The ground truth's measured noise of each scene frame of ``rows``: the grey band of a
    chart (none for a noise-free truth)."""
    return measured_noise(rows.drop_duplicates(["scene", "frame"])).to_numpy(float)


def _accuracy_block(page: _Page, group: str, slug: str, summary: pd.DataFrame, rows: pd.DataFrame,
                    ref: str) -> str:
    """Accuracy per spec. The accuracy cells may run in parallel, so their times are never
    charted: speed comes from the speed pass (:mod:`aaeval.sweeps.speed`)."""
    primary = page.primary
    noise = _noise(rows)
    data = summary.dropna(subset=[primary])
    if data.empty:
        return ""
    p = figures.accuracy_dots(data, page.figdir / f"{slug}_accuracy", metric=primary,
                              title=f"{group}: accuracy", styles=page.styles, noise=noise)
    return figure_html(p, page.root, f"Mean {primary} per method and option (bar: best to worst cell), "
                   f"{figures.UNIT}. {ref} The grey band is the ground truth's measured noise. Times of these cells "
                   "are not charted (cells may share the machine): see <a href='#speed'>Speed</a>.")


def _temporal_block(page: _Page, group: str, slug: str, rows: pd.DataFrame, temp: pd.DataFrame,
                    ref: str) -> list[str]:
    out = []
    ok = rows[rows["error"].isna()]
    animated = ok[ok.groupby(["scene", "spec"])["frame"].transform("nunique") > 1]
    if animated.empty:
        return out
    out.append("<h3>Over the frames of the animations</h3>")
    if page.primary in animated:
        p = figures.error_per_frame(animated, page.figdir / f"{slug}_error_per_frame", metric=page.primary,
                                    title=f"{group}: {page.primary} per frame", styles=page.styles)
        out.append(figure_html(p, page.root, f"{page.primary} of every frame, one curve per method and option; the "
                   f"thick grey curve is the ground truth's own noise in that frame; {figures.UNIT}. {ref}"))
    p = figures.intensity_sums(animated, page.figdir / f"{slug}_intensity_sum",
                               title=f"{group}: intensity sum per frame", styles=page.styles)
    out.append(figure_html(p, page.root, "Intensity sum of every frame divided by the ground truth's sum of the same "
               "frame (linear axis; 1 is right); the thick grey curve is the ground truth's own sum relative to "
               f"its frame 0. Area sampling keeps the sum while the scene moves inside the frame. {ref}"))
    phased = animated.dropna(subset=["phase"])
    if page.primary in animated and not phased.empty:
        p = figures.phase_figure(phased, page.figdir / f"{slug}_phase", metric=page.primary,
                                 title=f"{group}: against the sub-pixel phase", styles=page.styles)
        out.append(figure_html(p, page.root, f"{page.primary} (left, log axis; the grey curve is the ground truth's "
                   "noise) and the intensity sum over the ground truth's sum (right; 1 is right) of every frame, "
                   "against the frame's sub-pixel phase along x: its offset from the scene as written, modulo 1 px. "
                   "A sampler whose grid aliases with the motion repeats a pattern at the grid's spacing; area "
                   f"sampling stays flat. {figures.UNIT}. {ref}"))
    names = [m for m in page.group_temporal.get(group, []) if m in temp and temp[m].notna().any()]
    if not temp.empty and names:
        p = figures.temporal_bars(temp, page.figdir / f"{slug}_temporal", group=group, metrics=names,
                                  title=f"{group}: over the animations", styles=page.styles)
        out.append(figure_html(p, page.root, "Each temporal measure per method and option, one panel each (mean over "
                   "the animated scenes, linear axes; registered in aaeval/metrics, values from temporal.parquet): "
                   + "; ".join(f"<b>{html.escape(METRICS[m].title)}</b>: {html.escape(METRICS[m].summary)}"
                               for m in names)
                   + f". The dashed line is the ground truth's own noise RMS where it applies; {figures.UNIT}. {ref}"))
    slices = page.data.summary("space_time")
    slices = slices[slices["group"] == group] if not slices.empty else slices
    if slices.empty:
        return out
    at = slices.index[0]
    scene, row = slices.at[at, "scene"], int(slices.at[at, "row"])
    reference, series, frames = scene_series(animated, page.store, scene, page.styles)
    if reference is not None and series:
        p = image_figures.space_time(reference, [(r["label"].iloc[0], imgs) for r, imgs in series[:15]],
                               page.figdir / f"{slug}_space_time", row=row, title=f"{group}: {scene}")
        where = shown(row, Stored("summaries/space_time.parquet", at, "row"))
        out.append(figure_html(p, page.root, f"Space-time slices of {html.escape(scene)}: row {where} (the row that "
                   "changes most) of every frame stacked downwards, per method. Crawling edges show as "
                   "staircases, flicker as horizontal streaks; the viewer below shows any row (its space-time "
                   f"checkbox). The first panel is the ground truth. {ref}"))
    return out


def _policy_section(page: _Page, results: pd.DataFrame) -> str:
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
                                 {"reference_label": "reference", "noise_mean": "noise RMS (mean)",
                                  "noise_max": "noise RMS (max)"}))
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


def _how_to_read(page: _Page) -> str:
    from aaeval.report.controls_table import controls_html

    return f"""<h2 id='how-to-read'>How to read this report</h2><ul>
<li><b>Ground truth.</b> Every error is measured against the reference named at the top of each group (normally
the Mitsuba high-spp render); its measured noise is stated with it. The section <a href='#ground-truth'>Ground
truth</a> shows that the exact renderers agree with it within that noise.</li>
<li><b>Errors near the noise.</b> Against a noisy ground truth nothing can score below its noise: the grey band in
the charts marks it. An exact method lands on the band; a method above it is wrong by more than the ground truth's
own uncertainty. An error that is zero up to float rounding (below {figures.EXACT_BELOW:g}, possible only against
an exact reference) is drawn on a marked "exact" strip at the bottom of the axis.</li>
<li><b>Styles.</b> A method keeps one colour, marker and dash pattern in every figure; the shades of that colour
(light to dark) and growing markers are its option ladder (k, spp) from smallest to largest; marker fills (full,
empty, half) are categorical options. Legends list methods in one order, options by value.</li>
<li><b>Times.</b> Only the speed pass is timed for the page (section <a href='#speed'>Speed</a>): one worker,
a stated thread count, each method warmed up on its own spec, then interleaved rounds on images of at least
{SPEED_MIN_PIXELS} pixels (256 x 256), as time per megapixel (median, bars from the fastest to the slowest round).
The accuracy cells may run on several workers at once: their times are never charted.</li>
<li><b>Units.</b> {figures.UNIT}. Error maps and grids share one scale per figure (the viewer's "shared scale"
checkbox switches to each panel's own).</li>
<li><b>Bias and flicker.</b> Over an animation a method's error splits into its bias (the time-average of the
error, the part that stays with the object) and its flicker (what is left, frame to frame); for highlights the
same split is made on the highlight's energy, so a clamp that dims the highlight wherever it goes shows as bias,
not as flicker. Each is one registered metric (aaeval/metrics), used by every table, chart and section.</li>
<li id='controls'><b>Controls.</b> Each temporal measure is checked on images whose answer is known before it judges
a method (aaeval/metrics/controls.py; computed as this page was built):
{controls_html(page.data.controls)}</li>
<li><b>Failed.</b> {html.escape(page.definition)} The same definition is used by every table and chart; a metric
that could not be computed for a cell is listed separately and does not make the cell fail.</li>
<li><b>The viewer.</b> Each group ends with an interactive viewer: pick a scene, scrub or play the frames, choose
image, |error|, signed error (red: too bright, blue: too dark) or FLIP, on each panel's own scale or one shared
scale; the wheel zooms (nearest-neighbour pixels) and dragging pans every panel together; the cursor reads linear
RGB values. Keys: 0-9 show a panel alone (0: ground truth), f or space flips between the last two (A/B),
n / p next / previous, [ ] frames, k play, m display, +/- exposure, s space-time slice of the row under the cursor,
z resets the zoom.</li>
<li><b>Files.</b> Every figure is also an SVG and a PDF (links under it), every table a CSV and a LaTeX file.</li>
</ul>"""


SPECS = "summaries/specs.parquet"


def _overview(page: _Page) -> str:
    """Mean primary error and failed cells per method AND option (rows) and group (columns):
    the stored ``specs`` summary, pivoted."""
    primary = page.primary
    specs = page.data.summary("specs")
    if specs.empty:
        return ""
    first = specs.drop_duplicates("spec")
    order = sorted(zip(first["method"], first["options"], first["label"]), key=lambda r: page.styles.order(r[0], r[1]))
    labels = list(dict.fromkeys(label for _, _, label in order))
    groups = list(dict.fromkeys(specs["group"]))
    at = {(r.label, r.group): i for i, r in zip(specs.index, specs[["label", "group"]].itertuples())}

    def pivot(value, column: str) -> tuple[pd.DataFrame, pd.DataFrame]:
        shown_cells = {"method and option": labels}
        where = {"method and option": [next(Stored(SPECS, at[(label, g)], "label") for g in groups if (label, g) in at)
                                       for label in labels]}
        for g in groups:
            shown_cells[g] = [value(at[(label, g)]) if (label, g) in at else None for label in labels]
            where[g] = [Stored(SPECS, at[(label, g)], column) if (label, g) in at else None for label in labels]
        return pd.DataFrame(shown_cells), pd.DataFrame(where)

    errors, where_errors = pivot(lambda i: specs.at[i, primary] if primary in specs else None, primary)
    fails, where_fails = pivot(lambda i: specs.at[i, "failed_of_cells"], "failed_of_cells")
    return ("<h2 id='overview'>Overview</h2>"
            f"<p>Mean {html.escape(primary)} against each group's ground truth, per method and option (one row "
            "each: options are never averaged together). An empty cell: the method did not run in that group.</p>"
            + page.table(errors, "overview_error", f"Mean {primary} per method and option and group", where_errors)
            + f"<p>Failed cells / cells per method and option and group. {page.definition_html}</p>"
            + page.table(fails, "overview_failed", "Failed cells per method and option and group", where_fails))


def _group_section(page: _Page, group: str, rows: pd.DataFrame, temporal: pd.DataFrame, failed: pd.Series) -> str:
    slug = figure_stem(group)  # unique per name: "fence a" and "fence-a" must not share files
    out = [f"<h2 id='{html.escape(slug)}'>{html.escape(group)}</h2>"]
    refs = page.references(group)
    ref = reference_statement(refs)
    out.append(f"<p class='ref'>{ref} Methods' spp and seed are in their specs and in the table.</p>")
    if not refs["is_ground_truth"].all():
        out.append("<p class='warn'>This group's reference is not the Mitsuba ground truth and is not validated "
                   "in this report.</p>")
    ok = rows[rows["error"].isna()]
    specs = page.data.summary("specs")
    summary = specs[specs["group"] == group]
    out.append(_accuracy_block(page, group, slug, summary, rows, ref))
    temp = temporal[temporal["group"] == group] if not temporal.empty else temporal
    out.extend(_temporal_block(page, group, slug, rows, temp, ref))
    if rows["difficulty"].nunique() >= 3:  # a trend needs a few levels
        p = figures.stability(rows, page.figdir / f"{slug}_stability", metric=page.primary,
                              failed=failed.loc[rows.index], title=f"{group}: error and failures as difficulty grows",
                              styles=page.styles, definition=page.definition)
        out.append(figure_html(p, page.root, f"Mean {page.primary} (left; thick grey: the ground truth's noise; {figures.UNIT}) and "
                   f"fraction of failed cells (right) against difficulty. {page.definition_html} {ref}"))
    grid = _grid(page, ok, slug, group, ref)
    if grid:
        out.append(grid)
    payload, left_out = viewer_payload(ok, page.store, page.styles, budget=min(GROUP_BUDGET, page.viewer_left))
    if payload["scenes"]:
        out.append("<h3>Compare the images</h3>")
        page.viewer_left -= write_viewer_data(page.viewdir, slug, payload).stat().st_size
        page.viewer_scripts.append(f"viewer/{slug}.js")
        out.append(viewer_div(slug))
        if left_out:
            out.append(f"<p class='note'>Left out of the viewer to keep the page small: "
                       f"{html.escape(', '.join(left_out))} (their images are in images/ as .npy).</p>")
    out.append("<h3>Numbers per method and option</h3>")
    # the accuracy cells' times are left out: cells may share the machine (see the speed pass)
    numbers = summary.drop(columns=["group", "spec", "method", "options", f"{page.primary}_min",
                                    f"{page.primary}_max", "repeats", "render ms (median)", "ms_per_mpix",
                                    "ms_per_mpix_min", "ms_per_mpix_max", "failed_of_cells"], errors="ignore")
    numbers = numbers.dropna(axis=1, how="all")  # a metric of another group's
    out.append(page.stored_table(numbers, SPECS, f"{slug}_numbers", f"{group}: numbers per method and option (mean "
                                 f"over cells; {figures.UNIT}; times: see the speed pass)", {"label": "method (options)"}))
    out.append(f"<p class='dl'>{page.definition_html}</p>")
    if not temp.empty:
        names = [c for c in page.group_temporal.get(group, ("flicker", "sum_variation")) if c in temp]
        cols = ["scene", "label", "frames", "failed_frames", *names, "reference_sum_variation",
                "reference_noise_rmse"]
        out.append(page.stored_table(temp[[c for c in cols if c in temp.columns]], "temporal.parquet",
                                     f"{slug}_temporal", f"{group}: temporal metrics per animation"))
    spoiled = rows[rows["metric_errors"].notna()] if "metric_errors" in rows else rows.iloc[:0]
    if not spoiled.empty:
        out.append(f"<h3>Metrics that could not be computed ({len(spoiled)} cells; not failures)</h3>")
        out.append(page.stored_table(spoiled[["scene", "label", "frame", "metric_errors"]], "results.parquet",
                                     f"{slug}_metric_errors"))
    bad = rows[failed.loc[rows.index]]
    if not bad.empty:
        out.append(f"<h3 class='bad'>Failed cells ({len(bad)})</h3>")
        columns = ["scene", "label", "frame", *([page.primary] if page.primary in bad else []), "error", "host"]
        out.append(page.stored_table(bad[columns], "results.parquet", f"{slug}_failed"))
    return "\n".join(out)


def _ladder_tops(cells: pd.DataFrame, styles: Styles) -> pd.Series:
    """Which rows to keep for a static figure: of a method's numeric ladder (k, spp) only
    the last row given (the caller sorts by value: the largest); every categorical option."""
    keep = pd.Series(True, index=cells.index)
    for method, rows in cells.groupby("method", sort=False):
        options = [styles.options(method, o) for o in rows["options"]]
        varying = {k for k in set().union(*options) if len({json.dumps(o.get(k)) for o in options}) > 1}
        numeric = varying and all(isinstance(o.get(k), (int, float)) and not isinstance(o.get(k), bool)
                                  for o in options for k in varying)
        if numeric:
            keep[rows.index[:-1]] = False
    return keep


def _grid(page: _Page, ok: pd.DataFrame, slug: str, group: str, ref: str) -> str:
    """Static image grid of the hardest scene's middle frame, for a paper figure."""
    if ok.empty:
        return ""
    scene = ok["scene"].iloc[0]
    if ok["difficulty"].notna().any():
        scene = ok.loc[ok["difficulty"].idxmax(), "scene"]
    frames = sorted(ok[ok["scene"] == scene]["frame"].unique())
    frame = frames[len(frames) // 2]
    cells = ok[(ok["scene"] == scene) & (ok["frame"] == frame)].drop_duplicates("spec")
    cells = cells.iloc[sorted(range(len(cells)), key=lambda i: page.styles.order(cells["method"].iloc[i],
                                                                              cells["options"].iloc[i]))]
    cells = cells[_ladder_tops(cells, page.styles)]
    cells = cells.head(10)
    reference = page.store.load_reference(page.store.read_cell(cells["key"].iloc[0])["reference_key"])
    images = [(label, page.store.load_image(key)) for label, key in zip(cells["label"], cells["key"])]
    images = [(s, im) for s, im in images if im is not None]
    if reference is None or not images:
        return ""
    p = image_figures.image_grid(reference, images, page.figdir / f"{slug}_images", title=f"{group}: {scene}, frame {frame}")
    frame_html = shown(frame, Stored("results.parquet", cells.index[0], "frame"))
    return figure_html(p, page.root, f"{html.escape(scene)}, frame {frame_html}: each method (a ladder at its largest k or "
                   "spp; the viewer below has every option) with its image, the same zoomed crop "
                   "(red box, around the largest error) and its signed error, the mean of the R, G, B errors, on "
                   f"one symmetric scale shared by every row (red: too bright, blue: too dark); {figures.UNIT}. {ref}")


def _speed_section(page: _Page, results: pd.DataFrame, speed: pd.DataFrame) -> str:
    """The speed pass (``speed.parquet``): the only times charted; with each ``accuracy`` group,
    the speed-accuracy chart (each method's ladder and the Pareto front)."""
    out = ["<h2 id='speed'>Speed</h2>"]
    if speed.empty:
        out.append("<p class='warn'>This sweep has no speed pass (no [[speed]] table in its config): no time is "
                   "charted. The accuracy cells' render times in the tables may come from several workers sharing "
                   "the machine and are not comparable.</p>")
        return "\n".join(out)
    summary = page.data.summary("speed")
    import os

    stored = "summaries/speed.parquet"
    counts = pd.to_numeric(summary["threads"], errors="coerce")
    threads = ", ".join(shown(n, Stored(stored, counts[counts == n].index[0], "threads", ".0f"))
                        for n in sorted(counts.dropna().unique()))
    most = summary["rounds"].idxmax()
    rounds = shown(summary.at[most, "rounds"], Stored(stored, most, "rounds", ".0f"))
    note = (f"Timed in the speed pass, after the accuracy cells: <b>one worker</b> (the sweep's own process), "
            f"<b>{threads} thread(s)</b> for every method with a threads option (Mitsuba keeps its own "
            f"thread pool), on a machine with {os.cpu_count()} cores (see provenance); each method warmed up on its "
            f"own spec (untimed), then {rounds} interleaved rounds (the methods take turns, the order rotating, as "
            "benchmarks/bench_methods.py times them); images of 256 x 256 pixels or more. Time per megapixel: "
            "median of the rounds; bars from the fastest to the slowest round.")
    out.append(f"<p class='note'>{note}</p>")
    for index, rows in summary.groupby("pass", sort=True):
        group = rows["accuracy_group"].dropna().iloc[0] if rows["accuracy_group"].notna().any() else None
        scenes = list(dict.fromkeys(rows["scene"]))
        per = rows.groupby("spec", sort=False).agg(
            label=("label", "first"), method=("method", "first"), options=("options", "first"),
            ms_per_mpix=("ms_per_mpix", "median"), ms_per_mpix_min=("ms_per_mpix_min", "min"),
            ms_per_mpix_max=("ms_per_mpix_max", "max")).reset_index()
        specs = page.data.summary("specs")
        if group is not None and page.primary in specs:
            acc = specs[specs["group"] == group].set_index("spec")[page.primary]
            data = per.assign(**{page.primary: per["spec"].map(acc)}).dropna(subset=[page.primary, "ms_per_mpix"])
            if not data.empty:
                noise = _noise(results[results["group"] == group])
                p = figures.speed_accuracy(data, page.figdir / f"speed_accuracy_{index}", metric=page.primary,
                                           title=f"speed against accuracy (speed pass, one worker; error: {group})",
                                           styles=page.styles, noise=noise)
                out.append(figure_html(p, page.root, f"Render time per megapixel in the speed pass (one worker, {threads} "
                           f"thread(s); median over {', '.join(map(html.escape, scenes))} of the medians of "
                           f"{rounds} interleaved rounds; bar: fastest to slowest round) against mean {page.primary} "
                           f"in group <a href='#{html.escape(figure_stem(group))}'>{html.escape(group)}</a> "
                           f"({figures.UNIT}). Dotted lines join one method's option ladder (light: smallest value, "
                           "dark: largest); the dashed step is the Pareto front (no method is both faster and more "
                           "accurate than a point on it); the grey band is the ground truth's measured noise."))
        table = rows[["scene", "width", "height", "label", "threads", "rounds", "render_ms", "ms_per_mpix",
                      "ms_per_mpix_min", "ms_per_mpix_max"]].copy()
        ratios = []
        for scene, r in table.groupby("scene", sort=False):
            by = r.set_index("label")["render_ms"]
            if "skia" in by and "catmull" in by:
                ratios.append(f"{html.escape(scene)} ({int(r['width'].iloc[0])}x{int(r['height'].iloc[0])}): "
                              f"catmull / Skia = {by['catmull'] / by['skia']:.3g}")
        out.append(page.stored_table(table, stored, f"speed_pass_{index}", "Speed pass: render time per scene and method",
                                     {"label": "method (options)", "render_ms": "render ms (median)",
                                      "ms_per_mpix": "ms/Mpix (median)", "ms_per_mpix_min": "fastest",
                                      "ms_per_mpix_max": "slowest"}))
        if ratios:
            out.append("<p class='note'>Time ratios on the same scene: " + "; ".join(ratios) + ". "
                       "benchmarks/bench_methods.py times the same scene the same way (see docs/sweeps.md) for "
                       "the ratio to compare.</p>")
    return "\n".join(out)


def _provenance(root: Path, results: pd.DataFrame) -> str:
    """Machine, cores, threads and library versions of the run (``DIR/provenance.json``,
    written once per sweep run; older folders lack it)."""
    path = root / "provenance.json"
    try:
        found = json.loads(path.read_text()) if path.is_file() else None
    except (OSError, ValueError):
        found = None
    if not isinstance(found, dict):
        hosts = ", ".join(sorted(map(str, results["host"].dropna().unique()))) if "host" in results else ""
        return (f"<p class='note'>Machine: {html.escape(hosts or 'unknown')}. This sweep folder records no "
                "cores, threads or library versions (no provenance.json: it predates them).</p>")
    items = []

    def walk(prefix, value):
        if isinstance(value, dict):
            for k, v in value.items():
                walk(f"{prefix}.{k}" if prefix else str(k), v)
        else:
            items.append(f"<dt>{html.escape(prefix)}</dt><dd>{html.escape(str(value))}</dd>")

    walk("", found)
    return ("<h3>Where this ran (<a href='provenance.json'>provenance.json</a>)</h3><dl class='prov'>"
            + "".join(items) + "</dl>")


def _timing_note(results: pd.DataFrame) -> str:
    hosts = results["host"].dropna().unique() if "host" in results else []
    return (f"Rendered on {len(hosts)} host(s): {html.escape(', '.join(map(str, hosts)))}. " if len(hosts) else "")


def write_report(directory: str | Path, *, quiet: bool = True, formats=figures.FORMATS) -> Path:
    """Write ``DIR/index.html`` with ``DIR/figures/``, ``DIR/tables/`` and ``DIR/viewer/``;
    ``formats``: of the figures (``"svg"`` and ``"pdf"`` beside every PNG unless left out)."""
    data = read_sweep(directory)
    with figures.drawing(formats):  # the page is written once every figure is
        page_text = _page_text(data, quiet)
    index = data.store.root / "index.html"
    atomic_write(index, lambda tmp: Path(tmp).write_text(page_text))
    return index


def _page_text(data: SweepData, quiet: bool) -> str:
    """The page's HTML; its figures, tables and viewer data are written on the way."""
    store, manifest, results, temporal, speed = data.store, data.manifest, data.results, data.temporal, data.speed
    page = _Page(data)
    distinct = {c["key"] for c in manifest["cells"]}
    failed = (failed_cells(results, page.primary, page.fail_above, page.shaded) if not results.empty
              else pd.Series(dtype=bool))
    n_failed = int(failed[~results["key"].duplicated()].sum()) if not results.empty else 0
    n_errors = int(results.loc[~results["key"].duplicated(), "error"].notna().sum()) if not results.empty else 0
    done = results["key"].nunique() if not results.empty else 0

    parts = [f"<h1>{html.escape(manifest['experiment'])}</h1>",
             f"<p>{html.escape(manifest.get('description', ''))}</p>",
             f"<p class='note'>{done} of {len(distinct)} distinct cells finished ({n_failed} failed by the "
             f"definition in <a href='#how-to-read'>how to read</a>, {n_errors} of them because the render raised an "
             f"error; {len(distinct) - done} pending). Code version {html.escape(manifest.get('code_version', '?'))}. "
             f"Generated {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. "
             + (_timing_note(results) if not results.empty else "") + "</p>"]
    if not results.empty:
        parts.append(findings_section(data, speed_note="See <a href='#speed'>Speed</a>."))
    groups = list(dict.fromkeys(c["group"] for c in manifest["cells"]))
    parts.append("<p>Sections: <a href='#findings'>findings</a>, <a href='#how-to-read'>how to read this report</a>, "
                 "<a href='#ground-truth'>ground truth</a>, <a href='#overview'>overview</a>, <a href='#speed'>speed</a>"
                 "; groups: "
                 + ", ".join(f"<a href='#{html.escape(figure_stem(g))}'>{html.escape(g)}</a>" for g in groups) + "</p>")
    parts.append(_how_to_read(page))
    parts.append(_provenance(store.root, results))
    parts.append("<p>Data: <a href='results.parquet'>results.parquet</a> (one row per cell), "
                 "<a href='temporal.parquet'>temporal.parquet</a> (one row per animation), "
                 + ("<a href='speed.parquet'>speed.parquet</a> (the speed pass), " if not speed.empty else "") +
                 "<a href='experiment.toml'>experiment.toml</a> (the config as run), "
                 "<a href='manifest.json'>manifest.json</a>.</p>")
    if not results.empty:
        parts.append(_policy_section(page, results))
        parts.append(_overview(page))
    for group in groups:
        rows = results[results["group"] == group] if not results.empty else results
        if rows.empty:
            parts.append(f"<h2 id='{html.escape(figure_stem(group))}'>{html.escape(group)}</h2>"
                         "<p>No finished cells yet.</p>")
        else:
            parts.append(_group_section(page, group, rows, temporal, failed))
        if not quiet:
            print(f"report: group {group} drawn", file=sys.stderr, flush=True)
    parts.append(_speed_section(page, results, speed))
    if not results.empty:
        parts.append(specular_section(store.root, page.figdir, data,
                                      styles=page.styles, detection=data.detection))
        parts.append(filters_section(store.root, page.figdir, data, page.styles))
    scripts = "".join(f"<script src='{html.escape(s)}'></script>" for s in page.viewer_scripts)
    return ("<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
            f"<title>{html.escape(manifest['experiment'])} — aaeval report</title><style>{_CSS}</style>"
            f"<script>{viewer_script()}</script></head>"
            f"<body>{''.join(parts)}{scripts}<script>AAV.init();</script></body></html>\n")

