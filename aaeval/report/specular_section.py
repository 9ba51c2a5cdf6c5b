"""The specular study's section of the report: Amanatides 1992 against the exact Phong truth.

It draws the sweep's stored ``specular`` summary and computes no measure: every value is a
registered metric (:mod:`aaeval.metrics`) the sweep measured on the specular groups (scenes
with ``[shaded]`` objects), against the one specular ground truth of the page (the groups'
reference, whose spp is stated once, here), averaged per spec by
:func:`aaeval.sweeps.aggregate.per_spec`, the aggregation the findings and the group
charts use, so the rankings agree:

- the highlight's **bias** (time-average of its energy error) and **flicker** (what is
  left, frame to frame) side by side, as a chart and a table ranked by flicker;
- Amanatides' tables (his figures 2 and 3: the power cutoff of cos^n, and what clamping
  with renormalisation does to the lobe's cosine components) and where his detector flags
  the sweep's first scene with shaded objects (no ground truth involved: the paper's own
  quantities; the sweep ran the detector and stored its maps, ``specular_detection.npz``).

The images of every method (and the truth) are in the specular group's image grid and viewer.
The section appears when the sweep has scenes with ``[shaded]`` objects; otherwise it is empty.
"""

from __future__ import annotations

import html
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from scipy.special import gammaln  # noqa: E402

from aaeval.metrics.info import format_value  # noqa: E402
from aaeval.report.sweep_data import METRICS  # noqa: E402
from aaeval.report.figures import UNIT, save_figure, twin_formats  # noqa: E402
from aaeval.sweeps.summaries import SPECULAR_COLUMNS, shaded_groups  # noqa: E402
from aaeval.report.html_tables import Stored, shown  # noqa: E402
from aaeval.report.style import Styles  # noqa: E402
from aaeval.specular.tables import cutoff_table, maximum  # noqa: E402

__all__ = ["specular_section", "verdicts", "BIAS", "FLICKER", "ERROR", "STORED"]

#: The columns of the section: registered metric names.
ERROR, BIAS, FLICKER = SPECULAR_COLUMNS
STORED = "summaries/specular.parquet"


def _reference(refs: pd.DataFrame) -> str:
    """The truth of the shaded groups (``refs``: their rows of the stored ``references``)."""
    parts = []
    for i, r in refs.drop_duplicates("reference").iterrows():
        at = lambda column, f="": Stored("summaries/references.parquet", i, column, f)  # noqa: E731
        noise = shown(r["noise_mean"], at("noise_mean", ".2e"))
        if r["kind"] == "exact":
            # catmull:shading=exact: no samples, so no sampling noise; the quadrature's own
            # error bound (RMS per pixel) is what the sweep recorded as its noise
            parts.append(f"<code>{html.escape(r['reference'])}</code> (the Phong model integrated exactly over every "
                         f"visible piece: no sampling noise; its quadrature error bound, RMS {noise} per "
                         "pixel: a bound, not noise)")
            continue
        spp = "" if pd.isna(r["spp"]) else f"{shown(r['spp'], at('spp', '.0f'))} spp, "
        seed = "" if pd.isna(r["seed"]) else f"seed {shown(r['seed'], at('seed', '.0f'))}; "
        parts.append(f"<code>{html.escape(r['reference'])}</code> ({spp}{seed}noise RMS {noise}, seed 1 "
                     "against seed 0)")
    return "; ".join(parts)


def _is_baseline(row, options: dict) -> bool:
    """``catmull:specular=none`` with the default per-piece shading: one shade per visible piece."""
    return row.method == "catmull" and options.get("specular") == "none" and options.get("shading") == "piece"


def verdicts(table: pd.DataFrame, styles: Styles) -> list[str]:
    """One sentence per clamp of a group's table (:func:`specular_table`), against the
    group's truth: its highlight flicker and error beside ``catmull:specular=none``'s (the
    one-shade-per-piece baseline), and the Mitsuba cross-check rows' error."""
    options = {r.spec: styles.options(r.method, r.options) for r in table.itertuples()}
    base = [r for r in table.itertuples() if _is_baseline(r, options[r.spec])]
    out = []
    for r in table.itertuples():
        if r.method == "mitsuba":
            role = "cross-check" if int(options[r.spec].get("spp", 0)) >= 4096 else "sampled"
            out.append(f"{html.escape(r.label)} ({role}): {METRICS[ERROR].title} {METRICS[ERROR].format(getattr(r, ERROR))} "
                       f"against this truth, bias {METRICS[BIAS].format(getattr(r, BIAS))}.")
            continue
        if not base or r.method != "catmull" or _is_baseline(r, options[r.spec]):
            continue
        b = base[0]
        f0, f1 = getattr(b, FLICKER), getattr(r, FLICKER)
        e0, e1 = getattr(b, ERROR), getattr(r, ERROR)
        if f1 > 0 and f0 / f1 >= 2:
            steady = f"{f0 / f1:.3g}x steadier than none"
        elif f1 > 0 and f1 / max(f0, 1e-300) >= 2:
            steady = f"{f1 / max(f0, 1e-300):.3g}x less steady than none"
        else:
            steady = "as steady as none (within 2x)"
        closer = "closer to" if e1 < e0 else "further from"
        out.append(f"{html.escape(r.label)}: {steady} ({METRICS[FLICKER].format(f1)} against "
                   f"{METRICS[FLICKER].format(f0)}); {closer} the truth ({METRICS[ERROR].title} "
                   f"{METRICS[ERROR].format(e1)} against {METRICS[ERROR].format(e0)}), bias "
                   f"{METRICS[BIAS].format(getattr(r, BIAS))}.")
    return out


