"""The speed section: the speed pass's times (the only times charted), its chart against each
``accuracy`` group's errors with the Pareto front, a table per pass, and the time ratios of the
methods that declare a speed baseline (``specs.json``'s ``speed_baselines``)."""

from __future__ import annotations

import html

import pandas as pd

from aaeval.report import figures
from aaeval.report.html_tables import Stored, shown
from aaeval.report.names import figure_stem
from aaeval.report.page import Page, figure_html, truth_noise


def speed_section(page: Page, results: pd.DataFrame, speed: pd.DataFrame) -> str:
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
                noise = truth_noise(results[results["group"] == group])
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
        ratios = speed_ratios(table, page.data.specs.get("speed_baselines", {}))
        out.append(page.stored_table(table, stored, f"speed_pass_{index}", "Speed pass: render time per scene and method",
                                     {"label": "method (options)", "render_ms": "render ms (median)",
                                      "ms_per_mpix": "ms/Mpix (median)", "ms_per_mpix_min": "fastest",
                                      "ms_per_mpix_max": "slowest"}))
        if ratios:
            out.append("<p class='note'>Time ratios on the same scene: " + "; ".join(ratios) + ". "
                       "benchmarks/bench_methods.py times the same scene the same way (see docs/sweeps.md) for "
                       "the ratio to compare.</p>")
    return "\n".join(out)


def speed_ratios(table: pd.DataFrame, baselines: dict[str, str]) -> list[str]:
    """Per scene of a speed pass, the render time of each method over that of the method it
    declares as its speed baseline (``baselines``: method name to baseline's name, as the sweep
    stored them), both run with their default options (their label is their name)."""
    ratios = []
    for scene, r in table.groupby("scene", sort=False):
        by = r.set_index("label")["render_ms"]
        for method, baseline in baselines.items():
            if method in by and baseline in by:
                ratios.append(f"{html.escape(scene)} ({int(r['width'].iloc[0])}x{int(r['height'].iloc[0])}): "
                              f"{html.escape(method)} / {html.escape(baseline)} = {by[method] / by[baseline]:.3g}")
    return ratios
