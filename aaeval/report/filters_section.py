"""Report section of the pixel-filter experiment: flicker against blur, exact against sampled.

Reads the cells of the groups named ``filters*`` of a sweep folder (configs/experiments/
filters.toml, or the ``filters`` group of default.toml) and measures on their stored
images:

- **flicker**: on the picket-fence scenes, the RMS over the fence's interior of every
  pixel's standard deviation across the frames. The bars repeat at or above the Nyquist
  rate, so an ideal low-pass image is constant there: all temporal change is aliasing.
- **edge width** (blur): the 10-90% width of the edge spread function of the nearly
  vertical left edge of the ``edges`` scenes, from every row and frame aligned on the
  edge position its area gives (rows where the edge runs alone, background on one side
  and the quad on the other).
- **error against exact**: RMSE of each sampled render against the exact render with
  the same filter (``catmull:filter=F``), same scene and frame.
- **time**: mean render time of ``catmull:filter=F`` per frame against the box's.

:func:`filters_section` writes the trade-off chart and returns an HTML fragment.
"""

from __future__ import annotations

import html
import json
from pathlib import Path

import numpy as np
import pandas as pd

from aaeval.report.figures import save_figure
from aaeval.report.tables import write_table

__all__ = ["filters_section", "filter_measures", "picket_flicker", "edge_width_10_90"]

GROUP_PREFIX = "filters"
FILTER_ORDER = ("box", "tent", "bspline", "mitchell", "catmullrom", "gaussian")


def picket_flicker(frames: np.ndarray, mask: np.ndarray) -> float:
    """RMS over ``mask`` pixels (and channels) of the per-pixel standard deviation across frames.

    Parameters
    ----------
    frames : ndarray, shape (F, H, W, 3)
    mask : ndarray of bool, shape (H, W)
    """
    frames = np.asarray(frames, dtype=np.float64)
    if frames.ndim != 4 or frames.shape[1:3] != mask.shape:
        raise ValueError(f"expected (F, H, W, 3) frames matching a (H, W) mask, got {frames.shape} and {mask.shape}")
    if not mask.any():
        raise ValueError("empty mask")
    return float(np.sqrt(np.mean(np.var(frames, axis=0)[mask])))


def fence_interior(box_frames: np.ndarray, margin: int = 2) -> np.ndarray:
    """Pixels whose filter support (radius <= 2) stays inside the fence in every frame.

    ``box_frames`` are the exact box-filtered frames: a pixel is in the fence when the bars
    cover part of it in every frame; the mask keeps those at least ``margin`` pixels from
    the fence's outline (the fence's ends and its top and bottom).
    """
    from scipy.ndimage import binary_erosion

    covered = (np.asarray(box_frames).mean(axis=-1) > 1e-9).all(axis=0)
    return binary_erosion(covered, structure=np.ones((2 * margin + 1, 2 * margin + 1), bool))


def edge_width_10_90(frames: np.ndarray, *, rows: slice, cols: slice, channel: int = 0, bin_width: float = 0.02) -> float:
    """10-90% width (pixels) of a rising edge from its edge spread function.

    Every row of ``frames[:, rows, cols, channel]`` must cross the edge once, rising from a
    plateau at its first column to one at its last. Each row is normalised between those
    plateaus and aligned on the edge position its area gives; all rows of all frames are
    pooled and averaged in bins of ``bin_width``; the width is the distance between the
    first 10% and the first 90% crossings of that mean curve (the edge spread function,
    sampled at as many phases as the rows and frames give).
    """
    data = np.asarray(frames, dtype=np.float64)[:, rows, cols, channel].reshape(-1, cols.stop - cols.start)
    lo = data[:, :1]
    hi = data[:, -1:]
    keep = (hi - lo)[:, 0] > 1e-3
    data = (data[keep] - lo[keep]) / (hi[keep] - lo[keep])
    x = np.arange(data.shape[1]) + 0.5
    # each row's edge position from its area: for a filter whose integer shifts sum to
    # one, sum_i S(x_i - e) = (right end of the window) - e exactly (Catmull's area
    # invariance); the Gaussian only nearly, so its alignment is nearly exact too
    e = data.shape[1] - data.sum(axis=1)
    d = (x[None, :] - e[:, None]).ravel()
    v = data.ravel()
    edges = np.arange(np.floor(d.min()), np.ceil(d.max()) + bin_width, bin_width)
    which = np.digitize(d, edges)
    centres, means = [], []
    for b in np.unique(which):
        sel = which == b
        centres.append(d[sel].mean())
        means.append(v[sel].mean())
    centres = np.asarray(centres)
    means = np.asarray(means)
    return _crossing(centres, means, 0.9) - _crossing(centres, means, 0.1)


