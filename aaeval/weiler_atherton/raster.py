"""Exact box filter of non-overlapping polygons: each pixel gets the area of every piece
over its square, accumulated edge by edge (numba).

Every directed edge adds, to each pixel of a row it crosses, the signed area between the
edge and the pixel's right side, and the height it spans to every pixel farther right
(a running sum per row settles those). Summed over a closed contour this is the contour's
area inside each pixel, holes (negative contours) included; parts left of the image count
as if on its left border and parts right of it not at all.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from aaeval.scenes import Scene

__all__ = ["coverage", "box_filter"]


@njit(cache=True)
def _unit_cells(lo, hi, n):
    """First and last cell [k, k + 1), 0 <= k < n, that the interval lo < hi overlaps; each
    overlaps it over a length > 0 (so no cell of the loops below gets an empty stretch)."""
    return max(int(math.floor(lo)), 0), min(int(math.ceil(hi)) - 1, n - 1)


@njit(cache=True)
def _row_segment(r, xa, xb, dy, w, weight, area, cover):
    """A segment spanning height ``dy`` (signed) of row r, from x = xa to xb."""
    if xa == xb:
        x = xa
        if x <= 0.0:
            cover[r, 0] += weight * dy
        elif x < w:
            c = int(math.floor(x))
            area[r, c] += weight * dy * ((c + 1) - x)
            cover[r, c + 1] += weight * dy
        return
    lo = min(xa, xb)
    hi = max(xa, xb)
    per_x = dy / (hi - lo)  # height per unit of x
    if lo < 0.0:
        cover[r, 0] += weight * per_x * (min(hi, 0.0) - lo)
    c0, c1 = _unit_cells(lo, hi, w)
    for c in range(c0, c1 + 1):
        u = max(lo, float(c))
        v = min(hi, float(c + 1))
        h = per_x * (v - u)
        area[r, c] += weight * h * ((c + 1) - 0.5 * (u + v))
        cover[r, c + 1] += weight * h


@njit(cache=True)
def _accumulate(xs, ys, starts, lengths, weights, w, h, area, cover):
    for k in range(len(starts)):
        s = starts[k]
        n = lengths[k]
        wt = weights[k]
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
                _row_segment(r, xa, xb, sign * (yb - ya), w, wt, area, cover)


def coverage(rings, weights, width: int, height: int) -> np.ndarray:
    """Per-pixel sum of ``weight * area of ring over the pixel`` (signed rings).

    Parameters
    ----------
    rings : list of (n, 2) arrays or point lists
        Closed contours, positive shoelace area for main contours, negative for holes.
    weights : (len(rings),) or (len(rings), k) array
        Weight of each ring (e.g. its colour channels).
    """
    weights = np.asarray(weights, dtype=np.float64)
    wk = weights.reshape(len(rings), weights.shape[1] if weights.ndim > 1 else 1)
    lengths = np.array([len(r) for r in rings], dtype=np.int64)
    starts = (np.concatenate([[0], np.cumsum(lengths)[:-1]]) if len(rings) else np.zeros(0)).astype(np.int64)
    xy = np.concatenate([np.asarray(r, dtype=np.float64).reshape(-1, 2) for r in rings]) if rings else np.zeros((0, 2))
    x = np.ascontiguousarray(xy[:, 0])
    y = np.ascontiguousarray(xy[:, 1])
    out = np.empty((height, width, wk.shape[1]))
    for ch in range(wk.shape[1]):
        area = np.zeros((height, width))
        cover = np.zeros((height, width + 1))
        _accumulate(x, y, starts, lengths, np.ascontiguousarray(wk[:, ch]), width, height, area, cover)
        # the accumulated area lies right of each edge; a positive contour's edges going
        # down (y growing) bound its interior from the right, hence the minus sign
        out[:, :, ch] = -(area + np.cumsum(cover[:, :width], axis=1))
    return out if weights.ndim > 1 else out[:, :, 0]


def box_filter(scene: Scene, pieces) -> np.ndarray:
    """The exact box-filtered image (H, W, 3) of non-overlapping visible pieces."""
    rings, colors = [], []
    for p in pieces:
        color = scene.polygons[p.source].color
        for r in p.shape.rings:
            rings.append(r)
            colors.append(color)
    weights = np.hstack([np.array(colors).reshape(-1, 3), np.ones((len(rings), 1))])
    acc = coverage(rings, weights, scene.width, scene.height)
    covered = acc[:, :, 3:4]
    return acc[:, :, :3] + (1.0 - covered) * scene.background
