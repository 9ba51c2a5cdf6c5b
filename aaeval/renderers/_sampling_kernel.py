"""Point sampling of polygon scenes (numba kernels), shared by the sampling baselines.

``point``, ``supersample`` and ``jitter`` differ only in where the samples of a pixel
lie; :func:`sample_image` takes that as ``(k, jitter, seed)`` and does the rest. The
A-buffer reuses the row buckets and the strip edge lists.

Structure (a scanline algorithm, so the cost follows what the polygons cover):
- :func:`row_buckets`: every polygon is listed on each pixel row its y extent meets,
  in file order (CSR arrays).
- per row and per *strip* (the band of one row of strata, height 1/k), each listed
  polygon's edges that meet the strip are collected (:func:`strip_edges`) with the x
  range they span there; only the pixel columns of that range are visited, and only
  those edges take part in the inside test of a sample.
- inside test (:func:`inside`): crossing parity with the half-open rule
  ``(y0 <= y) != (y1 <= y)`` and ``x < x_cross``, the crossing computed from the edge's
  endpoints ordered by y. Two polygons sharing an edge compute the same crossing, so a
  sample on the shared edge belongs to exactly one of them; a polygon covers
  ``[ymin, ymax)`` vertically.
- depth: ``z = a x + b y + c``; polygons are visited in file order and a later one wins
  when its depth is within ``eps_z`` of the nearest so far or nearer
  (:func:`aaeval.scenes.depth.nearer_or_tied`: the scene format's tie rule, relative to
  the nearest depth; ``eps_z`` comes from :func:`aaeval.renderers.catmull.kernel_inputs`).

Jittered samples come from a counter-based hash of ``(seed, row, column, sample,
axis)``: reproducible, independent of the order of work, and fixed in screen space, so
every frame of an animation sees the same sample pattern for a given seed.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from aaeval.filters.evaluate import profile_at
from aaeval.filters.registry import KIND_BOX
from aaeval.scenes.depth import nearer_or_tied

NO_POLYGON = -1


@njit(cache=True)
def row_buckets(height, starts, lengths, ys):
    """Polygons per pixel row: CSR ``(row_start, polys)`` in file order.

    A polygon is listed on rows ``floor(ymin) .. ceil(ymax) - 1`` clipped to the image
    (it covers ``[ymin, ymax)``, so a row it only touches at its bottom is left out).
    """
    n = starts.size
    r0 = np.empty(n, np.int64)
    r1 = np.empty(n, np.int64)
    counts = np.zeros(height + 1, np.int64)
    for p in range(n):
        ymin = np.inf
        ymax = -np.inf
        for i in range(starts[p], starts[p] + lengths[p]):
            ymin = min(ymin, ys[i])
            ymax = max(ymax, ys[i])
        a = max(0, int(np.floor(ymin)))
        b = min(height - 1, int(np.ceil(ymax)) - 1)
        r0[p] = a
        r1[p] = b
        for r in range(a, b + 1):
            counts[r + 1] += 1
    row_start = np.cumsum(counts)
    fill = row_start[:-1].copy()
    polys = np.empty(row_start[-1], np.int64)
    for p in range(n):
        for r in range(r0[p], r1[p] + 1):
            polys[fill[r]] = p
            fill[r] += 1
    return row_start, polys


@njit(cache=True)
def edge_buffers(lengths):
    """Scratch arrays for one polygon's edges and crossings: ``(ex0, ey0, ex1, ey1, xc)``."""
    maxv = 3
    for n in lengths:
        maxv = max(maxv, n)
    return np.empty(maxv), np.empty(maxv), np.empty(maxv), np.empty(maxv), np.empty(maxv)


@njit(cache=True)
def strip_edges(xs, ys, start, n, ya, yb, ex0, ey0, ex1, ey1):
    """Edges of a polygon meeting the closed band ``ya <= y <= yb``.

    Writes them with endpoints ordered by y (``ey0 <= ey1``) and returns
    ``(count, xlo, xhi)``, the x range the edges span inside the band, which holds every
    point of the polygon in the band. Horizontal edges are kept (they bound the z range
    of A-buffer fragments; the inside test ignores them).
    """
    m = 0
    xlo = np.inf
    xhi = -np.inf
    prev = start + n - 1
    for i in range(start, start + n):
        x0 = xs[prev]
        y0 = ys[prev]
        x1 = xs[i]
        y1 = ys[i]
        prev = i
        if y1 < y0:
            x0, y0, x1, y1 = x1, y1, x0, y0
        if y0 > yb or y1 < ya:
            continue
        ex0[m] = x0
        ey0[m] = y0
        ex1[m] = x1
        ey1[m] = y1
        m += 1
        # x of the edge at the band's limits (or its own ends, inside the band)
        if y1 > y0:
            ta = max(ya, y0)
            tb = min(yb, y1)
            xa = x0 + (ta - y0) * (x1 - x0) / (y1 - y0)
            xb = x0 + (tb - y0) * (x1 - x0) / (y1 - y0)
        else:
            xa = x0
            xb = x1
        xlo = min(xlo, xa, xb)
        xhi = max(xhi, xa, xb)
    return m, xlo, xhi


