"""The report's figures: one plain function per chart, ``(data, path, ...) -> path``.

Errors are plotted on log axes; an exact method's error can be 0, which a log axis cannot
show, so errors are drawn no lower than a floor that the caller states in the caption.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from aaeval.imageio import linear_to_srgb8  # noqa: E402

__all__ = ["ERROR_FLOOR", "speed_accuracy", "pareto_front", "intensity_sums", "temporal_bars", "stability",
           "image_grid"]

ERROR_FLOOR = 1e-12
_MARKERS = "os^vD<>pP*Xhd"


def _style(methods) -> dict[str, tuple]:
    cmap = plt.get_cmap("tab10")
    return {m: (cmap(i % 10), _MARKERS[i % len(_MARKERS)]) for i, m in enumerate(sorted(methods))}


def _line_styles(rows: pd.DataFrame) -> dict[str, tuple]:
    """Colour per spec label, marker per method: lines of one method's options stay apart."""
    cmap = plt.get_cmap("tab20" if rows["label"].nunique() > 10 else "tab10")
    markers = {m: _MARKERS[i % len(_MARKERS)] for i, m in enumerate(sorted(rows["method"].unique()))}
    labels = list(dict.fromkeys(rows["label"]))
    method_of = dict(zip(rows["label"], rows["method"]))
    return {lab: (cmap(i % cmap.N), markers[method_of[lab]]) for i, lab in enumerate(labels)}


def _is_ladder(rows: pd.DataFrame) -> bool:
    """Whether a method's points differ only in numeric options (spp, k): a quality ladder."""
    import json

    opts = [json.loads(o) for o in rows["options"]]
    keys = {k for k in set().union(*opts) if len({json.dumps(o.get(k)) for o in opts}) > 1}
    return bool(keys) and all(isinstance(o.get(k), (int, float)) and not isinstance(o.get(k), bool)
                              for o in opts for k in keys)


def _save(fig, path: Path) -> Path:
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path


def pareto_front(times: np.ndarray, errors: np.ndarray) -> np.ndarray:
    """Indices of the points no other point beats in both time and error, by time."""
    order = np.lexsort((errors, times))
    front, best = [], math.inf
    for i in order:
        if errors[i] < best:
            front.append(i)
            best = errors[i]
    return np.array(front, dtype=int)


def speed_accuracy(summary: pd.DataFrame, path: Path, *, metric: str, title: str) -> Path:
    """Median render time against mean error per spec, log-log, with the Pareto front and
    each method's option ladder (Mitsuba's spp, supersampling's k) joined as a curve."""
    fig, ax = plt.subplots(figsize=(8.5, 5.5))
    style = _style(summary["method"].unique())
    t = summary["render_s"].to_numpy(float)
    e = np.maximum(summary[metric].to_numpy(float), ERROR_FLOOR)
    for method, rows in summary.groupby("method"):
        colour, marker = style[method]
        rows = rows.sort_values("render_s")
        y = np.maximum(rows[metric].to_numpy(float), ERROR_FLOOR)
        if len(rows) > 1 and _is_ladder(rows):
            ax.plot(rows["render_s"], y, "-", color=colour, alpha=0.5, lw=1)
        for (_, r), yy in zip(rows.iterrows(), y):
            ax.plot(r["render_s"], yy, marker, color=colour, ms=8, mec="black", mew=0.5)
            ax.annotate(r["label"], (r["render_s"], yy), textcoords="offset points", xytext=(5, 4), fontsize=7)
        ax.plot([], [], marker, color=colour, label=method, mec="black", mew=0.5)
    ok = np.isfinite(t) & np.isfinite(e) & (t > 0)
    if ok.sum() > 1:
        idx = np.flatnonzero(ok)[pareto_front(t[ok], e[ok])]
        ax.step(t[idx], e[idx], where="post", color="black", ls="--", lw=1, label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("render time per frame (s, median)")
    ax.set_ylabel(f"{_metric_title(metric)} (mean over cells, floor {ERROR_FLOOR:g})")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return _save(fig, path)


def intensity_sums(results: pd.DataFrame, path: Path, *, title: str) -> Path:
    """Intensity sum per frame relative to the reference's frame 0, one panel per scene."""
    scenes = list(dict.fromkeys(results["scene"]))
    fig, axes = plt.subplots(len(scenes), 1, figsize=(8.5, 3.2 * len(scenes)), squeeze=False)
    style = _line_styles(results)
    for ax, scene in zip(axes[:, 0], scenes):
        rows = results[results["scene"] == scene].sort_values("frame")
        base = rows["reference_intensity_sum"].iloc[0]
        ref = rows.drop_duplicates("frame")
        ax.plot(ref["frame"], ref["reference_intensity_sum"] / base, "k-", lw=2.5, alpha=0.35,
                label=f"reference {rows['reference'].iloc[0]}")
        for _, series in rows.groupby("spec", sort=False):
            colour, marker = style[series["label"].iloc[0]]
            ax.plot(series["frame"], series["intensity_sum"] / base, "-" + marker, color=colour, ms=4, lw=1,
                    label=series["label"].iloc[0])
        ax.set_title(f"{scene}", fontsize=9)
        ax.set_xlabel("frame")
        ax.set_ylabel("intensity sum / reference frame 0")
        ax.grid(True, alpha=0.25)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle(title, fontsize=10)
    return _save(fig, path)


def _metric_title(name: str) -> str:
    from aaeval.metrics import METRICS

    return METRICS[name].title if name in METRICS else name


def _metric_label(name: str) -> str:
    """Axis label of a metric from the registry: its title and which way is better."""
    from aaeval.metrics import METRICS

    m = METRICS.get(name)
    return name if m is None else f"{m.title} ({m.direction})"


def temporal_bars(temporal: pd.DataFrame, path: Path, *, metrics: list[str], title: str) -> Path:
    """One panel per temporal metric (flicker, sum variation): mean per spec, log scale."""
    agg = temporal.groupby("label", sort=False)[metrics].mean().sort_values(metrics[0])
    fig, axes = plt.subplots(1, len(metrics), figsize=(5.5 * len(metrics), 0.45 * len(agg) + 2), squeeze=False)
    for i, (ax, col) in enumerate(zip(axes[0], metrics)):
        ax.barh(agg.index, np.maximum(agg[col].to_numpy(float), ERROR_FLOOR), color="tab:blue")
        ax.set_xscale("log")
        ax.set_xlabel(f"{_metric_label(col)} (floor {ERROR_FLOOR:g})", fontsize=8)
        ax.grid(True, axis="x", alpha=0.25)
        ax.tick_params(axis="y", labelsize=7)
        if i:
            ax.set_yticklabels([])
    fig.suptitle(title, fontsize=10)
    return _save(fig, path)


def stability(results: pd.DataFrame, path: Path, *, metric: str, fail_above: float | None, title: str) -> Path:
    """Error and failures against difficulty, one line per spec."""
    style = _line_styles(results)
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.5))
    label = results["difficulty_label"].dropna().iloc[0] if results["difficulty_label"].notna().any() else "difficulty"
    for _, rows in results.groupby("spec", sort=False):
        spec = rows["label"].iloc[0]
        colour, marker = style[spec]
        by = rows.groupby("difficulty")
        err = by[metric].mean()
        ax.plot(err.index, np.maximum(err.to_numpy(float), ERROR_FLOOR), "-" + marker, color=colour, label=spec)
        failed = by.apply(lambda r: _failures(r, metric, fail_above) / len(r), include_groups=False)
        bx.plot(failed.index, failed.to_numpy(float), "-" + marker, color=colour, label=spec)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(label)
    ax.set_ylabel(f"{_metric_title(metric)} (mean, floor {ERROR_FLOOR:g})")
    ax.grid(True, which="both", alpha=0.25)
    bx.set_xscale("log")
    bx.set_xlabel(label)
    crit = "raised an error" + (f" or {metric} > {fail_above:g}" if fail_above else "")
    bx.set_ylabel(f"fraction of cells failed ({crit})", fontsize=8)
    bx.set_ylim(-0.05, 1.05)
    bx.grid(True, alpha=0.25)
    bx.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle(title, fontsize=10)
    return _save(fig, path)


