"""Fill rules resolved in float64: closed polylines to non-crossing rings with holes.

The rings of a path (any winding, crossing themselves or each other, overlapping along
edges) are cut into an arrangement of edges that meet only at their end points, every
arrangement edge is kept where the fill rule fills exactly one of its two sides, and the
kept edges are linked into rings, filled side on the left (shoelace-positive outer rings,
negative holes), each hole given to the smallest outer ring around it.

Everything is float64, and no input vertex ever moves: straight-edged input without
crossings comes out with exactly its own coordinates (only vertices closer than
:func:`snap_distance`, about 100 ulps of the largest coordinate, are taken as one); a
crossing becomes one new vertex, the intersection rounded once to float64.

1. Candidate edge pairs: edges whose boxes overlap (:mod:`aaeval.importers.fillpairs`).
2. The arrangement: edges cut where an end point lies on another edge or two edges cross,
   repeated on the pieces until nothing more is cut (an intersection rounded to float64 can
   cross a nearly parallel neighbour; the second pass cuts it); sub-edges between the same
   two vertices merged into one with a signed multiplicity (:mod:`aaeval.importers.fillcut`).
3. The winding number on each side of each edge, counted on rays
   (:mod:`aaeval.importers.fillwinding`).
4. Every edge kept where the rule fills exactly one of its two sides, the kept edges
   traced into rings and the holes nested (:mod:`aaeval.importers.fillrings`).

The stated limits (edges, close edge pairs) are :data:`aaeval.importers.limits.MAX_EDGES`
and :data:`~aaeval.importers.limits.MAX_PAIRS`, refused with a
:class:`~aaeval.importers.limits.FillError`.
"""

from __future__ import annotations

import numpy as np

from aaeval.importers.fillcut import cut_edges, edge_vertices, merge_edges
from aaeval.importers.fillrings import CRUMB_RTOL, nest_rings, ring_area, trace_rings
from aaeval.importers.fillwinding import side_windings
from aaeval.importers.limits import MAX_EDGES, FillError
from aaeval.scenes.simplicity import ring_contact

__all__ = ["resolve_fill", "snap_distance"]

# Cutting passes: the second finds the rare crossing that a rounded intersection point
# made with a nearly parallel neighbour; later ones are a safeguard.
MAX_PASSES = 6


def snap_distance(scale: float) -> float:
    """Distance under which two points are one and a point lies on an edge."""
    return 2e-14 * max(1.0, scale)


def resolve_fill(rings, rule: str = "nonzero", weights=None):
    """The region a set of closed rings fills under ``rule`` (``nonzero`` or ``evenodd``).

    Parameters
    ----------
    rings : sequence of (n, 2) arrays, closed implicitly (last vertex joins the first).
    rule : ``"nonzero"``, ``"evenodd"``, or ``"positive"`` (winding > 0 after
        ``weights``; with every ring oriented positively this is their union).
    weights : optional int per ring (default 1): each ring's edges count this many times.

    Returns
    -------
    list of (outer, holes): outer an (n, 2) float64 ring of positive shoelace area, holes
    a list of rings of negative area inside it.
    """
    if rule not in ("nonzero", "evenodd", "positive"):
        raise ValueError(f"unknown fill rule {rule!r}; use nonzero or evenodd")
    if len(rings) == 1 and (weights is None or weights[0] == 1) and rule != "positive":
        simple = _simple_ring(rings[0])
        if simple is not None:  # one simple ring fills itself under either rule
            return simple
    a, b, w = _edges(rings, weights)
    if len(a) == 0:
        return []
    if len(a) > MAX_EDGES:
        raise FillError(f"an outline of {len(a)} edges is over the limit of {MAX_EDGES}")
    scale = float(np.abs(np.concatenate([a, b])).max())
    eps = snap_distance(scale)
    pts, ea, eb, keep = edge_vertices(a, b, eps)
    w = w[keep]
    active = None
    for _ in range(MAX_PASSES):  # a crossing rounded to float64 may cross a neighbour: cut again
        pts, ea, eb, w, active = cut_edges(pts, ea, eb, w, eps, active)
        if active is None or not active.any():
            break
    ea, eb, w = merge_edges(ea, eb, w)
    if len(ea) == 0:
        return []
    left, right = side_windings(pts, ea, eb, w)
    fill = _filled(rule)
    fl, fr = fill(left), fill(right)
    keep = fl != fr
    src = np.where(fl[keep], ea[keep], eb[keep])  # filled side on the left
    dst = np.where(fl[keep], eb[keep], ea[keep])
    rings_out = trace_rings(pts, src, dst)
    return nest_rings(rings_out)


def _simple_ring(ring):
    """The region of one ring that neither crosses nor touches itself (the scene format's
    own simplicity check): itself, oriented positively; None when that does not hold."""
    r = np.asarray(ring, dtype=np.float64).reshape(-1, 2)
    if len(r) > 4096 or not np.isfinite(r).all():
        return None
    r = r[np.any(r != np.roll(r, 1, axis=0), axis=1)]
    if len(r) < 3:
        return []
    a = ring_area(r)
    ext = float(np.ptp(r, axis=0).max())
    if abs(a) <= CRUMB_RTOL * ext * ext or ring_contact(r) is not None:
        return None
    return [(r if a > 0 else r[::-1].copy(), [])]


def _filled(rule):
    if rule == "nonzero":
        return lambda wn: wn != 0
    if rule == "evenodd":
        return lambda wn: (wn % 2) != 0
    return lambda wn: wn > 0


def _edges(rings, weights):
    arrays, ws = [], []
    for k, ring in enumerate(rings):
        r = np.asarray(ring, dtype=np.float64).reshape(-1, 2)
        if len(r) >= 2:
            arrays.append(r)
            ws.append(1 if weights is None else int(weights[k]))
    if not arrays:
        return np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0, np.int64)
    lengths = np.array([len(r) for r in arrays])
    a = np.concatenate(arrays)
    if not np.isfinite(a).all():
        raise FillError("an outline has a coordinate that is not a finite number")
    starts = np.cumsum(lengths) - lengths
    nxt = np.arange(len(a)) + 1
    nxt[starts + lengths - 1] = starts  # each ring closes on its first vertex
    b = a[nxt]
    w = np.repeat(np.array(ws, dtype=np.int64), lengths)
    moving = np.any(a != b, axis=1)
    return a[moving], b[moving], w[moving]
