"""Candidate edge pairs for cutting an outline: the pairs of edges whose boxes overlap.

The first step of :func:`aaeval.importers.fill.resolve_fill`: a uniform grid over the
edges' boxes, swept in x within each cell, so an outline of E edges costs about the pairs
that are near each other rather than E^2. More than :data:`~aaeval.importers.limits.MAX_PAIRS`
pairs sharing a cell (a quadratic number of crossings) is refused, a stated limit instead
of a quadratic run.
"""

from __future__ import annotations

import numpy as np

from aaeval.importers.limits import MAX_PAIRS, FillError

__all__ = ["candidate_pairs", "distinct", "ALL_PAIRS_EDGES"]


#: Up to this many edges every pair is checked at once: a glyph's outline (40 edges typically)
#: costs a few array operations instead of the grid's few dozen. The grid finds the same pairs
#: (it loses no overlapping pair and keeps only those), and could not refuse an outline this
#: small (fewer pairs than :data:`~aaeval.importers.limits.MAX_PAIRS` in all its cells). That
#: holds for finite boxes; a box reaching infinity (an overflowed cut) still goes to the grid.
ALL_PAIRS_EDGES = 64


def candidate_pairs(lo, hi, eps, active=None):
    """Pairs (i < j) of boxes that overlap (with ``eps`` slack), sorted by (i, j), from a
    uniform grid (or every pair, for :data:`ALL_PAIRS_EDGES` boxes or fewer)."""
    n = len(lo)
    if n < 2:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    if n <= ALL_PAIRS_EDGES and np.isfinite(lo).all() and np.isfinite(hi).all():
        return _all_pairs(lo, hi, eps, active)
    ext = np.maximum(hi - lo, 0.0).max(axis=1)
    span = float(max((hi.max(axis=0) - lo.min(axis=0)).max(), 1e-300))
    cell = max(float(np.percentile(ext, 90)), span / 4096.0, 1e-300)
    origin = lo.min(axis=0)
    while True:
        c0 = np.floor((lo - eps - origin) / cell).astype(np.int64)
        c1 = np.floor((hi + eps - origin) / cell).astype(np.int64)
        nx, ny = c1[:, 0] - c0[:, 0] + 1, c1[:, 1] - c0[:, 1] + 1
        count = nx * ny
        total = int(count.sum())
        if total <= 4 * n + 1024:
            break
        cell *= 2.0
    edge = np.repeat(np.arange(n), count)
    k = np.arange(total) - np.repeat(np.cumsum(count) - count, count)
    gx = c0[edge, 0] + k % nx[edge]
    gy = c0[edge, 1] + k // nx[edge]
    key = gx * (int(c1[:, 1].max()) + 2) + gy
    order = np.argsort(key, kind="stable")
    key, edge = key[order], edge[order]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    ends = np.r_[starts[1:], len(key)]
    if active is not None:  # only cells that hold an edge cut in the last pass
        busy = np.maximum.reduceat(active[edge].astype(np.int8), starts) > 0
        keep_entry = np.repeat(busy, ends - starts)
        key, edge = key[keep_entry], edge[keep_entry]
        starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]]) if len(key) else np.zeros(0, np.int64)
        ends = np.r_[starts[1:], len(key)] if len(key) else np.zeros(0, np.int64)
    size = ends - starts
    pairs_total = int((size * (size - 1) // 2).sum())
    if pairs_total > MAX_PAIRS:
        raise FillError(f"an outline of {n} edges has {pairs_total} close edge pairs, over the limit of "
                        f"{MAX_PAIRS} (split it into simpler paths)")
    edge, partner_end = _sweep_cells(key, edge, lo[:, 0], hi[:, 0] + eps)
    partners = partner_end - np.arange(len(edge)) - 1
    first = np.repeat(np.arange(len(edge)), partners)
    offset = np.arange(int(partners.sum())) - np.repeat(np.cumsum(partners) - partners, partners)
    second = first + 1 + offset
    i, j = edge[first], edge[second]
    i, j = np.minimum(i, j), np.maximum(i, j)
    ok = i != j
    if active is not None:
        ok &= active[i] | active[j]
    i, j = i[ok], j[ok]
    ok = np.all(lo[i] <= hi[j] + eps, axis=1) & np.all(lo[j] <= hi[i] + eps, axis=1)
    code = distinct(i[ok] * n + j[ok])
    return code // n, code % n


def distinct(values: np.ndarray) -> np.ndarray:
    """The distinct values of an integer array, sorted: ``np.unique(values)`` by a sort.

    NumPy 2.3 and later find ``np.unique``'s values by hashing, which on millions of
    distinct integers (the pair codes of a self-crossing outline) is about 15 times slower
    than sorting them (2 million: 2.1 s against 0.13 s).
    """
    values = np.sort(values, axis=None)
    return values[np.r_[True, values[1:] != values[:-1]]] if len(values) else values


def _all_pairs(lo, hi, eps, active):
    """:func:`candidate_pairs` by checking every pair of boxes."""
    near = np.all(lo[:, None, :] <= (hi + eps)[None, :, :], axis=2)
    near &= near.T
    if active is not None:
        near &= active[:, None] | active[None, :]
    i, j = np.nonzero(np.triu(near, 1))
    return i.astype(np.int64), j.astype(np.int64)


def _sweep_cells(key, edge, lo_x, reach_x):
    """The cell entries (``key`` sorted) sorted by cell, then by their edge's left end, and
    for each entry the end of its partners: the entries after it in its cell whose edge
    starts at or before its own ``reach_x``.

    Within a cell every pair whose boxes overlap in x is one such (entry, partner) pair,
    seen from the entry whose edge starts first, so no overlapping pair is lost; a cell
    crowded with small edges (the offsets of a stroke at a cusp: thousands in one cell)
    then yields the pairs that are near in x, not all its pairs.
    """
    values = np.unique(lo_x)  # x as an exact integer rank, so cell and x sort as one integer
    rank = np.searchsorted(values, lo_x[edge])
    reach = np.searchsorted(values, reach_x[edge], side="right")  # how many left ends are <= reach
    stride = len(values) + 1
    cell = np.cumsum(np.r_[0, key[1:] != key[:-1]]) if len(key) else np.zeros(0, np.int64)
    code = cell * stride + rank
    order = np.argsort(code, kind="stable")
    partner_end = np.searchsorted(code[order], (cell * stride + reach)[order], side="left")
    return edge[order], partner_end