@njit(cache=True, inline="always")
def inside(ex0, ey0, ex1, ey1, m, x, y):
    """Crossing parity of ``(x, y)`` against ``m`` y-ordered edges (half-open rule)."""
    odd = False
    for e in range(m):
        if ey0[e] <= y < ey1[e]:
            xc = ex0[e] + (y - ey0[e]) * (ex1[e] - ex0[e]) / (ey1[e] - ey0[e])
            if x < xc:
                odd = not odd
    return odd


@njit(cache=True, inline="always")
def _splitmix64(z):
    z = z + np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


@njit(cache=True, inline="always")
def jitter_uniform(seed, row, col, sample, axis):
    """A uniform number in [0, 1) fixed by ``(seed, row, col, sample, axis)``."""
    h = _splitmix64(np.uint64(seed))
    h = _splitmix64(h ^ np.uint64(row))
    h = _splitmix64(h ^ np.uint64(col))
    h = _splitmix64(h ^ (np.uint64(sample) * np.uint64(2) + np.uint64(axis)))
    return np.float64(h >> np.uint64(11)) * (1.0 / 9007199254740992.0)  # 53 bits


@njit(cache=True)
def crossings(ex0, ey0, ex1, ey1, m, y, out):
    """Sorted x of the edges' crossings with the line at ``y`` (half-open rule); returns the count.

    A point ``(x, y)`` is inside exactly when ``out[2t] <= x < out[2t + 1]`` for some ``t``
    (the same rule as :func:`inside`).
    """
    nc = 0
    for e in range(m):
        if ey0[e] <= y < ey1[e]:
            xc = ex0[e] + (y - ey0[e]) * (ex1[e] - ex0[e]) / (ey1[e] - ey0[e])
            t = nc
            while t > 0 and out[t - 1] > xc:
                out[t] = out[t - 1]
                t -= 1
            out[t] = xc
            nc += 1
    return nc


@njit(cache=True, inline="always")
def grid_x(g, k):
    """x of column ``g`` of the sample grid with ``k`` samples per pixel: ``(g + 1/2) / k``."""
    return (g + 0.5) / k


@njit(cache=True)
def grid_range(xa, xb, k, n):
    """Grid columns ``g`` in ``[0, n)`` with ``xa <= grid_x(g, k) < xb``, as ``(g0, g1)``."""
    # a first guess from the limits clamped to the grid, then exact fix-ups
    xa = min(max(xa, -1.0), n / k + 1.0)
    xb = min(max(xb, -1.0), n / k + 1.0)
    g0 = max(0, int(np.ceil(xa * k - 0.5)) - 1)
    while g0 < n and grid_x(g0, k) < xa:
        g0 += 1
    g1 = min(n, max(g0, int(np.ceil(xb * k - 0.5)) + 1))
    while g1 > g0 and grid_x(g1 - 1, k) >= xb:
        g1 -= 1
    return g0, g1


@njit(cache=True)
def jitter_offsets(seed, row, width, k, out):
    """Jittered in-stratum offsets ``u, v`` of every sample of one pixel row into ``out`` (width, k*k, 2)."""
    for col in range(width):
        for s in range(k * k):
            out[col, s, 0] = jitter_uniform(seed, row, col, s, 0)
            out[col, s, 1] = jitter_uniform(seed, row, col, s, 1)


@njit(cache=True)
def splat_row(r, k, jitter, offsets, best_p, colors, background, fkind, fradius, fpieces, falpha, fbias, num, den):
    """Add one pixel row's samples to every pixel whose filter reaches them (Mitsuba's film).

    Sample ``(col, s)`` lies where :func:`sample_image` put it; it adds ``w * colour`` to
    ``num`` and ``w`` to ``den`` of each pixel ``(j, i)`` with ``w = k(x - i - 1/2) k(y - j - 1/2)``
    non-zero, inside the image.
    """
    height, width = den.shape
    inv_k = 1.0 / k
    reach = int(np.ceil(fradius)) + 1
    for col in range(width):
        for s in range(k * k):
            j = s // k
            i = s - j * k
            u = offsets[col, s, 0] if jitter else 0.5
            v = offsets[col, s, 1] if jitter else 0.5
            x = (col * k + i + u) * inv_k
            y = r + (j + v) * inv_k
            p = best_p[col, s]
            for py in range(max(0, r - reach), min(height, r + reach + 1)):
                wy = profile_at(fkind, fradius, fpieces, falpha, fbias, y - py - 0.5)
                if wy == 0.0:
                    continue
                for px in range(max(0, col - reach), min(width, col + reach + 1)):
                    w = wy * profile_at(fkind, fradius, fpieces, falpha, fbias, x - px - 0.5)
                    if w == 0.0:
                        continue
                    den[py, px] += w
                    for ch in range(3):
                        num[py, px, ch] += w * (background[ch] if p == NO_POLYGON else colors[p, ch])


