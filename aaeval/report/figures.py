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

import contextlib
import functools
import inspect
import math
import multiprocessing
import os
import textwrap
import traceback
from concurrent.futures import Future, ProcessPoolExecutor
from pathlib import Path

import matplotlib

from aaeval.report.names import MATHTEXT_OFF

matplotlib.use("Agg")
matplotlib.rcParams.update(MATHTEXT_OFF)  # group names and labels are text: "$5" is no mathtext
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.image  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.transforms import Bbox  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from aaeval.fileio import atomic_write, linear_to_srgb8  # noqa: E402
from aaeval.report.style import Styles, ground_truth_style  # noqa: E402

__all__ = ["EXACT_BELOW", "UNIT", "FORMATS", "drawing", "twin_formats", "metric_label", "temporal_bars", "save_figure", "pareto_front", "speed_accuracy", "accuracy_dots", "error_per_frame",
           "intensity_sums", "phase_figure", "space_time", "stability", "image_grid", "validation"]

# An error this small is float64 rounding of an exact render against an exact reference.
EXACT_BELOW = 1e-10
#: The one unit of every error on the page, stated in every caption.
UNIT = ("unit: linear RGB per channel (error maps: the mean of the R, G, B errors; RMSE and flicker: root mean square "
        "over pixels and channels)")
#: The formats a figure can be written in: the page shows the PNG; SVG and PDF are for papers.
FORMATS = ("png", "svg", "pdf")
_DPI = 100
plt.rcParams.update({"svg.fonttype": "none", "pdf.fonttype": 42, "font.size": 9, "legend.fontsize": 7.5,
                     "axes.titlesize": 9.5})


def _suptitle(fig, text: str, fontsize: float = 10) -> None:
    """A figure title just above the top row's titles (figures use no layout engine:
    constrained layout cost most of the report's time; the tight bounding box keeps it)."""
    top = max((ax.get_position().y1 for ax in fig.axes), default=1.0)
    fig.suptitle(text, y=top + 0.42 / fig.get_figheight(), va="bottom", fontsize=fontsize)


def metric_label(name: str) -> str:
    """A metric's axis label from the registry: its title and which way is better."""
    from aaeval.report.sweep_data import METRICS

    m = METRICS.get(name)
    return name if m is None else f"{m.title} ({m.direction})"


def save_figure(fig, path: Path) -> Path:
    """Write the figure as ``path`` with suffix ``.png`` (what the page shows), and its twins
    in the other formats of :func:`drawing`; close it; return the PNG path. Inside
    :func:`drawing` a worker process writes the files."""
    path = Path(path).with_suffix(".png")
    _plain_log_axes(fig)
    if _workers.executor is not None:
        _workers.submit(path, _write_files, fig, path)
    else:
        _write_files(fig, path)
    plt.close(fig)
    return path


def twin_formats() -> tuple[str, ...]:
    """The formats besides PNG that :func:`save_figure` writes now (for the page's links)."""
    return tuple(f for f in _workers.formats if f != "png")


def _write_files(fig, path: Path) -> None:
    box = _write_png(fig, path)
    for fmt in _workers.formats:
        if fmt != "png":
            # a temporary file moved into place: a link planted at the name is replaced, never written through
            atomic_write(path.with_suffix(f".{fmt}"),
                         lambda tmp, fmt=fmt: fig.savefig(tmp, format=fmt, dpi=_DPI, bbox_inches=box,
                                                          metadata=_metadata(fmt)))


#: Room drawn beside and above/below a figure (inches, whole pixels at :data:`_DPI`) for what
#: lies outside it: legends beside the axes, long tick labels, titles above.
_ROOM = (4.0, 2.0)


