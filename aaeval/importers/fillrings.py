"""Rings of a resolved fill: kept edges linked into non-crossing rings, holes nested.

Step 5 of :func:`aaeval.importers.fill.resolve_fill`: the kept edges, filled side on the
left, are traced into rings; where several meet in one vertex the walk takes the first
edge clockwise from the way it came, so rings never cross (they may touch at a vertex).
Outer rings have a positive shoelace area, holes a negative one; each hole goes to the
smallest outer ring around it. Rings thinner than :data:`CRUMB_RTOL` are rounding crumbs.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["trace_rings", "nest_rings", "ring_area", "CRUMB_RTOL"]

# A ring thinner than this (area over its extent squared) is a rounding crumb of a
# crossing: the scene format refuses it as degenerate, and it covers nothing.
CRUMB_RTOL = 2e-12


def trace_rings(pts, src, dst):
    """Link directed edges into closed rings; at a vertex with several ways on, the first
    edge clockwise from the way back (so the filled side, on the left, stays bounded)."""
    n = len(src)
    if n == 0:
        return []
    order = np.argsort(src, kind="stable")
    starts = np.searchsorted(src[order], np.arange(len(pts) + 1))
    out_count = np.diff(starts)
    nxt = np.full(n, -1, dtype=np.int64)
    simple = out_count[dst] == 1
    nxt[simple] = order[starts[dst[simple]]]
    for e in np.flatnonzero(~simple):
        v = dst[e]
        outs = order[starts[v]:starts[v + 1]]
        if len(outs) == 0:
            continue
        back = pts[src[e]] - pts[v]
        ang_back = math.atan2(back[1], back[0])
        d = pts[dst[outs]] - pts[v]
        ang = np.arctan2(d[:, 1], d[:, 0])
        cw = np.mod(ang_back - ang, 2 * math.pi)
        cw[cw <= 0] += 2 * math.pi
        nxt[e] = outs[int(np.argmin(cw))]
    used = np.zeros(n, dtype=bool)
    rings = []
    for e0 in range(n):
        if used[e0]:
            continue
        ring, e = [], e0
        while e >= 0 and not used[e]:
            used[e] = True
            ring.append(src[e])
            e = nxt[e]
        for part in _split_at_repeats(ring):
            if len(part) >= 3:
                rings.append(pts[np.array(part)])
    return rings


def _split_at_repeats(ring: list) -> list[list]:
    """A closed walk that passes a vertex twice (touching itself there, never crossing) as
    the simple rings between its visits: a lobe, or a hole touching its outer ring."""
    if len(set(ring)) == len(ring):
        return [ring]
    parts, stack, where = [], [], {}
    for v in ring:
        if v in where:
            k = where[v]
            part = stack[k:]
            for u in part[1:]:
                del where[u]
            del stack[k + 1:]
            parts.append(part)
        else:
            where[v] = len(stack)
            stack.append(v)
    parts.append(stack)
    return parts


def ring_area(r) -> float:
    """The signed area of a closed ring of (x, y) rows (the shoelace formula; positive
    counter-clockwise in x-right, y-up axes)."""
    x, y = r[:, 0], r[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _inside(p, ring) -> bool:
    x, y = ring[:, 0], ring[:, 1]
    x2, y2 = np.roll(x, -1), np.roll(y, -1)
    up = (y <= p[1]) & (p[1] < y2)
    down = (y2 <= p[1]) & (p[1] < y)
    side = (x2 - x) * (p[1] - y) - (y2 - y) * (p[0] - x)
    return int(np.sum(up & (side > 0)) - np.sum(down & (side < 0))) != 0


def nest_rings(rings):
    outers, holes = [], []
    for r in rings:
        a = ring_area(r)
        ext = float(np.ptp(r, axis=0).max())
        if abs(a) <= CRUMB_RTOL * ext * ext:
            continue
        (outers if a > 0 else holes).append((abs(a), r))
    outers.sort(key=lambda t: t[0])
    regions = [(r, []) for _, r in outers]
    lo = [r.min(axis=0) for _, r in outers]
    hi = [r.max(axis=0) for _, r in outers]
    for _, h in holes:
        probe = 0.5 * (h[0] + h[1])  # on the hole's first edge, which no outer ring holds
        for k, (_, r) in enumerate(outers):  # smallest first
            if np.all(lo[k] <= probe) and np.all(probe <= hi[k]) and _inside(probe, r):
                regions[k][1].append(h)
                break
    return regions
