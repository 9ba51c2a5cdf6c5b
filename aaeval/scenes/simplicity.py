"""Whether polygon outlines cross or touch themselves or each other, in O(n log n).

A scene polygon must be simple: no two of its edges meet except consecutive edges at
their shared vertex. Comparing every pair of edges costs n^2 / 2 tests and as much
memory (37 GiB at 100000 vertices), so outlines beyond a few hundred edges are checked
with the Shamos-Hoey sweep line: edges enter an ordered list at their left end and leave
it at their right end, and only edges that become neighbours in that list are tested.
The leftmost meeting point of any two edges is always between two neighbours, so the
sweep finds a meeting whenever there is one, in O(n log n) time and O(n) memory
(M. I. Shamos and D. Hoey, "Geometric intersection problems", FOCS 1976).

The functions take *rings*: closed outlines given as ``(n, 2)`` arrays of their vertices,
without the closing vertex, edge ``k`` running from vertex ``k`` to vertex ``k + 1``. One
ring is one polygon outline; several rings (an outline and its holes) are checked together,
where no edge of one ring may meet any edge of another.

The sweep runs in C++ (``src/samplers/simplicity.cpp``, module ``aaeval.native.samplers``).
Orientation signs are computed in float64 the way the pairwise test computes them, so the
two agree wherever the signs are exact (integer coordinates, tests/scenes/test_simplicity.py);
a meeting or a miss within rounding error of a tie may be judged either way by either.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from aaeval.native.samplers import first_meeting_pair as _native_first_pair
from aaeval.native.samplers import sweep as _native_sweep

__all__ = ["ring_contact", "rings_contact", "BRUTE_FORCE_EDGES"]

# Up to this many edges in all, every pair whose boxes meet is tested, natively (the sweep's
# sorting and bookkeeping do not pay on a small outline, most of what a font's glyphs are).
BRUTE_FORCE_EDGES = 256


def ring_contact(xy: np.ndarray) -> tuple[int, int] | None:
    """Two edges ``(i, j)``, ``i < j``, of the closed ring ``xy`` that meet other than
    consecutive edges at their shared vertex; None when the ring is simple."""
    hit = rings_contact([xy])
    return None if hit is None else (hit[1], hit[3])


def rings_contact(rings: Sequence[np.ndarray]) -> tuple[int, int, int, int] | None:
    """``(ring_a, edge_i, ring_b, edge_j)`` of two edges that meet, ``(ring_a, edge_i) <
    (ring_b, edge_j)``, or None when every ring is simple and no two rings meet.

    Edges meet when the closed segments share a point; consecutive edges of a ring may
    share only their common vertex (folding back along each other is a meeting).
    """
    rings = [np.ascontiguousarray(np.asarray(r, dtype=np.float64)[:, :2]) for r in rings]
    sizes = np.array([len(r) for r in rings], dtype=np.int64)
    if not len(rings) or sizes.sum() == 0:
        return None
    pts = np.concatenate(rings)
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    # edge e runs from vertex a[e] to vertex b[e] (global vertex indices)
    a = np.arange(len(pts), dtype=np.int64)
    ring_of = np.repeat(np.arange(len(rings)), sizes)
    b = a + 1
    last = first + sizes - 1
    b[last] = first
    if len(pts) <= BRUTE_FORCE_EDGES:
        e, f = _native_first_pair(pts, a, b)
        hit = None if e < 0 else (int(e), int(f))
    else:
        hit = _duplicate_vertices(pts)
        if hit is None:
            order = np.lexsort((pts[:, 1], pts[:, 0]))
            incoming = np.empty(len(pts), dtype=np.int64)
            incoming[b] = a  # edge ending at vertex v; edge e starts at vertex e
            e, f = _native_sweep(pts, a, b, order.astype(np.int64), incoming)
            hit = None if e < 0 else (int(e), int(f))
    if hit is None:
        return None
    e, f = sorted(hit)
    return int(ring_of[e]), int(e - first[ring_of[e]]), int(ring_of[f]), int(f - first[ring_of[f]])


def _duplicate_vertices(pts: np.ndarray) -> tuple[int, int] | None:
    """Edges starting at two vertices at the same place: they touch there."""
    order = np.lexsort((pts[:, 1], pts[:, 0]))
    s = pts[order]
    same = np.flatnonzero(np.all(s[1:] == s[:-1], axis=1))
    if not len(same):
        return None
    return int(order[same[0]]), int(order[same[0] + 1])


def _brute_force(pts: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[int, int] | None:
    """The plain reference of the native brute force (``first_meeting_pair`` in
    ``src/samplers/simplicity.cpp``): the first pair, in ``np.triu_indices`` order, of edges
    whose boxes meet and that meet; the tests hold the two to the same answers."""
    i, j = _pairs_with_meeting_boxes(pts, a, b)
    shared = (a[i] == a[j]) | (a[i] == b[j]) | (b[i] == a[j]) | (b[i] == b[j])
    p, q, r, s = pts[a[i]], pts[b[i]], pts[a[j]], pts[b[j]]
    o1, o2, o3, o4 = _orient(p, q, r), _orient(p, q, s), _orient(r, s, p), _orient(r, s, q)
    proper = (o1 * o2 < 0) & (o3 * o4 < 0)
    touching = ((o1 == 0) & _within(p, q, r)) | ((o2 == 0) & _within(p, q, s)) | (
        (o3 == 0) & _within(r, s, p)) | ((o4 == 0) & _within(r, s, q))
    # consecutive edges meet at their vertex; they may not also run along each other
    far_i = np.where((a[i] == a[j]) | (a[i] == b[j]), b[i], a[i])
    far_j = np.where((a[j] == a[i]) | (a[j] == b[i]), b[j], a[j])
    near = np.where((a[i] == a[j]) | (a[i] == b[j]), a[i], b[i])
    fp, fq, nv = pts[far_i], pts[far_j], pts[near]
    fold = (_orient(nv, fp, fq) == 0) & (_within(nv, fp, fq) | _within(nv, fq, fp))
    hit = np.where(shared, fold, proper | touching)
    if not hit.any():
        return None
    k = int(np.flatnonzero(hit)[0])
    return int(i[k]), int(j[k])


def _pairs_with_meeting_boxes(pts: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every pair of edges (i < j, in ``np.triu_indices`` order) whose bounding boxes meet.

    Edges that meet in any way (crossing, touching, sharing a vertex) have meeting boxes,
    and the box test is exact (comparisons only), so the pairs left out are ones the full
    test would pass; most pairs of a long outline are far apart. The pairs come from a
    sweep in x (each edge, in order of left end, with the edges that start before its
    right end), then the y test, then sorted back into ``triu_indices`` order, so the
    first meeting pair is the one the all-pairs test finds first.
    """
    lo = np.minimum(pts[a], pts[b])
    hi = np.maximum(pts[a], pts[b])
    order = np.argsort(lo[:, 0], kind="stable")
    left = lo[order, 0]
    partners = np.searchsorted(left, hi[order, 0], side="right") - np.arange(len(order)) - 1
    first = np.repeat(np.arange(len(order)), partners)
    second = first + 1 + np.arange(len(first)) - np.repeat(np.cumsum(partners) - partners, partners)
    e, f = order[first], order[second]
    i, j = np.minimum(e, f), np.maximum(e, f)
    meet = (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1])
    i, j = i[meet], j[meet]
    ranked = np.argsort(i * len(a) + j)
    return i[ranked], j[ranked]


def _orient(p, q, r):
    return np.sign((q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0]))


def _within(p, q, r):  # r on segment pq, given collinear
    return ((np.minimum(p[:, 0], q[:, 0]) <= r[:, 0]) & (r[:, 0] <= np.maximum(p[:, 0], q[:, 0]))
            & (np.minimum(p[:, 1], q[:, 1]) <= r[:, 1]) & (r[:, 1] <= np.maximum(p[:, 1], q[:, 1])))