def _write_png(fig, path: Path):
    """Write ``path``, the PNG of ``fig``'s tight box, drawing the figure once; return the box
    (inches, with savefig's pad), for the other formats.

    ``savefig(bbox_inches=box)`` lays every text out twice: once to find the box, once more
    for the canvas of the box's size. Here the figure is drawn once on a canvas with
    :data:`_ROOM` around it, the box is measured with the renderer that drew it (its text
    extents cached), widened to whole pixels, and cut out: the same pixels savefig draws
    for the widened box (hatching aside: its pattern starts at the canvas' corner). Where
    the figure reaches beyond the room, savefig draws the box."""
    # a figure sent to a worker comes without pyplot's canvas
    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    fig.set_dpi(_DPI)
    width, height = fig.get_size_inches()
    across, up = _ROOM
    fig.savefig(os.devnull, format="raw", dpi=_DPI,  # the pixels are read from the renderer that drew
                bbox_inches=Bbox.from_extents(-across, -up, width + across, height + up))
    renderer = canvas.renderer
    box = fig.get_tightbbox(renderer).padded(plt.rcParams["savefig.pad_inches"])
    x0, y0 = math.floor(box.x0 * _DPI), math.floor(box.y0 * _DPI)
    x1, y1 = math.ceil(box.x1 * _DPI), math.ceil(box.y1 * _DPI)
    top, left = renderer.height - round(up * _DPI) - y1, round(across * _DPI) + x0  # Agg's rows run downwards
    if min(top, left) >= 0 and left + x1 - x0 <= renderer.width and top + y1 - y0 <= renderer.height:
        cut = np.asarray(renderer.buffer_rgba())[top:top + y1 - y0, left:left + x1 - x0]
        atomic_write(path, lambda tmp: matplotlib.image.imsave(tmp, cut, format="png", origin="upper", dpi=_DPI,
                                                                metadata=_metadata("png")))
    else:
        widened = Bbox.from_extents(x0 / _DPI, y0 / _DPI, x1 / _DPI, y1 / _DPI)
        atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=_DPI, bbox_inches=widened,
                                                   metadata=_metadata("png")))
    return box


def _metadata(fmt: str) -> dict:
    # no creation dates: the same data gives the same files
    return {"png": {"Software": None}, "svg": {"Date": None}, "pdf": {"CreationDate": None}}[fmt]


class _Workers:
    """Processes forked once per report that build and write the figures while the parent
    reads the sweep and writes the page: building and drawing are most of the report's time.
    They live for the whole report, so matplotlib's caches (fonts, text extents) serve
    every figure, and the parent's memory is not copied again for each one. Each file is
    written by one process, so the output is the same as drawing them in turn."""

    def __init__(self):
        self.executor: ProcessPoolExecutor | None = None
        self.formats: tuple[str, ...] = ("png",)
        self.jobs: list[tuple[Path, Future]] = []

    def open(self, count: int, formats: tuple[str, ...]) -> None:
        self.formats = formats
        if count:  # forked at the first job, with what the parent holds then
            self.executor = ProcessPoolExecutor(count, mp_context=multiprocessing.get_context("fork"),
                                                initializer=_in_worker)

    def submit(self, path: Path, work, *args, **kwargs) -> None:
        self.jobs.append((path, self.executor.submit(_job, work, args, kwargs)))

    def close(self, check: bool = True) -> None:
        """Wait for the jobs (``check=False``: for the running ones only, the queued ones are
        dropped) and raise if one failed."""
        executor, jobs = self.executor, self.jobs
        self.executor, self.formats, self.jobs = None, ("png",), []
        if executor is not None:
            executor.shutdown(wait=True, cancel_futures=not check)
        failed = []
        for path, job in jobs:
            if job.cancelled():
                continue
            if job.exception() is not None:  # never ran: its arguments would not pickle, or a worker died
                traceback.print_exception(job.exception())
            if job.exception() is not None or not job.result():
                failed.append(path)
        if failed and check:
            raise RuntimeError(f"drawing {', '.join(p.name for p in failed)} failed (its error is printed above)")


def _in_worker() -> None:
    _workers.executor = None  # a worker draws its figures itself