def _crossing(x: np.ndarray, y: np.ndarray, level: float) -> float:
    """First x where y rises through ``level`` (linear interpolation)."""
    k = np.flatnonzero((y[:-1] < level) & (y[1:] >= level))
    if k.size == 0:
        return float("nan")
    k = k[0]
    return float(x[k] + (level - y[k]) * (x[k + 1] - x[k]) / (y[k + 1] - y[k]))


def _filter_of(options_json: str) -> str:
    return json.loads(options_json or "{}").get("filter", "box")


def _sampler_label(row) -> str:
    options = json.loads(row["options"] or "{}")
    if row["method"] == "catmull":
        return "exact"
    if row["method"] == "supersample":
        return f"supersample k={options.get('k')}"
    if row["method"] == "jitter":
        return f"jitter k={options.get('k')}"
    if row["method"] == "mitsuba":
        return f"mitsuba {options.get('spp')} spp"
    return row["method"]


def _frames(store, keys) -> np.ndarray | None:
    """The stored images of ``keys`` stacked, or None if one is missing."""
    images = [store.load_image(key) if key is not None else None for key in keys]
    if any(image is None for image in images):
        return None
    return np.stack(images)


def _edge_window(width: int, height: int) -> tuple[slice, slice]:
    """Rows and columns of the ``edges`` generator's nearly vertical left edge, alone in its rows.

    The back quad's left edge runs near x = 0.12 W down from y = 0.2 H to 0.7 H and drifts
    right by at most (frames x step) pixels; the front triangle starts right of 0.28 W.
    """
    return slice(int(0.3 * height), int(0.6 * height)), slice(0, int(0.26 * width))


def filter_measures(out_dir: Path) -> pd.DataFrame:
    """One row per (scene, filter, sampler): flicker or edge width, error against exact, time."""
    from aaeval.experiments.store import SweepStore
    from aaeval.experiments.table import load_results

    store = SweepStore(Path(out_dir))
    results, _ = load_results(store)
    if results.empty:
        return pd.DataFrame()
    rows = results[results["group"].astype(str).str.startswith(GROUP_PREFIX) & results["error"].isna()].copy()
    if rows.empty:
        return pd.DataFrame()
    rows["filter"] = rows["options"].map(_filter_of)
    rows["sampler"] = rows.apply(_sampler_label, axis=1)
    rows = rows.drop_duplicates(["scene", "spec", "frame"]).sort_values("frame")
    exact = {(r.scene, r.filter, r.frame): r.key for r in rows[rows["sampler"] == "exact"].itertuples()}
    exact_box = {(s, f): k for (s, fl, f), k in exact.items() if fl == "box"}
    box_time = rows[(rows["sampler"] == "exact") & (rows["filter"] == "box")].groupby("scene")["render_s"].mean()
    out = []
    for (scene, spec), cells in rows.groupby(["scene", "spec"]):
        frames = _frames(store, cells["key"])
        if frames is None:
            continue
        first = cells.iloc[0]
        record = {"scene": scene, "spec": spec, "filter": first["filter"], "sampler": first["sampler"],
                  "frames": len(cells), "render_s": float(cells["render_s"].mean()),
                  "time_vs_box": float(cells["render_s"].mean() / box_time.get(scene, np.nan))}
        if "picket" in scene:
            box = _frames(store, [exact_box.get((scene, f)) for f in cells["frame"]])
            if box is None:
                continue
            record["flicker"] = picket_flicker(frames, fence_interior(box))
        else:
            rws, cls = _edge_window(frames.shape[2], frames.shape[1])
            record["edge_width"] = edge_width_10_90(frames, rows=rws, cols=cls)
        refs = _frames(store, [exact.get((scene, first["filter"], f)) for f in cells["frame"]])
        record["rmse_vs_exact"] = float(np.sqrt(np.mean((frames - refs) ** 2))) if refs is not None else np.nan
        out.append(record)
    return pd.DataFrame(out)


