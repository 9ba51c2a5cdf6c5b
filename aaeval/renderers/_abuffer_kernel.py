"""Carpenter 1984 A-buffer (numba kernel).

Per pixel, every polygon that reaches a subsample becomes a *fragment*: a 4 x 8 bit
coverage mask (4 rows of 8 subsamples, bit ``8 j + i`` at the subcell centre
``(col + (i + 1/2)/8, row + (j + 1/2)/4)``) and the z range of its plane over the part
of the polygon inside the pixel. The mask is Carpenter's XOR of per-edge masks (a bit
flips for every edge crossing to its right), i.e. the crossing-parity test of
:func:`aaeval.renderers._sampling_kernel.inside` at the 32 subcell centres. The z range
is exact: the plane is linear, so its extremes over polygon ∩ pixel lie at that
region's vertices, which are the polygon's edges clipped to the pixel square and the
pixel corners inside the polygon.

Resolution, front to back: fragments are sorted on ``zmin`` by the scene format's tie
rule (fragments within ``eps_z`` of the nearest ``zmin`` are tied, the later polygon in
the file first: :func:`aaeval.scenes.depth.tied_latest_first`) and each one claims the subsamples of its mask that no nearer fragment has
claimed. Where the z range of a fragment ``f`` overlaps that of the next fragment ``g``
whose mask meets f's claimed bits, the two surfaces may cross inside the pixel, and the
paper blends them on the shared bits by the fraction of f estimated to be in front,
assuming the two planes run in opposite directions across the pixel::

    front = (g.zmax - f.zmin) / ((f.zmax - f.zmin) + (g.zmax - g.zmin))

(clamped to [0, 1]). The paper is not in ``shared/seeds``: this formula is the one the
A-buffer is usually described with, not checked against its text. For planes of equal
and opposite slope across the pixel the estimate is exact.

This is a simple version of Carpenter's recursive blender: only the next overlapping
fragment is blended in (not the whole chain behind it), and two fragments on one plane
over the pixel are not blended — the later polygon in the file takes the shared bits,
as the scene format requires. Everything else is quantised to 1/32 of the pixel.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from aaeval.renderers._catmull_kernel import _grow
from aaeval.renderers._sampling_kernel import (
    crossings,
    edge_buffers,
    grid_range,
    inside,
    row_buckets,
    strip_edges,
)
from aaeval.scenes.depth import tied_latest_first

SUBSAMPLES = 32
SUB_COLS = 8
SUB_ROWS = 4
FULL_MASK = (1 << SUBSAMPLES) - 1


@njit(cache=True, inline="always")
def popcount(v):
    n = 0
    while v:
        v &= v - 1
        n += 1
    return n


@njit(cache=True)
def coverage_masks(ex0, ey0, ex1, ey1, m, row, width, c0, c1, xc, masks):
    """The 32-bit masks of the polygon over pixels ``c0..c1`` of a row, into ``masks[c0:c1+1]``.

    Bit ``8 j + i`` of pixel ``col`` is the subcell centre ``((8 col + i + 1/2)/8,
    row + (j + 1/2)/4)``; a bit is set between crossing pairs of its subsample row.
    """
    masks[c0 : c1 + 1] = 0
    for j in range(SUB_ROWS):
        nc = crossings(ex0, ey0, ex1, ey1, m, row + (j + 0.5) / SUB_ROWS, xc)
        for t in range(0, nc - 1, 2):
            g0, g1 = grid_range(xc[t], xc[t + 1], SUB_COLS, width * SUB_COLS)
            for g in range(g0, g1):
                col = g // SUB_COLS
                masks[col] |= 1 << (j * SUB_COLS + g - col * SUB_COLS)


@njit(cache=True)
def z_range(ex0, ey0, ex1, ey1, m, col, row, a, b, c):
    """Min and max of ``z = a x + b y + c`` over the polygon inside the pixel square."""
    zlo = np.inf
    zhi = -np.inf
    x0b = float(col)
    x1b = col + 1.0
    y0b = float(row)
    y1b = row + 1.0
    for e in range(m):
        # Liang-Barsky: the part of the edge inside the square
        px = ex0[e]
        py = ey0[e]
        dx = ex1[e] - px
        dy = ey1[e] - py
        t0 = 0.0
        t1 = 1.0
        ok = True
        for k in range(4):
            if k == 0:
                pp, qq = -dx, px - x0b
            elif k == 1:
                pp, qq = dx, x1b - px
            elif k == 2:
                pp, qq = -dy, py - y0b
            else:
                pp, qq = dy, y1b - py
            if pp == 0.0:
                if qq < 0.0:
                    ok = False
                    break
            else:
                t = qq / pp
                if pp < 0.0:
                    t0 = max(t0, t)
                else:
                    t1 = min(t1, t)
                if t0 > t1:
                    ok = False
                    break
        if not ok:
            continue
        for t in (t0, t1):
            z = a * (px + t * dx) + b * (py + t * dy) + c
            zlo = min(zlo, z)
            zhi = max(zhi, z)
    for cy in (y0b, y1b):
        for cx in (x0b, x1b):
            if inside(ex0, ey0, ex1, ey1, m, cx, cy):
                z = a * cx + b * cy + c
                zlo = min(zlo, z)
                zhi = max(zhi, z)
    if zlo > zhi:  # a sliver touching no edge or corner test: use the centre
        zlo = zhi = a * (col + 0.5) + b * (row + 0.5) + c
    return zlo, zhi


@njit(cache=True)
def _same_plane(planes, p, q, col, row, eps_z):
    x0 = float(col)
    y0 = float(row)
    for cx, cy in ((x0, y0), (x0 + 1.0, y0), (x0, y0 + 1.0)):
        zp = planes[p, 0] * cx + planes[p, 1] * cy + planes[p, 2]
        zq = planes[q, 0] * cx + planes[q, 1] * cy + planes[q, 2]
        if abs(zp - zq) > eps_z:
            return False
    return True


@njit(cache=True)
def resolve_pixel(order, fmask, fzmin, fzmax, fpoly, planes, eps_z, colors, background, col, row, out):
    """Front-to-back resolution of one pixel's sorted fragments into ``out`` (3,)."""
    free = FULL_MASK
    acc0 = 0.0
    acc1 = 0.0
    acc2 = 0.0
    n = order.size
    for a in range(n):
        f = order[a]
        claim = fmask[f] & free
        if claim == 0:
            continue
        pf = fpoly[f]
        g = -1
        for b in range(a + 1, n):
            if fmask[order[b]] & claim:
                g = order[b]
                break
        w_front = float(popcount(claim))
        w_back = 0.0
        pg = 0
        if g >= 0 and fzmin[g] < fzmax[f]:
            pg = fpoly[g]
            shared = float(popcount(claim & fmask[g]))
            if _same_plane(planes, pf, pg, col, row, eps_z):
                front = 1.0 if pf > pg else 0.0
            else:
                span = (fzmax[f] - fzmin[f]) + (fzmax[g] - fzmin[g])
                front = (fzmax[g] - fzmin[f]) / span if span > 0.0 else 0.5
                front = min(1.0, max(0.0, front))
            w_back = shared * (1.0 - front)
            w_front -= w_back
        acc0 += w_front * colors[pf, 0] + w_back * colors[pg, 0]
        acc1 += w_front * colors[pf, 1] + w_back * colors[pg, 1]
        acc2 += w_front * colors[pf, 2] + w_back * colors[pg, 2]
        free &= ~claim
        if free == 0:
            break
    w_bg = float(popcount(free))
    out[0] = (acc0 + w_bg * background[0]) / SUBSAMPLES
    out[1] = (acc1 + w_bg * background[1]) / SUBSAMPLES
    out[2] = (acc2 + w_bg * background[2]) / SUBSAMPLES


