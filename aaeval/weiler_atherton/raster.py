"""Exact box filter of non-overlapping polygons: each pixel gets the area of every piece
over its square, accumulated edge by edge (numba).

Every directed edge adds, to each pixel of a row it crosses, the signed area between the
edge and the pixel's right side, and the height it spans to every pixel farther right.
Both go into one array of differences along the row (the area to the pixel and, less
that area, the height to the next one, as font-rs and FreeType's smooth rasterizer
accumulate coverage), and a running sum per row settles it. Summed over a closed contour
this is the contour's area inside each pixel, holes (negative contours) included; parts
left of the image count as if on its left border and parts right of it not at all.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from aaeval.scenes import Scene

__all__ = ["coverage", "coverage_flat", "box_filter"]


@njit(cache=True)
def _unit_cells(lo, hi, n):
    """First and last cell [k, k + 1), 0 <= k < n, that the interval lo < hi overlaps; each
    overlaps it over a length > 0 (so no cell of the loops below gets an empty stretch)."""
    return max(int(math.floor(lo)), 0), min(int(math.ceil(hi)) - 1, n - 1)


@njit(cache=True)
def _add_cell(diff, r, c, weight, area, height):
    """Cell (r, c) gets ``area``, every cell right of it ``height``: as differences, area
    at c and the rest of the height at c + 1, in every channel."""
    for k in range(len(weight)):
        diff[r, c, k] += weight[k] * area
        diff[r, c + 1, k] += weight[k] * (height - area)


@njit(cache=True)
def _row_segment(r, xa, xb, dy, w, weight, diff):
    """A segment spanning height ``dy`` (signed) of row r, from x = xa to xb."""
    if xa == xb:
        x = xa
        if x <= 0.0:
            for k in range(len(weight)):
                diff[r, 0, k] += weight[k] * dy
        elif x < w:
            c = int(math.floor(x))
            _add_cell(diff, r, c, weight, dy * ((c + 1) - x), dy)
        return
    lo = min(xa, xb)
    hi = max(xa, xb)
    per_x = dy / (hi - lo)  # height per unit of x
    if lo < 0.0:
        for k in range(len(weight)):
            diff[r, 0, k] += weight[k] * (per_x * (min(hi, 0.0) - lo))
    c0, c1 = _unit_cells(lo, hi, w)
    for c in range(c0, c1 + 1):
        u = max(lo, float(c))
        v = min(hi, float(c + 1))
        h = per_x * (v - u)
        _add_cell(diff, r, c, weight, h * ((c + 1) - 0.5 * (u + v)), h)


@njit(cache=True)
def _accumulate(xs, ys, starts, lengths, weights, w, h, diff):
    for k in range(len(starts)):
        s = starts[k]
        n = lengths[k]
        wt = weights[k]  # one row: the contour's weight in every channel
        for i in range(n):
            x0 = xs[s + i]
            y0 = ys[s + i]
            j = s + (i + 1) % n
            x1 = xs[j]
            y1 = ys[j]
            if y0 == y1:
                continue
            ylo = max(min(y0, y1), 0.0)
            yhi = min(max(y0, y1), float(h))
            if ylo >= yhi:
                continue
            dxdy = (x1 - x0) / (y1 - y0)
            sign = 1.0 if y1 > y0 else -1.0
            r0, r1 = _unit_cells(ylo, yhi, h)
            for r in range(r0, r1 + 1):
                ya = max(ylo, float(r))
                yb = min(yhi, float(r + 1))
                xa = x0 + (ya - y0) * dxdy
                xb = x0 + (yb - y0) * dxdy
                _row_segment(r, xa, xb, sign * (yb - ya), w, wt, diff)


@njit(cache=True)
def _settle(diff, out):
    """Each cell's total: the running sum of the differences along its row, negated (the
    accumulated area lies right of each edge; a positive contour's edges going down, y
    growing, bound its interior from the right), added to ``out`` (h, w, k)."""
    h, w, k = out.shape
    run = np.zeros(k)
    for r in range(h):
        run[:] = 0.0
        for c in range(w):
            for ch in range(k):
                run[ch] += diff[r, c, ch]
                out[r, c, ch] -= run[ch]


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
    area = np.zeros((height, width, wk.shape[1]))
    _add_coverage(xs, ys, starts, wk, area)
    return area if weights.ndim > 1 else area[:, :, 0]


def _add_coverage(xs, ys, starts, weights, out: np.ndarray) -> None:
    """out (H, W, k) += per-pixel sum of ``weights[ring] * area of ring over the pixel``."""
    height, width, k = out.shape
    starts = np.asarray(starts, dtype=np.int64)
    diff = np.zeros((height, width + 1, k))
    _accumulate(np.ascontiguousarray(xs, dtype=np.float64), np.ascontiguousarray(ys, dtype=np.float64),
                starts[:-1].copy(), np.diff(starts), np.ascontiguousarray(weights, dtype=np.float64),
                width, height, diff)
    _settle(diff, out)


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
    image = np.empty((scene.height, scene.width, 3))
    image[:] = background
    _add_coverage(xs, ys, starts, colors[ring_source].reshape(-1, 3), image)
    return image