def _summary(measures: pd.DataFrame) -> pd.DataFrame:
    """Per filter and sampler: flicker per picket scene and their mean, mean edge width, error, time."""
    keys = ["filter", "sampler"]
    agg = measures.groupby(keys).agg(
        flicker=("flicker", "mean"), edge_width=("edge_width", "mean"),
        rmse_vs_exact=("rmse_vs_exact", "mean"), time_vs_box=("time_vs_box", "mean")).reset_index()
    pickets = measures.dropna(subset=["flicker"]) if "flicker" in measures else measures.iloc[:0]
    if not pickets.empty:
        per_scene = pickets.pivot_table(index=keys, columns="scene", values="flicker").add_prefix("flicker ")
        agg = agg.merge(per_scene.reset_index(), on=keys, how="left")
    agg["order"] = agg["filter"].map({f: i for i, f in enumerate(FILTER_ORDER)})
    return agg.sort_values(["order", "sampler"]).drop(columns="order").reset_index(drop=True)


def _chart(summary: pd.DataFrame, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    markers = {"exact": "o", "mitsuba": "x", "supersample": "^", "jitter": "s"}
    colours = dict(zip(FILTER_ORDER, plt.get_cmap("tab10").colors))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for row in summary.itertuples():
        if not (np.isfinite(row.flicker) and np.isfinite(row.edge_width)):
            continue
        kind = row.sampler.split()[0]
        ax.scatter(row.edge_width, row.flicker, marker=markers.get(kind, "."), s=60 if kind == "exact" else 30,
                   color=colours.get(row.filter, "k"), label=f"{row.filter}" if kind == "exact" else None,
                   facecolors=None if kind in ("exact", "mitsuba") else "none")
    ax.set_xlabel("blur: 10-90% edge width (px), edges scenes")
    ax.set_ylabel("flicker: RMS temporal std in the fence (mean of picket scenes)")
    ax.set_title("Pixel filters: flicker against blur (o exact, ^ supersample, s jitter, x Mitsuba)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, path)  # PNG, SVG and PDF, as every report figure


def _table(summary: pd.DataFrame, out_dir: Path) -> str:
    """The summary as the report writes every table: HTML here, CSV and LaTeX in tables/."""
    named = {"filter": "filter", "sampler": "sampler", "edge_width": "edge width (px)",
             "rmse_vs_exact": "RMSE vs exact", "time_vs_box": "time / exact box"}
    cols = ["filter", "sampler"] + [c for c in summary.columns if c.startswith("flicker ")] \
        + ["edge_width", "rmse_vs_exact", "time_vs_box"]
    shown = summary[cols].rename(columns=named)
    return write_table(shown, out_dir / "tables", "filters_tradeoff", out_dir, "Pixel filters: flicker and blur")


def filters_section(out_dir: Path, figures_dir: Path) -> str:
    """HTML fragment of the filter trade-off (chart in ``figures_dir``); empty when the sweep has no filter groups."""
    out_dir = Path(out_dir)
    figures_dir = Path(figures_dir)
    measures = filter_measures(out_dir)
    if measures.empty:
        return ""
    summary = _summary(measures)
    figures_dir.mkdir(parents=True, exist_ok=True)
    chart = _chart(summary, figures_dir / "filters_tradeoff.png")
    try:
        src = chart.relative_to(out_dir).as_posix()
    except ValueError:
        src = chart.as_posix()
    return ("<h2 id='filters'>Pixel filters: flicker against blur</h2>"
            "<p>Every filter as Mitsuba 3 defines it and normalises its film (docs/filters.md). <b>exact</b> is "
            "<code>catmull:filter=F</code>: the visible pieces integrated against the filter exactly (the Gaussian by "
            "edge quadrature to 1e-12). Sampled: <code>supersample</code>/<code>jitter</code> with the same filter "
            "(jitter seed 1) and Mitsuba (stratified, seed 1, the spp shown). Flicker: RMS over the picket fence's "
            "interior of each pixel's standard deviation across the frames (an ideal low-pass image is constant "
            "there). Blur: 10-90% width of the edge spread function of the edges scenes' nearly vertical edge. "
            "RMSE vs exact: each sampler against <code>catmull:filter=F</code> on the same frames (its noise). Time: "
            "mean render time per frame against <code>catmull</code> (box) on the same scene, measured during the "
            "sweep (other work on the machine disturbs it; benchmarks/bench_filters.py interleaves).</p>"
            f"<figure><img src='{html.escape(src)}' alt='filters trade-off'><figcaption>Flicker against blur per "
            "filter; filled markers exact and Mitsuba, hollow markers supersample and jitter.</figcaption></figure>"
            + _table(summary, out_dir))
