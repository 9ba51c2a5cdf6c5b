"""Winding numbers on both sides of every edge of an arrangement, counted on rays.

Step 4 of :func:`aaeval.importers.fill.resolve_fill`: a ray from each edge's midpoint
(along +x, or +y for an edge nearer horizontal than vertical) counts the signed crossings
of every other edge with the half-open rule, in bands of the ray coordinate (about E^1.5
work). The counts are integers, so the answer does not depend on how the work is banded.
"""

from __future__ import annotations

import math

import numpy as np

from aaeval.importers.fillcut import cross

__all__ = ["side_windings"]


def side_windings(pts, ea, eb, w):
    """Winding numbers just left and just right of every edge (ea -> eb, multiplicity w)."""
    A, B = pts[ea], pts[eb]
    # the ray runs along the axis the edge spans least: it leaves the edge's midpoint at
    # 45 degrees or more, so the points beside it are beside the edge, not along it
    horizontal = np.abs(B[:, 1] - A[:, 1]) < np.abs(B[:, 0] - A[:, 0])
    left = np.zeros(len(ea), dtype=np.int64)
    right = np.zeros(len(ea), dtype=np.int64)
    for swap in (False, True):
        q = np.flatnonzero(horizontal == swap)
        if len(q) == 0:
            continue
        P, Q = (A[:, ::-1], B[:, ::-1]) if swap else (A, B)
        plus = _ray_windings(P, Q, w, q)  # at the midpoint + dx (own edge left out)
        dy = Q[q, 1] - P[q, 1]
        minus = plus + np.sign(dy).astype(np.int64) * w[q]
        plus_is_left = dy < 0
        if swap:  # a mirror image: its left is our right, and its windings turn the other way
            plus_is_left = ~plus_is_left
            plus, minus = -plus, -minus
        left[q] = np.where(plus_is_left, plus, minus)
        right[q] = np.where(plus_is_left, minus, plus)
    return left, right


SMALL_BLOCK = 40_000  # query x edge pairs below which _ray_windings takes one block


def _ray_windings(A, B, w, queries):
    """For each query edge, the winding number at its midpoint of all the other edges,
    counted on the ray towards +x with the half-open rule (a.y <= y < b.y)."""
    m = 0.5 * (A[queries] + B[queries])
    qy = m[:, 1]
    ylo, yhi = np.minimum(A[:, 1], B[:, 1]), np.maximum(A[:, 1], B[:, 1])
    out = np.zeros(len(queries), dtype=np.int64)
    order = np.argsort(qy, kind="stable")
    # bands of queries, each against the edges its y range meets: a large outline's blocks
    # stay small; a small one (a glyph) is one block, as numpy's calls cost more than its
    # arithmetic (the counts are integers: the same whichever edges a band leaves out)
    nb = 1 if len(queries) * len(A) <= SMALL_BLOCK else max(1, int(math.sqrt(len(A))))
    bands = np.array_split(order, nb)
    for band in bands:
        if len(band) == 0:
            continue
        y0, y1 = qy[band].min(), qy[band].max()
        cand = np.flatnonzero((ylo <= y1) & (yhi > y0))
        if len(cand) == 0:
            continue
        # chunks so that the (queries x edges) block stays small
        step = max(1, int(4_000_000 // max(len(cand), 1)))
        for s in range(0, len(band), step):
            rows = band[s:s + step]
            px, py = m[rows, 0][:, None], m[rows, 1][:, None]
            a, b = A[cand], B[cand]
            ay, by = a[:, 1][None, :], b[:, 1][None, :]
            up = (ay <= py) & (py < by)
            down = (by <= py) & (py < ay)
            side = cross((b[:, 0] - a[:, 0])[None, :], (b[:, 1] - a[:, 1])[None, :],
                          px - a[:, 0][None, :], py - a[:, 1][None, :])
            own = cand[None, :] == queries[rows][:, None]
            hit_up = up & (side > 0) & ~own
            hit_down = down & (side < 0) & ~own
            wc = w[cand][None, :]
            out[rows] = (np.where(hit_up, wc, 0) - np.where(hit_down, wc, 0)).sum(axis=1)
    return out