def _failures(rows: pd.DataFrame, metric: str, fail_above: float | None) -> int:
    bad = rows["error"].notna()
    if fail_above:
        bad |= rows[metric].to_numpy(float) > fail_above
    return int(bad.sum())


def _crop_box(error: np.ndarray, size: int) -> tuple[int, int, int, int]:
    """A square of ``size`` pixels around the largest error, inside the image."""
    h, w = error.shape
    r, c = np.unravel_index(int(np.argmax(error)), error.shape)
    size = min(size, h, w)
    r0 = int(np.clip(r - size // 2, 0, h - size))
    c0 = int(np.clip(c - size // 2, 0, w - size))
    return r0, r0 + size, c0, c0 + size


def image_grid(reference: np.ndarray, images: list[tuple[str, np.ndarray]], path: Path, *, title: str) -> Path:
    """Rows: the reference, then each method; columns: image, zoomed crop, |error| map.

    The crop is the same square for every row (around the largest error of any method);
    the error maps share one colour scale.
    """
    errors = [np.abs(img - reference).sum(axis=2) for _, img in images]
    worst = np.max(np.stack(errors), axis=0) if errors else np.zeros(reference.shape[:2])
    r0, r1, c0, c1 = _crop_box(worst, max(4, min(reference.shape[:2]) // 3))
    vmax = max(float(worst.max()), 1e-12)
    rows = [("reference", reference, None)] + [(n, img, err) for (n, img), err in zip(images, errors)]
    h, w = reference.shape[:2]
    row_height = 9 / 3 * min(1.0, h / w) + 0.35  # image rows as tall as their aspect needs
    fig, axes = plt.subplots(len(rows), 3, figsize=(9, row_height * len(rows)), squeeze=False,
                             layout="constrained")
    im = None
    for (name, img, err), ax in zip(rows, axes):
        srgb = linear_to_srgb8(img)
        ax[0].imshow(srgb, interpolation="nearest")
        ax[0].add_patch(plt.Rectangle((c0 - 0.5, r0 - 0.5), c1 - c0, r1 - r0, fill=False, ec="red", lw=1))
        ax[0].set_ylabel(name.replace(":", ":\n").replace(",", ",\n"), fontsize=7)  # long specs wrap
        ax[1].imshow(srgb[r0:r1, c0:c1], interpolation="nearest")
        if err is not None:
            im = ax[2].imshow(err, cmap="magma", vmin=0, vmax=vmax, interpolation="nearest")
            ax[2].set_title(f"max |err| {err.max():.3g}, mean {err.mean():.3g}", fontsize=7)
        for a in ax:
            a.set_xticks([])
            a.set_yticks([])
    axes[0, 0].set_title("image", fontsize=8)
    axes[0, 1].set_title(f"crop rows {r0}-{r1 - 1}, cols {c0}-{c1 - 1}", fontsize=8)
    axes[0, 2].axis("off")
    if im is not None:
        fig.colorbar(im, ax=axes[1:, 2].tolist(), shrink=0.6, label="|error| summed over RGB")
    fig.suptitle(title, fontsize=9)
    return _save(fig, path)