def _job(work, args, kwargs) -> bool:
    """Run one figure's work in a worker; its error is printed there (the parent names the figure)."""
    try:
        work(*args, **kwargs)
    except BaseException:  # noqa: BLE001 - reported to the parent as a failed figure
        traceback.print_exc()
        return False
    return True


_workers = _Workers()


def _figure(draw):
    """A figure function ``draw(..., path, ...)``: inside :func:`drawing` the whole call,
    building the figure as well as writing it, runs in a worker process (its arguments
    are sent there), and the PNG's path is returned at once."""
    signature = inspect.signature(draw)

    @functools.wraps(draw)
    def call(*args, **kwargs):
        if _workers.executor is None:
            return draw(*args, **kwargs)
        path = Path(signature.bind(*args, **kwargs).arguments["path"]).with_suffix(".png")
        _workers.submit(path, call, *args, **kwargs)  # by its module name: the worker runs it itself
        return path

    return call


@contextlib.contextmanager
def drawing(formats=("png",)):
    """Within this block the figure functions and :func:`save_figure` write ``formats``
    (PNG always; SVG and PDF for papers cost most of the drawing time: PDF subsets its
    fonts) in worker processes, as many as the cores this process may use (none where
    ``os.fork`` is missing); leaving it waits for them all and raises if one failed."""
    unknown = set(formats) - set(FORMATS)
    if unknown:
        raise ValueError(f"unknown figure format(s) {', '.join(sorted(unknown))}; known: {', '.join(FORMATS)}")
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    _workers.open(cores if hasattr(os, "fork") and cores > 1 else 0,
                  tuple(f for f in FORMATS if f in formats or f == "png"))
    try:
        yield
    except BaseException:
        _workers.close(check=False)  # the body's error is the one to see
        raise
    _workers.close()


def _placed_title(ax, text: str, **kw) -> None:
    """An axes title at its usual place, for an axes whose y axis is log, categorical or
    hidden. Matplotlib's automatic placement lays the y axis out once more per title, at
    every draw, to dodge an offset text above it; such an axis never shows one."""
    ax.set_title(text, y=1.0, **kw)


def _opaque_rgba(srgb8: np.ndarray) -> np.ndarray:
    """uint8 sRGB as the float32 RGBA matplotlib turns it into (the same pixels): given
    uint8 RGB it resamples a float64 copy, a fifth of an image grid's drawing time."""
    rgba = np.empty(srgb8.shape[:2] + (4,), np.float32)
    np.divide(srgb8, np.float32(255), out=rgba[..., :3], dtype=np.float32)
    rgba[..., 3] = 1.0
    return rgba


def _legend(ax, *, outside: bool = True, **kw) -> None:
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return
    if outside:
        ax.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0, **kw)
    else:
        ax.legend(handles, labels, **kw)


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


@_figure
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
    _placed_title(ax, title)
    ax.grid(True, which="major", alpha=0.3)
    _legend(ax, ncols=1 if len(summary) <= 22 else 2)
    return save_figure(fig, path)


@_figure
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
    _placed_title(ax, title)
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
    from aaeval.experiments.summaries import measured_noise

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


@_figure
def error_per_frame(results: pd.DataFrame, path: Path, *, metric: str, title: str, styles: Styles) -> Path:
    """The error of every frame, one curve per spec, one panel per animated scene; the
    ground truth's noise of each frame as a grey curve."""
    scenes = list(dict.fromkeys(results["scene"]))
    fig, axes = _scene_axes(scenes, results["spec"].nunique() + 1)
    for ax, scene in zip(axes, scenes):
        _error_panel(ax, results[results["scene"] == scene], "frame", metric, styles)
        _frame_ticks(ax)
        _placed_title(ax, scene)
        ax.set_xlabel("frame")
        _legend(ax)
    _suptitle(fig, title)
    return save_figure(fig, path)


@_figure
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
        _legend(ax)
    _suptitle(fig, title)
    return save_figure(fig, path)


@_figure
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
        _placed_title(ax_error, scene)
        ax_sum.set_title(scene)  # linear: its y axis may show an offset text to dodge
        _legend(ax_sum)
    _suptitle(fig, title)
    return save_figure(fig, path)


