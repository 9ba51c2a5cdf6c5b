"""The report's figures: one plain function per chart, ``(data, path, ..., styles) -> path``.

Every figure is written three times beside each other: PNG (for the page), SVG and PDF
(for a paper). Every method is drawn in the style :mod:`aaeval.report.style` gives it, and
every artist of a spec carries ``gid="method=NAME;options=k=v,..."`` (kept in the SVG) so that tests can
check that a method looks the same in every figure.

Errors are drawn on log axes without an invented floor: the ground truth's measured noise
is a grey band (an exact method's error against a noisy ground truth lands on it), and an
error that is zero up to float rounding (below :data:`EXACT_BELOW`, possible only against
an exact reference) is drawn on a marked "exact" strip under the axis' data range.
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import matplotlib

from aaeval.report.names import MATHTEXT_OFF

matplotlib.use("Agg")
matplotlib.rcParams.update(MATHTEXT_OFF)  # group names and labels are text: "$5" is no mathtext
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from aaeval.report import chart_parts, figure_files  # noqa: E402
from aaeval.report.figure_files import FORMATS, drawing, twin_formats  # noqa: E402,F401 - the figures' API
from aaeval.report.style import Styles, ground_truth_style  # noqa: E402

__all__ = ["EXACT_BELOW", "UNIT", "FORMATS", "drawing", "twin_formats", "metric_label", "temporal_bars", "save_figure", "pareto_front", "speed_accuracy", "accuracy_dots", "error_per_frame",
           "intensity_sums", "phase_figure", "stability", "validation"]

# An error this small is float64 rounding of an exact render against an exact reference.
EXACT_BELOW = 1e-10
#: The one unit of every error on the page, stated in every caption.
UNIT = ("unit: linear RGB per channel (error maps: the mean of the R, G, B errors; RMSE and flicker: root mean square "
        "over pixels and channels)")
plt.rcParams.update({"svg.fonttype": "none", "pdf.fonttype": 42, "font.size": 9, "legend.fontsize": 7.5,
                     "axes.titlesize": 9.5})


def metric_label(name: str) -> str:
    """A metric's axis label from the registry: its title and which way is better."""
    from aaeval.report.sweep_data import METRICS

    m = METRICS.get(name)
    return name if m is None else f"{m.title} ({m.direction})"


def save_figure(fig, path: Path) -> Path:
    """Write the figure (:func:`aaeval.report.figure_files.save`) with its log axes' ticks
    in plain numbers; return the PNG path."""
    _plain_log_axes(fig)
    return figure_files.save(fig, path)


def _sorted_specs(rows: pd.DataFrame, styles: Styles) -> list[tuple[str, pd.DataFrame]]:
    """(label, rows) per spec, in legend order (method, then option value)."""
    out = [(spec, r) for spec, r in rows.groupby("spec", sort=False)]
    out.sort(key=lambda item: styles.order(item[1]["method"].iloc[0], item[1]["options"].iloc[0]))
    return [(r["label"].iloc[0], r) for _, r in out]


def _spec_style(rows: pd.DataFrame, styles: Styles):
    return styles.spec(rows["method"].iloc[0], rows["options"].iloc[0])


def _noise_band(ax, noise, *, axis: str = "y", label: str = "ground-truth noise (measured)") -> None:
    """Grey band from the smallest to the largest measured noise of the ground truth."""
    noise = np.asarray(noise, dtype=float)
    noise = noise[np.isfinite(noise) & (noise > 0)]
    if noise.size == 0:
        return
    lo, hi = float(noise.min()), float(noise.max())
    if hi <= lo * 1.05:
        lo, hi = lo / 1.1, hi * 1.1
    span = ax.axhspan if axis == "y" else ax.axvspan
    span(lo, hi, color="0.55", alpha=0.25, lw=0, zorder=0, label=label)


