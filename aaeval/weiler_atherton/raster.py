"""Exact box filter of non-overlapping polygons: each pixel gets the area of every piece
over its square, accumulated edge by edge (native: ``src/weiler_atherton/raster.cpp``).

Every directed edge adds, to each pixel of a row it crosses, the signed area between the
edge and the pixel's right side, and the height it spans to every pixel farther right.
Both go into one array of differences along the row (the area to the pixel and, less
that area, the height to the next one, as font-rs and FreeType's smooth rasterizer
accumulate coverage), and a running sum per row settles it. Summed over a closed contour
this is the contour's area inside each pixel, holes (negative contours) included; parts
left of the image count as if on its left border and parts right of it not at all.
"""

from __future__ import annotations

import numpy as np

from aaeval.native.weiler_atherton import coverage_over
from aaeval.scenes import Scene

__all__ = ["coverage", "coverage_flat", "box_filter"]


def coverage(rings, weights, width: int, height: int) -> np.ndarray:
    """Per-pixel sum of ``weight * area of ring over the pixel`` (signed rings).

    Parameters
    ----------
    rings : list of (n, 2) arrays or point lists
        Closed contours, positive shoelace area for main contours, negative for holes.
    weights : (len(rings),) or (len(rings), k) array
        Weight of each ring (e.g. its colour channels).
    """
    lengths = np.array([len(r) for r in rings], dtype=np.int64)
    starts = np.zeros(len(rings) + 1, dtype=np.int64)
    np.cumsum(lengths, out=starts[1:])
    xy = np.concatenate([np.asarray(r, dtype=np.float64).reshape(-1, 2) for r in rings]) if rings else np.zeros((0, 2))
    return coverage_flat(xy[:, 0], xy[:, 1], starts, weights, width, height)


def coverage_flat(xs, ys, starts, weights, width: int, height: int) -> np.ndarray:
    """:func:`coverage` of contours given flat: contour k is vertices ``starts[k]:starts[k + 1]``."""
    weights = np.asarray(weights, dtype=np.float64)
    wk = weights.reshape(len(starts) - 1, weights.shape[1] if weights.ndim > 1 else 1)
    area = _coverage_over(xs, ys, starts, wk, np.zeros(wk.shape[1]), width, height)
    return area if weights.ndim > 1 else area[:, :, 0]


def _coverage_over(xs, ys, starts, weights, base, width: int, height: int) -> np.ndarray:
    """A new (H, W, k) image: ``base`` plus the per-pixel sum of ``weights[ring] * area of
    ring over the pixel`` (the native ``add_coverage`` on an image filled with ``base``,
    bit for bit)."""
    return coverage_over(np.ascontiguousarray(xs, dtype=np.float64), np.ascontiguousarray(ys, dtype=np.float64),
                         np.ascontiguousarray(starts, dtype=np.int64), np.ascontiguousarray(weights, dtype=np.float64),
                         np.ascontiguousarray(base, dtype=np.float64), height, width)


def box_filter(scene: Scene, pieces) -> np.ndarray:
    """The exact box-filtered image (H, W, 3) of non-overlapping visible pieces (a list
    of :class:`~.hidden_surface.Piece` or the flat :class:`~.hidden_surface.VisibleArrays`)."""
    if hasattr(pieces, "piece_rings"):
        ring_source = np.repeat(pieces.sources, np.diff(pieces.piece_rings))
        xs, ys, starts = pieces.xs, pieces.ys, pieces.starts
    else:
        rings = [r for p in pieces for r in p.shape.rings]
        ring_source = np.array([p.source for p in pieces for _ in p.shape.rings], dtype=np.int64)
        lengths = np.array([len(r) for r in rings], dtype=np.int64)
        starts = np.zeros(len(rings) + 1, dtype=np.int64)
        np.cumsum(lengths, out=starts[1:])
        xy = np.array([q for r in rings for q in r], dtype=np.float64).reshape(-1, 2)
        xs, ys = xy[:, 0], xy[:, 1]
    # pieces do not overlap: colour * area summed, plus the background over what is left,
    # is the background plus (colour - background) * area summed
    background = np.asarray(scene.background, dtype=np.float64)
    colors = np.array([p.color for p in scene.polygons], dtype=np.float64).reshape(-1, 3) - background
    return _coverage_over(xs, ys, starts, colors[ring_source].reshape(-1, 3), background, scene.width, scene.height)