@_figure
def temporal_bars(temporal: pd.DataFrame, path: Path, *, group: str, metrics: list[str], title: str,
                  styles: Styles) -> Path:
    """One panel per temporal metric (registered, from temporal.parquet): a bar per spec, mean over
    the group's animations (:func:`aaeval.experiments.aggregate.per_spec`, the findings' aggregation),
    linear axes, the ground truth's noise RMS dashed where the metric is an RMS of errors."""
    from aaeval.report.sweep_data import METRICS
    from aaeval.experiments.aggregate import per_spec

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
    _suptitle(fig, title)
    return save_figure(fig, path)


_HATCH = {"full": None, "none": "///", "left": "\\\\", "right": "xx", "bottom": "..", "top": "--"}


def _bar_edge(st) -> str:
    return "black"


@_figure
def space_time(reference: np.ndarray, series: list[tuple[str, np.ndarray]], path: Path, *, row: int,
               title: str) -> Path:
    """Space-time slices: image row ``row`` of every frame stacked downwards (x: column,
    y: frame), the ground truth first. ``reference`` and each series: (F, H, W, 3)."""
    panels = [("ground truth", reference)] + series
    f, _, w, _ = reference.shape
    cols = min(4, len(panels))
    nrows = math.ceil(len(panels) / cols)
    cell_w = 2.4
    cell_h = max(0.5, cell_w * f / w) + 0.35
    fig, axes = plt.subplots(nrows, cols, figsize=(cell_w * cols, cell_h * nrows), squeeze=False,
                             gridspec_kw={"hspace": 0.35, "wspace": 0.05})
    for ax in axes.ravel():
        ax.axis("off")
    for ax, (name, frames) in zip(axes.ravel(), panels):
        ax.imshow(_opaque_rgba(linear_to_srgb8(frames[:, row])), interpolation="nearest", aspect="auto")
        _placed_title(ax, name, fontsize=7)
    _suptitle(fig, f"{title} (row {row}; x: column, y: frame downwards)")
    return save_figure(fig, path)


@_figure
def stability(results: pd.DataFrame, path: Path, *, metric: str, failed, title: str, styles: Styles,
              definition: str) -> Path:
    """Error (left) and fraction of failed cells (right) against difficulty, one line per spec.
    ``failed``: boolean Series over ``results``' index (the report's one definition)."""
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, max(4.2, 0.17 * results["spec"].nunique())),
                                 gridspec_kw={"wspace": 0.25})
    label = results["difficulty_label"].dropna().iloc[0] if results["difficulty_label"].notna().any() else "difficulty"
    from aaeval.experiments.summaries import measured_noise

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
    _legend(bx)
    _suptitle(fig, title)
    return save_figure(fig, path)


@_figure
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
    _placed_title(ax, title)
    ax.grid(True, alpha=0.3)
    _legend(ax)
    return save_figure(fig, path)


