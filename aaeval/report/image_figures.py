"""The report's image figures: a space-time slice of a row over the frames, and the grid of
every method's image beside the ground truth with a crop and its error."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from aaeval.fileio import linear_to_srgb8
from aaeval.report import chart_parts, figure_files
from aaeval.report.figures import plt, save_figure

__all__ = ["space_time", "image_grid"]


@figure_files.figure
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
        ax.imshow(chart_parts.opaque_rgba(linear_to_srgb8(frames[:, row])), interpolation="nearest", aspect="auto")
        chart_parts.placed_title(ax, name, fontsize=7)
    chart_parts.suptitle(fig, f"{title} (row {row}; x: column, y: frame downwards)")
    return save_figure(fig, path)


def _crop_box(error: np.ndarray, size: int) -> tuple[int, int, int, int]:
    """A square of ``size`` pixels around the largest error, inside the image."""
    h, w = error.shape
    r, c = np.unravel_index(int(np.argmax(error)), error.shape)
    size = min(size, h, w)
    r0 = int(np.clip(r - size // 2, 0, h - size))
    c0 = int(np.clip(c - size // 2, 0, w - size))
    return r0, r0 + size, c0, c0 + size


@figure_files.figure
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
    ax.imshow(chart_parts.opaque_rgba(canvas), interpolation="nearest")
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
