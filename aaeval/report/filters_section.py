"""Report section of the pixel-filter groups (``filters*``): exact against sampled, and how much
each filter lets a picket fence flicker. It draws the sweep's stored ``filters`` summary and
computes nothing: every value is a registered metric (:mod:`aaeval.metrics`) the sweep
measured, averaged per (filter, method) by :func:`aaeval.sweeps.aggregate.per_spec`.

Each cell of these groups was judged against the ground truth through its own filter
(``mitsuba:filter=F``, or ``catmull:filter=F`` for an exact reference;
:func:`aaeval.sweeps.cells.reference_for`), never against the box.
"""

from __future__ import annotations

import html
from pathlib import Path

import numpy as np
import pandas as pd

from aaeval.report.sweep_data import METRICS
from aaeval.report.figures import UNIT, metric_label, save_figure
from aaeval.sweeps.summaries import FILTER_ORDER
from aaeval.report.style import Styles
from aaeval.report.html_tables import stored_cells, write_table

__all__ = ["filters_section"]

_MEASURES = ("rmse", "temporal_bias", "flicker", "image_flicker")
_STORED = "summaries/filters.parquet"


def _chart(table: pd.DataFrame, path: Path, styles: Styles, group: str) -> Path:
    import matplotlib.pyplot as plt

    methods = list(dict.fromkeys(table["method"]))
    filters = [f for f in FILTER_ORDER if f in set(table["filter"])]
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8), gridspec_kw={"wspace": 0.3})
    width = 0.8 / max(1, len(methods))
    for panel, (ax, name) in enumerate(zip(axes, ("image_flicker", "rmse"))):
        for j, method in enumerate(methods):
            rows = table[table["method"] == method].set_index("filter").reindex(filters)
            first = table[table["method"] == method].iloc[0]
            st = styles.spec(first["style_method"], first["options"])
            ax.bar(np.arange(len(filters)) + (j - (len(methods) - 1) / 2) * width, rows[name].to_numpy(float),
                   width=width, color=st.colour, edgecolor="black", lw=0.5, label=method if panel == 0 else None,
                   hatch=None if j % 2 == 0 else "//", gid=st.gid)
        ax.set_xticks(range(len(filters)), filters, fontsize=7.5)
        # the unit stands in the caption (UNIT): as an axis label it ran the height of the figure
        ax.set_ylabel(metric_label(name), fontsize=8)
        ax.grid(True, axis="y", alpha=0.3)
        ax.set_title(METRICS[name].summary, fontsize=7.5)
    fig.legend(loc="upper center", bbox_to_anchor=(0.5, 0.0), ncols=min(4, len(methods)), fontsize=8)
    fig.suptitle(f"{group}: each filter, exact and sampled", fontsize=9.5)
    return save_figure(fig, path)


def filters_section(out_dir: Path, figures_dir: Path, data=None, styles: Styles | None = None) -> str:
    """HTML fragment of the filter groups; empty when the sweep has none. ``data``: the
    sweep's :class:`~aaeval.report.sweep_data.SweepData` (read from ``out_dir`` when not given)."""
    out_dir, figures_dir = Path(out_dir), Path(figures_dir)
    if data is None:
        from aaeval.report.sweep_data import read_sweep

        data = read_sweep(out_dir)
    styles = styles or Styles.from_sweep(data.specs)
    stored = data.summary("filters")
    if stored.empty:
        return ""
    groups = list(dict.fromkeys(stored["group"]))
    parts = ["<h2 id='filters'>Pixel filters</h2>",
             "<p>Every filter as Mitsuba 3 defines it and normalises its film (docs/filters.md). <code>catmull:filter=F"
             "</code> integrates the visible pieces against the filter exactly; the samplers use the same filter. "
             "<b>Each cell is judged against the ground truth through its own filter</b> "
             "(<code>mitsuba:filter=F</code> at the group's spp, cached under its own key), so an exact render "
             "lands on the ground truth's noise whatever its filter. All values are registered metrics from "
             "<a href='results.parquet'>results.parquet</a> and <a href='temporal.parquet'>temporal.parquet</a>, "
             f"mean over the group's cells or animations, {UNIT}: "
             + "; ".join(f"<b>{html.escape(METRICS[m].title)}</b>: {html.escape(METRICS[m].summary)}"
                         for m in _MEASURES) + ".</p>"]
    figures_dir.mkdir(parents=True, exist_ok=True)
    for group in groups:
        table = stored[stored["group"] == group]
        slug = "".join(c if c.isalnum() else "_" for c in group)
        png = _chart(table, figures_dir / f"filters_{slug}", styles, group)
        try:
            src = png.relative_to(out_dir).as_posix()
        except ValueError:
            src = png.as_posix()
        parts.append(f"<h3>{html.escape(group)}</h3><figure><img src='{html.escape(src)}' "
                     f"alt='{html.escape(group)}: filters'><figcaption>Left: the image's own flicker inside the "
                     "scene's interior (the picket fences' bars repeat at or above the Nyquist rate, so an ideal "
                     "low-pass image is constant there: every change is aliasing the filter let through). Right: "
                     f"RMSE against the ground truth through the same filter. {UNIT}.</figcaption></figure>")
        renamed = {"noise": "ground truth noise RMS", **{m: METRICS[m].title for m in _MEASURES}}
        shown = table.drop(columns=["group", "spec", "style_method", "options"]).rename(columns=renamed)
        where = stored_cells(shown, _STORED, table.index, renamed)
        parts.append(write_table(shown.reset_index(drop=True), out_dir / "tables", f"filters_{slug}", out_dir,
                                 f"{group}: every filter, exact and sampled, against its own ground truth",
                                 where.reset_index(drop=True)))
    return "\n".join(parts)
