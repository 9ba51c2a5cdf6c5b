"""One group's section of the page: its reference, accuracy chart, the charts over the frames of
its animations, stability against difficulty, the image grid, the viewer and its tables."""

from __future__ import annotations

import html
import json

import pandas as pd

from aaeval.report import figures, image_figures
from aaeval.report.html_tables import Stored, shown
from aaeval.report.names import figure_stem
from aaeval.report.overview_section import SPECS
from aaeval.report.page import Page, figure_html, truth_noise
from aaeval.report.ground_truth_section import reference_statement
from aaeval.report.style import Styles
from aaeval.report.sweep_data import METRICS
from aaeval.report.viewer import GROUP_BUDGET, scene_series, viewer_div, viewer_payload, write_viewer_data


def group_section(page: Page, group: str, rows: pd.DataFrame, temporal: pd.DataFrame, failed: pd.Series) -> str:
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


def _accuracy_block(page: Page, group: str, slug: str, summary: pd.DataFrame, rows: pd.DataFrame,
                    ref: str) -> str:
    """Accuracy per spec. The accuracy cells may run in parallel, so their times are never
    charted: speed comes from the speed pass (:mod:`aaeval.sweeps.speed`)."""
    primary = page.primary
    noise = truth_noise(rows)
    data = summary.dropna(subset=[primary])
    if data.empty:
        return ""
    p = figures.accuracy_dots(data, page.figdir / f"{slug}_accuracy", metric=primary,
                              title=f"{group}: accuracy", styles=page.styles, noise=noise)
    return figure_html(p, page.root, f"Mean {primary} per method and option (bar: best to worst cell), "
                   f"{figures.UNIT}. {ref} The grey band is the ground truth's measured noise. Times of these cells "
                   "are not charted (cells may share the machine): see <a href='#speed'>Speed</a>.")


def _temporal_block(page: Page, group: str, slug: str, rows: pd.DataFrame, temp: pd.DataFrame,
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


def _grid(page: Page, ok: pd.DataFrame, slug: str, group: str, ref: str) -> str:
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
