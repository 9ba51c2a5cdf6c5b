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

import pandas as pd

from aaeval.fileio import atomic_write
from aaeval.report import figures
from aaeval.report.filters_section import filters_section
from aaeval.report.findings import findings_section
from aaeval.report.ground_truth_section import ground_truth_section
from aaeval.report.group_section import group_section
from aaeval.report.how_to_read import how_to_read_section
from aaeval.report.names import figure_stem
from aaeval.report.overview_section import overview_section
from aaeval.report.page import Page
from aaeval.report.specular_section import specular_section
from aaeval.report.speed_section import speed_section
from aaeval.report.sweep_data import SweepData, read_sweep
from aaeval.report.viewer import VIEWER_CSS, viewer_script
from aaeval.sweeps.aggregate import failed_cells

__all__ = ["write_report"]


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
    page = Page(data)
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
    parts.append(how_to_read_section(page))
    parts.append(_provenance(store.root, results))
    parts.append("<p>Data: <a href='results.parquet'>results.parquet</a> (one row per cell), "
                 "<a href='temporal.parquet'>temporal.parquet</a> (one row per animation), "
                 + ("<a href='speed.parquet'>speed.parquet</a> (the speed pass), " if not speed.empty else "") +
                 "<a href='experiment.toml'>experiment.toml</a> (the config as run), "
                 "<a href='manifest.json'>manifest.json</a>.</p>")
    if not results.empty:
        parts.append(ground_truth_section(page, results))
        parts.append(overview_section(page))
    for group in groups:
        rows = results[results["group"] == group] if not results.empty else results
        if rows.empty:
            parts.append(f"<h2 id='{html.escape(figure_stem(group))}'>{html.escape(group)}</h2>"
                         "<p>No finished cells yet.</p>")
        else:
            parts.append(group_section(page, group, rows, temporal, failed))
        if not quiet:
            print(f"report: group {group} drawn", file=sys.stderr, flush=True)
    parts.append(speed_section(page, results, speed))
    if not results.empty:
        parts.append(specular_section(store.root, page.figdir, data,
                                      styles=page.styles, detection=data.detection))
        parts.append(filters_section(store.root, page.figdir, data, page.styles))
    scripts = "".join(f"<script src='{html.escape(s)}'></script>" for s in page.viewer_scripts)
    return ("<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
            f"<title>{html.escape(manifest['experiment'])} — aaeval report</title><style>{_CSS}</style>"
            f"<script>{viewer_script()}</script></head>"
            f"<body>{''.join(parts)}{scripts}<script>AAV.init();</script></body></html>\n")


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
