"""Measures of pixel filters on exact renders (docs/filters.md): the blur a filter puts on an edge.

:func:`edge_width_10_90` is the 10-90% width of an edge spread function, measured on the
nearly vertical left edge of the ``edges`` generator's scenes (:func:`edges_window`); the
tests hold it to each filter's analytic step response. The temporal measures of a filter
(flicker, bias, the image's own flicker inside a fence) are registered metrics
(:mod:`aaeval.metrics.temporal`), computed by the sweep.
"""

from __future__ import annotations

import numpy as np

__all__ = ["edge_width_10_90", "edges_window"]


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


def edges_window(width: int, height: int) -> tuple[slice, slice]:
    """Rows and columns of the ``edges`` generator's nearly vertical left edge, alone in its rows.

    The back quad's left edge runs near x = 0.12 W down from y = 0.2 H to 0.7 H and drifts
    right by at most (frames x step) pixels; the front triangle starts right of 0.28 W.
    """
    return slice(int(0.3 * height), int(0.6 * height)), slice(0, int(0.26 * width))