def specular_section(out_dir: Path, figures_dir: Path, data, *, styles: Styles, detection: dict | None = None) -> str:
    """HTML fragment of the specular study, or "" when the sweep has no shaded scenes
    (``data``: the sweep's :class:`~aaeval.report.sweep_data.SweepData`). ``detection``: the
    detector's maps the sweep stored (``specular_detection.npz``)."""
    out_dir, figures_dir = Path(out_dir), Path(figures_dir)
    groups = shaded_groups(data.results)
    if not groups:
        return ""
    figures_dir.mkdir(parents=True, exist_ok=True)
    rel = _relative_to(figures_dir, out_dir)
    parts = ["<h2 id='specular'>Specular aliasing (Amanatides 1992)</h2>",
             f"<p class='ref'>The specular truth of this page: {_reference(_group_rows(data.summary('references'), groups))}. Mitsuba's Phong render "
             "at 4096 spp (the same Phong formula at every sample, box filter) is the cross-check row of each group "
             "judged against the exact truth; the highlight mask (pixels where its specular term exceeds 0.02) is "
             "read from it. Methods: the Catmull renderer (exact "
             "visibility, one shade per visible piece) under every registered specular method. Values: registered "
             "metrics from results.parquet and temporal.parquet, mean over each group's cells or animations, "
             f"{UNIT}.</p>"]
    stored = data.summary("specular")
    for group in groups:
        table = _group_rows(stored, [group])
        if table.empty:
            continue
        slug = "".join(c if c.isalnum() else "_" for c in group)
        png = _fig_highlight_split(figures_dir / f"specular_bias_flicker_{slug}", table, styles, group)
        parts.append(_figure(rel, png, f"{group}: each method's highlight bias ({METRICS[BIAS].summary}) against "
                                       f"its highlight flicker ({METRICS[FLICKER].summary}). A clamp that widens and "
                                       "dims the highlight wherever it goes sits left (bias), a highlight that pops "
                                       "between frames high (flicker)."))
        parts.append(_html_table(table, group))
        said = verdicts(table, styles)
        if said:
            parts.append(f"<p class='verdict'>Verdict on each clamp in {html.escape(group)}, against this group's "
                         "truth:</p><ul>" + "".join(f"<li>{v}</li>" for v in said) + "</ul>")
    parts.append(_figure(rel, _fig_power_cutoff(figures_dir),
                         "Amanatides' figure 2: frequency below which a fraction of the power of cos^n lies."))
    parts.append(_figure(rel, _fig_clamp_ratio(figures_dir),
                         "Amanatides' figure 3: cosine components of cos^160 clamped to n' and renormalised by "
                         "Maximum[160]/Maximum[n'], over those of cos^160."))
    if detection is not None:
        name = str(detection["scene"])
        parts.append(_figure(rel, _fig_detection(figures_dir / f"specular_detection_{_slug(name)}", detection),
                             f"{name}, frame 0: Amanatides' detection (conservative and P = 0.999) and the "
                             "largest normal turn per pixel (the detector's own output, no ground truth)."))
    return "\n".join(parts)


def _group_rows(stored: pd.DataFrame, groups: list[str]) -> pd.DataFrame:
    return stored[stored["group"].isin(groups)] if not stored.empty else stored