@njit(cache=True)
def sample_image(width, height, starts, lengths, xs, ys, planes, eps_z, colors, background, k, jitter, seed,
                 fkind, fradius, fpieces, falpha, fbias):
    """Filtered image from ``k x k`` point samples per pixel.

    Sample ``(i, j)`` of pixel ``(row, col)`` lies at ``x = (col k + i + u) / k``,
    ``y = row + (j + v) / k``, with ``u = v = 1/2`` on the regular grid and ``u, v`` from
    :func:`jitter_uniform` when ``jitter``. The box filter averages each
    pixel's own samples; any other filter (``f*`` from
    :func:`aaeval.filters.evaluate.profile_args`) weights every sample by the filter of
    each pixel it reaches and divides by the weight collected (:func:`splat_row`).
    Returns ``(height, width, 3)``.
    """
    row_start, polys = row_buckets(height, starts, lengths, ys)
    ns = k * k
    ex0, ey0, ex1, ey1, xc = edge_buffers(lengths)
    best_z = np.empty((width, ns))
    best_p = np.empty((width, ns), np.int64)
    offsets = np.empty((width, ns, 2))
    image = np.zeros((height, width, 3))
    filtered = fkind != KIND_BOX
    den = np.zeros((height, width) if filtered else (0, 0))
    inv_k = 1.0 / k
    for r in range(height):
        best_z[:] = np.inf
        best_p[:] = NO_POLYGON
        if jitter:
            jitter_offsets(seed, r, width, k, offsets)
        for j in range(k):
            ya = r + j * inv_k
            yb = r + (j + 1) * inv_k
            y = r + (j + 0.5) * inv_k
            for q in range(row_start[r], row_start[r + 1]):
                p = polys[q]
                m, xlo, xhi = strip_edges(xs, ys, starts[p], lengths[p], ya, yb, ex0, ey0, ex1, ey1)
                if m == 0:
                    continue
                a = planes[p, 0]
                b = planes[p, 1]
                c = planes[p, 2]
                if jitter:
                    # samples of a stratum row have different y: test each one
                    c0 = max(0, int(np.floor(xlo)))
                    c1 = min(width - 1, int(np.floor(xhi)))
                    for col in range(c0, c1 + 1):
                        for i in range(k):
                            s = j * k + i
                            x = (col * k + i + offsets[col, s, 0]) * inv_k
                            ys_ = r + (j + offsets[col, s, 1]) * inv_k
                            if inside(ex0, ey0, ex1, ey1, m, x, ys_):
                                z = a * x + b * ys_ + c
                                if best_p[col, s] == NO_POLYGON or nearer_or_tied(z, best_z[col, s], eps_z):
                                    best_z[col, s] = min(z, best_z[col, s])
                                    best_p[col, s] = p
                else:
                    # one scanline through the stratum centres: fill between crossings
                    nc = crossings(ex0, ey0, ex1, ey1, m, y, xc)
                    for t in range(0, nc - 1, 2):
                        g0, g1 = grid_range(xc[t], xc[t + 1], k, width * k)
                        for g in range(g0, g1):
                            col = g // k
                            s = j * k + (g - col * k)
                            z = a * grid_x(g, k) + b * y + c
                            if best_p[col, s] == NO_POLYGON or nearer_or_tied(z, best_z[col, s], eps_z):
                                best_z[col, s] = min(z, best_z[col, s])
                                best_p[col, s] = p
        if filtered:
            splat_row(r, k, jitter, offsets, best_p, colors, background, fkind, fradius, fpieces, falpha, fbias,
                      image, den)
            continue
        for col in range(width):
            for s in range(ns):
                p = best_p[col, s]
                for ch in range(3):
                    image[r, col, ch] += background[ch] if p == NO_POLYGON else colors[p, ch]
            for ch in range(3):
                image[r, col, ch] /= ns
    if filtered:
        for r in range(height):
            for col in range(width):
                for ch in range(3):
                    image[r, col, ch] /= den[r, col]
    return image