def _log_limits(values, noise=()) -> tuple[float, float, bool]:
    """Log-axis limits from the data (no floor; at least two decades) and whether an
    "exact" strip is needed."""
    v = np.asarray(list(values), dtype=float)
    n = np.asarray(list(noise), dtype=float)
    pos = np.concatenate([v[np.isfinite(v) & (v >= EXACT_BELOW)], n[np.isfinite(n) & (n > 0)]])
    exact = bool(np.any(np.isfinite(v) & (v < EXACT_BELOW)))
    if pos.size == 0:
        return 1e-3, 1.0, exact
    lo, hi = float(pos.min()) / 2.0, float(pos.max()) * 2.0
    lo = min(lo, hi / 100.0)
    if exact:  # room under the data for the strip: a tenth of the axis
        lo = lo / (hi / lo) ** (1 / 9)
    return lo, hi, exact


def _exact_strip(ax, lo: float, hi: float, orientation: str = "y") -> float:
    """Mark the bottom tenth of a log axis as the "exact" strip; returns where exact points go."""
    top = lo * (hi / lo) ** 0.1
    at = math.sqrt(lo * top)
    if orientation == "y":
        ax.axhspan(lo, top, color="#cfe3f3", lw=0, zorder=0)
        ax.text(0.995, at, f"exact (error < {EXACT_BELOW:g})", transform=ax.get_yaxis_transform(), ha="right",
                va="center", fontsize=7, color="#23527c")
    else:
        ax.axvspan(lo, top, color="#cfe3f3", lw=0, zorder=0)
        ax.text(at, 1.0, "exact", transform=ax.get_xaxis_transform(), ha="center", va="bottom", fontsize=7,
                color="#23527c")
    return at


_SUPERSCRIPT = str.maketrans("-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079")


def _tick_text(value: float, _pos=None) -> str:
    """A log-axis tick as plain text (mathtext is off for user names): 0.5, 20, 10⁻⁴."""
    if value <= 0 or not math.isfinite(value):
        return ""
    if 1e-2 <= value < 1e4:
        return f"{value:g}"
    exponent = math.floor(math.log10(value) + 1e-9)
    mantissa = value / 10**exponent
    head = "" if abs(mantissa - 1) < 1e-6 else f"{mantissa:g}\u00d7"
    return f"{head}10{str(exponent).translate(_SUPERSCRIPT)}"