def _html_table(table: pd.DataFrame, group: str) -> str:
    """The stored rows of one group, best flicker first, each cell naming where it is stored."""
    columns = {"label": "method (options), best flicker first", ERROR: METRICS[ERROR].title,
               BIAS: METRICS[BIAS].title, FLICKER: METRICS[FLICKER].title, "noise": "ground truth noise RMS"}
    head = "".join(f"<th>{html.escape(title)}</th>" for title in columns.values())
    body = []
    for i, r in table.iterrows():
        cells = [f"<td {Stored(STORED, i, 'label').attributes()}>{html.escape(r['label'])}</td>"]
        for column in (ERROR, BIAS, FLICKER, "noise"):
            fmt = METRICS[column].fmt if column in METRICS else ".2e"
            where = Stored(STORED, i, column, fmt)
            cells.append(f"<td class='num' {where.attributes()}>{html.escape(format_value(r[column], fmt))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table class='specular' data-group='{html.escape(group)}'><tr>{head}</tr>{''.join(body)}</table>"


def _fig_highlight_split(stem: Path, table: pd.DataFrame, styles: Styles, group: str) -> Path:
    fig, ax = plt.subplots(figsize=(7.6, 4.4))
    ax.axvline(0.0, color="0.4", lw=0.8)
    for r in table.itertuples():
        st = styles.spec(r.method, r.options)
        kw = st.point()
        ax.plot([getattr(r, BIAS)], [getattr(r, FLICKER)], label=r.label, **kw)
    ax.set_xlabel(f"{METRICS[BIAS].title}: {METRICS[BIAS].direction}")
    ax.set_ylabel(f"{METRICS[FLICKER].title} (lower is better)")
    if (table[FLICKER] > 0).all():
        ax.set_yscale("log")
    ax.set_title(f"{group}: highlight bias and flicker (one answer per method)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7.5, borderaxespad=0)
    return save_figure(fig, stem)


def _fig_power_cutoff(figures_dir: Path) -> Path:
    n_max = 1000
    n = np.arange(n_max + 1)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.plot(n, n, "k:", lw=1, label="100 % (highest frequency n)")
    for power in (0.9999, 0.999, 0.99, 0.9):
        ax.plot(n, cutoff_table(n_max, power), label=f"{100 * power:g} % of the power")
    ax.plot([500, 500], [40, 52], "ko", ms=4)
    ax.annotate("n = 500: 52 (99.9 %), 40 (99 %)", (500, 52), (520, 150), arrowprops={"arrowstyle": "-"})
    ax.set(xlabel="n (highest frequency of cos^n)", ylabel="cutoff frequency", ylim=(0, 250),
           title="Power cutoff of cos^n (Amanatides 1992, fig. 2)")
    ax.legend(fontsize=8)
    return save_figure(fig, figures_dir / "specular_fig2_power_cutoff")


def cosine_amplitudes(n: int, m: np.ndarray) -> np.ndarray:
    """Amplitude of cos(m x) in cos^n x (0 where m > n or parities differ)."""
    ok = (m <= n) & ((n - m) % 2 == 0)
    k = (n - m[ok]) // 2
    amp = np.zeros(len(m))
    amp[ok] = np.exp(gammaln(n + 1) - gammaln(k + 1) - gammaln(n - k + 1) - n * np.log(2.0))
    amp[ok & (m > 0)] *= 2
    return amp


def _fig_clamp_ratio(figures_dir: Path) -> Path:
    n = 160
    m = np.arange(0, 81, 2)
    base = cosine_amplitudes(n, m)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for n_clamped in range(20, 141, 20):
        ratio = maximum(n) / maximum(n_clamped) * cosine_amplitudes(n_clamped, m) / base
        ax.plot(m, ratio, marker=".", label=f"n' = {n_clamped}")
    ax.axhline(1.0, color="k", lw=0.6)
    ax.set(xlabel="frequency", ylabel="clamped / original component", ylim=(0, 1.2),
           title="cos^160 clamped to n', renormalised by Maximum[n]/Maximum[n'] (fig. 3)")
    ax.legend(fontsize=8, ncol=2)
    return save_figure(fig, figures_dir / "specular_fig3_clamp_ratio")


def _fig_detection(stem: Path, detection: dict) -> Path:
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.8), layout="constrained")
    for ax, power in zip(axes[:2], (1.0, 0.999)):
        rate, flag = detection[f"rate_{power:g}"], detection[f"flag_{power:g}"]
        im = ax.imshow(np.log2(np.maximum(rate, 1e-3)), cmap="magma", vmin=-4, vmax=8, interpolation="nearest")
        if flag.any():
            ax.contour(flag, levels=[0.5], colors="c", linewidths=0.5)
        ax.set_title(f"log2 oversampling rate, power {power} (cyan: flagged)", fontsize=8)
        fig.colorbar(im, ax=ax, fraction=0.046)
    # the normal's turn does not depend on the power: one map, stored once
    im = axes[2].imshow(np.degrees(np.arccos(detection["dot"])), cmap="viridis", interpolation="nearest")
    axes[2].set_title("largest normal turn in the pixel (degrees)", fontsize=8)
    fig.colorbar(im, ax=axes[2], fraction=0.046)
    for ax in axes:
        ax.set_xticks([])
        ax.set_yticks([])
    return save_figure(fig, stem)


def _figure(rel: str, png: Path, caption: str) -> str:
    src = f"{rel}/{png.name}" if rel else png.name
    twins = "".join(f" <a href='{html.escape(src[:-4])}.{f}'>{f.upper()}</a>" for f in twin_formats())
    return (f"<figure><img src='{html.escape(src)}' alt='{html.escape(caption[:120])}' style='max-width:100%'>"
            f"<figcaption>{html.escape(caption)}{twins}</figcaption></figure>")


def _relative_to(folder: Path, root: Path) -> str:
    try:
        return folder.resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return folder.resolve().as_uri()


def _slug(text: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in text).strip("_") or "scene"