def _crop_box(error: np.ndarray, size: int) -> tuple[int, int, int, int]:
    """A square of ``size`` pixels around the largest error, inside the image."""
    h, w = error.shape
    r, c = np.unravel_index(int(np.argmax(error)), error.shape)
    size = min(size, h, w)
    r0 = int(np.clip(r - size // 2, 0, h - size))
    c0 = int(np.clip(c - size // 2, 0, w - size))
    return r0, r0 + size, c0, c0 + size


@_figure
def image_grid(reference: np.ndarray, images: list[tuple[str, np.ndarray]], path: Path, *, title: str,
               shared: bool = True) -> Path:
    """Rows: the ground truth, then each method; columns: image, zoomed crop, signed error
    (the mean of the R, G, B errors, the page's one unit; red: too bright, blue: too dark) on
    one symmetric scale for the whole figure (``shared=False``: each row its own), stated per row.

    The crop is the same square for every row (around the largest error of any method). The
    panels are laid into one raster shown by one axes (an axes per panel cost most of the
    report's drawing time); names and scales are text beside them.
    """
    errors = [(img - reference).mean(axis=2) for _, img in images]
    common = max((float(np.abs(e).max()) for e in errors), default=0.0)
    worst = np.max(np.abs(np.stack(errors)), axis=0) if errors else np.zeros(reference.shape[:2])
    r0, r1, c0, c1 = _crop_box(worst, max(4, min(reference.shape[:2]) // 3))
    rows = [("ground truth", reference, None)] + [(n, img, err) for (n, img), err in zip(images, errors)]
    h, w = reference.shape[:2]
    # columns: the image, the crop enlarged to a square as tall as the image, the error map
    crop_side = max(h, r1 - r0)
    gap = max(3, max(h, w) // 12)
    lefts = (0, w + gap, w + crop_side + 2 * gap)
    row_height = max(h, crop_side)
    canvas = np.full((len(rows) * (row_height + gap) - gap, lefts[2] + w, 3), 255, np.uint8)
    # the canvas fitted into 10 x 18 in (a long grid is read by scrolling, a wide one is not),
    # an image at most 3 in across
    inches = min(10.0 / canvas.shape[1], 18.0 / canvas.shape[0], 3.0 / max(h, w))
    fig, ax = plt.subplots(figsize=(canvas.shape[1] * inches, canvas.shape[0] * inches))
    ax.set_position([0.0, 0.0, 1.0, 1.0])
    upright = row_height * inches >= 1.3
    for i, (name, img, err) in enumerate(rows):
        top = i * (row_height + gap)
        srgb = linear_to_srgb8(img)
        _put(canvas, top, lefts[0], srgb, h, w)
        _put(canvas, top, lefts[1], srgb[r0:r1, c0:c1], crop_side, crop_side)
        ax.add_patch(plt.Rectangle((c0 - 0.5, top + r0 - 0.5), c1 - c0, r1 - r0, fill=False, ec="red", lw=1))
        # a name reads along a row tall enough for it, across a short one (wide scenes, text)
        ax.text(-gap / 2, top + row_height / 2, name.replace(":", ":\n").replace(",", ",\n"),
                rotation=90 if upright else 0, ha="right", va="center", fontsize=7 if upright else 6)
        if err is not None:
            scale = max(common if shared else float(np.abs(err).max()), np.finfo(float).tiny)
            coloured = plt.get_cmap("RdBu_r")((err / scale + 1) / 2)[..., :3]
            _put(canvas, top, lefts[2], np.round(coloured * 255).astype(np.uint8), h, w)
            ax.text(lefts[2] + w / 2, top - gap / 8,
                    f"signed error, scale ±{scale:.2g}; mean |err| {np.abs(err).mean():.2g}"
                    if np.abs(err).max() > 0 else "no error: identical to the ground truth",
                    ha="center", va="bottom", fontsize=7)
    ax.imshow(_opaque_rgba(canvas), interpolation="nearest")
    ax.text(w / 2, -gap / 8, "image", ha="center", va="bottom", fontsize=8)
    ax.text(lefts[1] + crop_side / 2, -gap / 8, f"crop rows {r0}-{r1 - 1}, cols {c0}-{c1 - 1}", ha="center",
            va="bottom", fontsize=8)
    ax.axis("off")
    fig.suptitle(title, y=1.0 + 0.5 / fig.get_figheight(), va="bottom", fontsize=9)
    return save_figure(fig, path)


def _put(canvas: np.ndarray, top: int, left: int, panel: np.ndarray, height: int, width: int) -> None:
    """``panel`` (uint8 RGB) enlarged by whole pixels (nearest) to fit a ``height`` x ``width``
    box at (top, left)."""
    ph, pw = panel.shape[:2]
    k = max(1, min(height // ph, width // pw))
    big = np.repeat(np.repeat(panel, k, axis=0), k, axis=1)[:height, :width]
    canvas[top:top + big.shape[0], left:left + big.shape[1]] = big