def _log_ticks(axis) -> None:
    """Plain-text labels on a log axis: decades, and 2 and 5 between them on short axes."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    lo, hi = sorted(axis.get_view_interval())
    decades = math.log10(hi / lo) if lo > 0 and hi > 0 else 10
    axis.set_major_locator(LogLocator(base=10))
    axis.set_major_formatter(FuncFormatter(_tick_text))
    if decades < 2.5:
        axis.set_minor_locator(LogLocator(base=10, subs=(2.0, 5.0)))
        axis.set_minor_formatter(FuncFormatter(_tick_text))
    else:
        axis.set_minor_formatter(NullFormatter())


def _plain_log_axes(fig) -> None:
    """Every log axis of ``fig`` with plain-text ticks (the default ones are mathtext)."""
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            if axis.get_scale() == "log":
                _log_ticks(axis)


def _frame_ticks(ax) -> None:
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(integer=True))


def _on_axis(values, at: float) -> np.ndarray:
    v = np.asarray(values, dtype=float)
    return np.where(v < EXACT_BELOW, at, v)


def pareto_front(times: np.ndarray, errors: np.ndarray) -> np.ndarray:
    """Indices of the points no other point beats in both time and error, by time."""
    order = np.lexsort((errors, times))
    front, best = [], math.inf
    for i in order:
        if errors[i] < best:
            front.append(i)
            best = errors[i]
    return np.array(front, dtype=int)


@figure_files.figure
def speed_accuracy(summary: pd.DataFrame, path: Path, *, metric: str, title: str, styles: Styles,
                   noise=()) -> Path:
    """Time per megapixel (median, bars from the fastest to the slowest repeat) against mean
    error, log-log; one point per spec, option ladders joined, the Pareto front dashed.

    ``summary``: one row per spec with ``ms_per_mpix``, ``ms_per_mpix_min``,
    ``ms_per_mpix_max``, ``metric``, ``method``, ``options``, ``label``, ``spec``.
    """
    fig, ax = plt.subplots(figsize=(8.0, 4.8))
    lo, hi, exact = _log_limits(summary[metric], noise)
    at = _exact_strip(ax, lo, hi) if exact else None
    _noise_band(ax, noise)
    for method, rows in summary.groupby("method", sort=False):
        rows = rows.sort_values("ms_per_mpix")
        if len(rows) > 1:
            st = _spec_style(rows, styles)
            y = _on_axis(rows[metric], at) if exact else rows[metric]
            ax.plot(rows["ms_per_mpix"], y, ls=(0, (2, 2)), color=st.colour, lw=0.8, alpha=0.6,
                    gid=f"method={method}")
    for label, r in _sorted_specs(summary, styles):
        st = _spec_style(r, styles)
        x = r["ms_per_mpix"].to_numpy(float)
        y = r[metric].to_numpy(float)
        y = _on_axis(y, at) if exact else y
        err = np.vstack([x - r["ms_per_mpix_min"].to_numpy(float), r["ms_per_mpix_max"].to_numpy(float) - x])
        kw = st.point()
        gid = kw.pop("gid")
        bars = ax.errorbar(x, y, xerr=np.clip(err, 0, None), capsize=2, elinewidth=0.8, ecolor=st.colour,
                           label=label, **kw)
        bars.lines[0].set_gid(gid)  # the point itself; caps and bars are not the method's marker
    t = summary["ms_per_mpix"].to_numpy(float)
    e = summary[metric].to_numpy(float)
    ok = np.isfinite(t) & np.isfinite(e) & (t > 0)
    if ok.sum() > 1:
        idx = np.flatnonzero(ok)[pareto_front(t[ok], e[ok])]
        y = _on_axis(e[idx], at) if exact else e[idx]
        ax.step(t[idx], y, where="post", color="0.2", ls="--", lw=0.8, label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylim(lo, hi)
    _log_ticks(ax.yaxis)
    ax.set_xlabel("render time per megapixel (ms; speed pass, one worker: median of the rounds, bar: fastest to "
                  "slowest)")
    ax.set_ylabel(f"{metric_label(metric)} against the ground truth (mean over cells)")
    chart_parts.placed_title(ax, title)
    ax.grid(True, which="major", alpha=0.3)
    chart_parts.legend(ax, ncols=1 if len(summary) <= 22 else 2)
    return save_figure(fig, path)


@figure_files.figure
def accuracy_dots(summary: pd.DataFrame, path: Path, *, metric: str, title: str, styles: Styles,
                  noise=()) -> Path:
    """Mean error per spec (dot, bar from the best to the worst cell) on a log axis, with the
    ground truth's noise band: the accuracy view of groups whose times are overhead."""
    specs = _sorted_specs(summary, styles)
    fig, ax = plt.subplots(figsize=(7.0, 0.26 * len(specs) + 1.4))
    lo, hi, exact = _log_limits(pd.concat([summary[metric], summary[f"{metric}_min"],
                                           summary[f"{metric}_max"]]), noise)
    if exact:
        at = _exact_strip(ax, lo, hi, "x")
    _noise_band(ax, noise, axis="x")
    for i, (label, r) in enumerate(specs):
        st = _spec_style(r, styles)
        vals = [r[c].iloc[0] for c in (metric, f"{metric}_min", f"{metric}_max")]
        if exact:
            vals = list(_on_axis(vals, at))
        ax.plot([vals[1], vals[2]], [i, i], color=st.colour, lw=1.2, gid=st.gid)
        ax.plot([vals[0]], [i], **st.point())
    ax.set_yticks(range(len(specs)), [label for label, _ in specs], fontsize=7.5)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.set_xlim(lo, hi)
    _log_ticks(ax.xaxis)
    ax.set_xlabel(f"{metric_label(metric)} against the ground truth (dot: mean over cells; bar: best to worst cell)")
    chart_parts.placed_title(ax, title)
    ax.grid(True, axis="x", which="major", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:  # below the axis, never over a point
        ax.legend(loc="upper right", bbox_to_anchor=(1.0, -0.5 / fig.get_figheight() - 0.05), fontsize=7,
                  borderaxespad=0)
    return save_figure(fig, path)


def _scene_axes(scenes: list[str], entries: int, width: float = 7.6):
    height = max(2.6, 0.17 * entries)  # room for the legend beside each panel
    fig, axes = plt.subplots(len(scenes), 1, figsize=(width, height * len(scenes) + 0.4), squeeze=False,
                             gridspec_kw={"hspace": 0.55})
    return fig, axes[:, 0]


def _error_panel(ax, rows: pd.DataFrame, x: str, metric: str, styles: Styles, *, lw: float | None = None) -> None:
    """One scene's ``metric`` against the column ``x`` (frame or phase) on a log axis, one
    curve per spec, the ground truth's noise of each frame as a grey curve."""
    from aaeval.sweeps.summaries import measured_noise

    ref = rows.drop_duplicates("frame").sort_values(x)
    noise = measured_noise(ref)  # a noise-free truth's error bound is no noise
    lo, hi, exact = _log_limits(rows[metric], noise)
    at = _exact_strip(ax, lo, hi) if exact else None
    if noise.fillna(0).gt(0).any():
        ax.plot(ref[x], noise, label="ground-truth noise", **ground_truth_style())
    for label, series in _sorted_specs(rows, styles):
        series = series.sort_values(x)
        style = _spec_style(series, styles).line()
        if lw is not None:
            style["lw"] = lw
        y = _on_axis(series[metric], at) if exact else series[metric]
        ax.plot(series[x], y, label=label, **style)
    ax.set_yscale("log")
    ax.set_ylim(lo, hi)
    _log_ticks(ax.yaxis)
    ax.set_ylabel(metric)
    ax.grid(True, alpha=0.3)


@figure_files.figure
def error_per_frame(results: pd.DataFrame, path: Path, *, metric: str, title: str, styles: Styles) -> Path:
    """The error of every frame, one curve per spec, one panel per animated scene; the
    ground truth's noise of each frame as a grey curve."""
    scenes = list(dict.fromkeys(results["scene"]))
    fig, axes = _scene_axes(scenes, results["spec"].nunique() + 1)
    for ax, scene in zip(axes, scenes):
        _error_panel(ax, results[results["scene"] == scene], "frame", metric, styles)
        _frame_ticks(ax)
        chart_parts.placed_title(ax, scene)
        ax.set_xlabel("frame")
        chart_parts.legend(ax)
    chart_parts.suptitle(fig, title)
    return save_figure(fig, path)


@figure_files.figure
def intensity_sums(results: pd.DataFrame, path: Path, *, title: str, styles: Styles) -> Path:
    """Intensity sum per frame relative to the ground truth's sum of the same frame, on a
    linear axis: 1 is right, and area sampling stays at 1 while the scene moves."""
    scenes = list(dict.fromkeys(results["scene"]))
    fig, axes = _scene_axes(scenes, results["spec"].nunique() + 1)
    for ax, scene in zip(axes, scenes):
        rows = results[results["scene"] == scene]
        ref = rows.drop_duplicates("frame").sort_values("frame")
        base = ref["reference_intensity_sum"].to_numpy(float)
        ax.plot(ref["frame"], base / base[0], label="ground truth (relative to its frame 0)",
                **ground_truth_style())
        for label, series in _sorted_specs(rows, styles):
            series = series.sort_values("frame")
            ax.plot(series["frame"], series["intensity_sum"] / series["reference_intensity_sum"], label=label,
                    **_spec_style(series, styles).line())
        ax.axhline(1.0, color="0.3", lw=0.6)
        _frame_ticks(ax)
        ax.set_title(scene)
        ax.set_xlabel("frame")
        ax.set_ylabel("intensity sum over ground-truth sum")
        ax.grid(True, alpha=0.3)
        chart_parts.legend(ax)
    chart_parts.suptitle(fig, title)
    return save_figure(fig, path)


@figure_files.figure
def phase_figure(results: pd.DataFrame, path: Path, *, metric: str, title: str, styles: Styles) -> Path:
    """Each method's error and intensity sum against the sub-pixel phase of the frame.

    ``results`` has a ``phase`` column (the frame's offset modulo 1 px along x, in [0, 1));
    one row of two panels per scene: ``metric`` on a log axis (the ground truth's noise as a
    grey curve) and the intensity sum over the ground truth's sum of the same frame. A
    method that aliases with its sample grid draws a pattern that repeats with the grid's
    spacing; area sampling is flat.
    """
    scenes = list(dict.fromkeys(results["scene"]))
    height = max(2.6, 0.17 * (results["spec"].nunique() + 1))
    fig, axes = plt.subplots(len(scenes), 2, figsize=(11.5, height * len(scenes) + 0.4), squeeze=False,
                             gridspec_kw={"hspace": 0.55, "wspace": 0.3})
    for (ax_error, ax_sum), scene in zip(axes, scenes):
        rows = results[results["scene"] == scene]
        thin = 0.6  # the phases are samples, not a path: thin joins, the markers carry it
        _error_panel(ax_error, rows, "phase", metric, styles, lw=thin)
        ax_sum.axhline(1.0, color="0.3", lw=0.6)
        for label, series in _sorted_specs(rows, styles):
            series = series.sort_values("phase")
            ax_sum.plot(series["phase"], series["intensity_sum"] / series["reference_intensity_sum"], label=label,
                        **{**_spec_style(series, styles).line(), "lw": thin})
        ax_sum.set_ylabel("intensity sum over ground-truth sum")
        ax_sum.grid(True, alpha=0.3)
        for ax in (ax_error, ax_sum):
            ax.set_xlim(0.0, 1.0)
            ax.set_xlabel("sub-pixel phase of the frame along x (px)")
        chart_parts.placed_title(ax_error, scene)
        ax_sum.set_title(scene)  # linear: its y axis may show an offset text to dodge
        chart_parts.legend(ax_sum)
    chart_parts.suptitle(fig, title)
    return save_figure(fig, path)


@figure_files.figure
def temporal_bars(temporal: pd.DataFrame, path: Path, *, group: str, metrics: list[str], title: str,
                  styles: Styles) -> Path:
    """One panel per temporal metric (registered, from temporal.parquet): a bar per spec, mean over
    the group's animations (:func:`aaeval.sweeps.aggregate.per_spec`, the findings' aggregation),
    linear axes, the ground truth's noise RMS dashed where the metric is an RMS of errors."""
    from aaeval.report.sweep_data import METRICS
    from aaeval.sweeps.aggregate import per_spec

    tables = {m: per_spec(temporal, group, m) for m in metrics}
    specs = tables[metrics[0]]
    order = sorted(specs.itertuples(), key=lambda r: styles.order(r.method, r.options))
    fig, axes = plt.subplots(1, len(metrics), figsize=(3.3 * len(metrics) + 2.2, 0.26 * len(order) + 1.5),
                             squeeze=False, sharey=True, gridspec_kw={"wspace": 0.08})
    for ax, name in zip(axes[0], metrics):
        values = tables[name].set_index("spec")["value"]
        for i, r in enumerate(order):
            st = styles.spec(r.method, r.options)
            ax.barh(i, values.get(r.spec, np.nan), color=st.colour, edgecolor=_bar_edge(st), lw=0.8,
                    hatch=_HATCH.get(st.fillstyle), gid=st.gid)
        noise = tables[name]["noise"].dropna()
        if name in ("flicker", "temporal_bias") and len(noise) and noise.max() > 0:
            ax.axvline(float(noise.mean()), color="0.35", ls="--", lw=1)
            ax.text(float(noise.mean()), -0.7, " truth noise", fontsize=6.5, color="0.35", va="bottom")
        metric = METRICS[name]
        if metric.target is not None:
            ax.axvline(metric.target, color="0.2", lw=0.8)
        else:
            ax.set_xlim(0, None)
        ax.set_xlabel(f"{metric.title} ({metric.direction})", fontsize=7.5)
        ax.grid(True, axis="x", alpha=0.3)
    axes[0, 0].set_yticks(range(len(order)), [r.label for r in order], fontsize=7.5)
    axes[0, 0].invert_yaxis()
    chart_parts.suptitle(fig, title)
    return save_figure(fig, path)


_HATCH = {"full": None, "none": "///", "left": "\\\\", "right": "xx", "bottom": "..", "top": "--"}


def _bar_edge(st) -> str:
    return "black"


@figure_files.figure
def stability(results: pd.DataFrame, path: Path, *, metric: str, failed, title: str, styles: Styles,
              definition: str) -> Path:
    """Error (left) and fraction of failed cells (right) against difficulty, one line per spec.
    ``failed``: boolean Series over ``results``' index (the report's one definition)."""
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, max(4.2, 0.17 * results["spec"].nunique())),
                                 gridspec_kw={"wspace": 0.25})
    label = results["difficulty_label"].dropna().iloc[0] if results["difficulty_label"].notna().any() else "difficulty"
    from aaeval.sweeps.summaries import measured_noise

    lo, hi, exact = _log_limits(results[metric], measured_noise(results))
    at = _exact_strip(ax, lo, hi) if exact else None
    frames = results.drop_duplicates(["scene", "frame"])
    noise = measured_noise(frames).groupby(frames["difficulty"]).mean()
    if noise.fillna(0).gt(0).any():
        ax.plot(noise.index, noise.to_numpy(float), label="ground-truth noise", **ground_truth_style())
    for spec_label, rows in _sorted_specs(results, styles):
        st = _spec_style(rows, styles)
        by = rows.groupby("difficulty")
        err = by[metric].mean().to_numpy(float)
        ax.plot(by[metric].mean().index, _on_axis(err, at) if exact else err, label=spec_label, **st.line())
        frac = failed.loc[rows.index].groupby(rows["difficulty"]).mean()
        bx.plot(frac.index, frac.to_numpy(float), label=spec_label, **st.line())
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylim(lo, hi)
    _log_ticks(ax.yaxis)
    ax.set_xlabel(label)
    ax.set_ylabel(f"{metric_label(metric)} (mean over cells)")
    ax.grid(True, alpha=0.3)
    bx.set_xscale("log")
    bx.set_xlabel(label)
    bx.set_ylabel("fraction of cells failed")
    # the definition under the panel, wrapped: as its one-line title it set the figure's width
    bx.text(0.5, -0.16, textwrap.fill(definition, 85), transform=bx.transAxes, ha="center", va="top", fontsize=7)
    bx.set_ylim(-0.05, 1.05)
    bx.grid(True, alpha=0.3)
    chart_parts.legend(bx)
    chart_parts.suptitle(fig, title)
    return save_figure(fig, path)