@njit(cache=True)
def abuffer_image(width, height, starts, lengths, xs, ys, planes, eps_z, colors, background):
    """The A-buffer image ``(height, width, 3)`` of the polygons (file order)."""
    row_start, polys = row_buckets(height, starts, lengths, ys)
    ex0, ey0, ex1, ey1, xc = edge_buffers(lengths)
    masks = np.zeros(width, np.int64)
    fcol = np.empty(64, np.int64)
    fmask = np.empty(64, np.int64)
    fzmin = np.empty(64)
    fzmax = np.empty(64)
    fpoly = np.empty(64, np.int64)
    image = np.empty((height, width, 3))
    per_col = np.zeros(width + 1, np.int64)
    for r in range(height):
        nf = 0
        for q in range(row_start[r], row_start[r + 1]):
            p = polys[q]
            m, xlo, xhi = strip_edges(xs, ys, starts[p], lengths[p], float(r), r + 1.0, ex0, ey0, ex1, ey1)
            if m == 0:
                continue
            c0 = max(0, int(np.floor(xlo)))
            c1 = min(width - 1, int(np.floor(xhi)))
            if c0 > c1:
                continue
            coverage_masks(ex0, ey0, ex1, ey1, m, r, width, c0, c1, xc, masks)
            for col in range(c0, c1 + 1):
                mask = masks[col]
                if mask == 0:
                    continue
                zlo, zhi = z_range(ex0, ey0, ex1, ey1, m, col, r, planes[p, 0], planes[p, 1], planes[p, 2])
                fcol = _grow(fcol, nf + 1)
                fmask = _grow(fmask, nf + 1)
                fzmin = _grow(fzmin, nf + 1)
                fzmax = _grow(fzmax, nf + 1)
                fpoly = _grow(fpoly, nf + 1)
                fcol[nf] = col
                fmask[nf] = mask
                fzmin[nf] = zlo
                fzmax[nf] = zhi
                fpoly[nf] = p
                nf += 1
        # bucket the row's fragments by column, then sort each pixel's on (zmin, -polygon)
        # and put each run within eps_z of its nearest zmin latest polygon first
        per_col[:] = 0
        for f in range(nf):
            per_col[fcol[f] + 1] += 1
        for col in range(width):
            per_col[col + 1] += per_col[col]
        order = np.empty(nf, np.int64)
        fill = per_col[:width].copy()
        for f in range(nf):
            order[fill[fcol[f]]] = f
            fill[fcol[f]] += 1
        for col in range(width):
            lo = per_col[col]
            hi = per_col[col + 1]
            for a in range(lo + 1, hi):
                f = order[a]
                b = a - 1
                while b >= lo and (
                    fzmin[order[b]] > fzmin[f] or (fzmin[order[b]] == fzmin[f] and fpoly[order[b]] < fpoly[f])
                ):
                    order[b + 1] = order[b]
                    b -= 1
                order[b + 1] = f
            tied_latest_first(order[lo:hi], fzmin, fpoly, eps_z)
            resolve_pixel(order[lo:hi], fmask, fzmin, fzmax, fpoly, planes, eps_z, colors, background,
                          col, r, image[r, col])
    return image