@figure_files.figure
def validation(table: pd.DataFrame, path: Path, *, title: str, styles: Styles) -> Path:
    """Exact method against the ground truth (y) over the ground truth's own noise (x), one
    point per scene frame: on the diagonal, the exact method agrees within the noise."""
    fig, ax = plt.subplots(figsize=(5.6, 4.6))
    vals = pd.concat([table["noise_rmse"], table["rmse"]]).to_numpy(float)
    vals = vals[np.isfinite(vals) & (vals > 0)]
    lo, hi = (vals.min() / 2, vals.max() * 2) if vals.size else (1e-6, 1.0)
    xs = np.geomspace(lo, hi, 10)
    ax.fill_between(xs, xs / 1.5, xs * 1.5, color="0.85", lw=0, label="within 1.5x of the noise")
    ax.plot(xs, xs, color="0.3", lw=0.8, label="error = ground-truth noise")
    for (method, options), rows in table.groupby(["method", "options"], sort=False):
        st = styles.spec(method, options)
        ax.plot(rows["noise_rmse"], rows["rmse"], label=rows["label"].iloc[0], **st.point())
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(lo, hi)
    ax.set_ylim(lo, hi)
    ax.set_xlabel("ground truth's noise RMS (seed-to-seed RMSE / sqrt 2)")
    ax.set_ylabel("exact method's RMSE against the ground truth")
    chart_parts.placed_title(ax, title)
    ax.grid(True, alpha=0.3)
    chart_parts.legend(ax)
    return save_figure(fig, path)


