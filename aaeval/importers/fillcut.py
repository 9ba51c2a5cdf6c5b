"""The arrangement of an outline's edges: edges cut so that they meet only at end points.

Steps 2 and 3 of :func:`aaeval.importers.fill.resolve_fill`. Vertices closer than the snap
distance are one (:func:`edge_vertices`); for each candidate pair
(:func:`aaeval.importers.fillpairs.candidate_pairs`) an end point within the snap distance
of the other edge's interior splits that edge at the end point itself, and two edges
crossing properly are both split at their intersection, rounded once to float64 (refused
first if that would leave more than :data:`~aaeval.importers.limits.MAX_EDGES` edges).
Collinear overlaps split each other at their end points. Sub-edges between the same two
vertices are then merged, their directions summed as a signed multiplicity
(:func:`merge_edges`; edges whose copies cancel disappear).
"""

from __future__ import annotations

import numpy as np

from aaeval.importers.fillpairs import candidate_pairs, distinct
from aaeval.importers.limits import MAX_EDGES, FillError

__all__ = ["edge_vertices", "cut_edges", "merge_edges", "cross"]


def _cluster(points: np.ndarray, eps: float):
    """Unique points and a label per input point: points closer than ``eps`` in both
    coordinates (transitively) share one label, the smallest index of the unique points.

    Runs of x within ``eps`` (sorted by x), then runs of y within ``eps`` inside each x
    run: two points within ``eps`` always fall into one run of each (every point between
    them in the sort is closer still), so no close pair is missed; only chains of points
    each within ``eps`` of the next are joined beyond it.
    """
    uniq, inverse = np.unique(points, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    n = len(uniq)
    labels = np.arange(n)
    if n > 1:
        x, y = uniq[:, 0], uniq[:, 1]  # np.unique sorted them by x, then y
        run_x = np.concatenate([[0], np.cumsum(np.diff(x) > eps)])
        if run_x[-1] < n - 1:  # some x run holds two points
            order = np.lexsort((y, run_x))
            ys, rx = y[order], run_x[order]
            run = np.concatenate([[0], np.cumsum((np.diff(rx) != 0) | (np.diff(ys) > eps))])
            first = np.full(n, n, dtype=np.int64)
            np.minimum.at(first, run, order)
            labels = np.empty(n, dtype=np.int64)
            labels[order] = first[run]
    return uniq, labels[inverse]


def edge_vertices(a, b, eps):
    """Unique vertices (within eps) and each edge's end point ids."""
    uniq, lab = _cluster(np.concatenate([a, b]), eps)
    used, ids = np.unique(lab, return_inverse=True)
    pts = uniq[used]
    n = len(a)
    ea, eb = ids[:n], ids[n:]
    keep = ea != eb
    return pts, ea[keep], eb[keep], keep


def _check_cut_edges(before: int, after: int) -> None:
    """Refuse a cut that would leave more than :data:`MAX_EDGES` edges (each crossing cuts
    two edges in two) before it is made: the next pass over them would hold a cell entry
    and candidate pair per close edge (a 2000-point star: 3 million edges, 1.3 GB)."""
    if after > MAX_EDGES:
        raise FillError(f"an outline of {before} edges crosses itself into {after} edges, over the limit of "
                        f"{MAX_EDGES} (split it into simpler paths)")


def cross(ux, uy, vx, vy):
    """The z component of the cross product of vectors u and v (elementwise on arrays)."""
    return ux * vy - uy * vx


def cut_edges(pts, ea, eb, w, eps, active=None):
    """Cut edges where another edge's end point lies on them or where two edges cross
    (only pairs with an ``active`` edge, if given). Returns the new edges, whether any was
    cut, and which new edges come from cut ones."""
    A, B = pts[ea], pts[eb]
    lo, hi = np.minimum(A, B), np.maximum(A, B)
    i, j = candidate_pairs(lo, hi, eps, active)
    split_edge, split_vid, new_points, new_edges = [], [], [], []
    if len(i):
        # proper crossings: no end point of one on the other (those are splits below); counted
        # first, so an outline refused for its crossings costs no more than counting them
        a, b, c, d = A[i], B[i], A[j], B[j]
        shared = (ea[i] == ea[j]) | (ea[i] == eb[j]) | (eb[i] == ea[j]) | (eb[i] == eb[j])
        ab, cd = b - a, d - c
        lab, lcd = np.hypot(ab[:, 0], ab[:, 1]), np.hypot(cd[:, 0], cd[:, 1])
        o1 = cross(ab[:, 0], ab[:, 1], c[:, 0] - a[:, 0], c[:, 1] - a[:, 1])
        o2 = cross(ab[:, 0], ab[:, 1], d[:, 0] - a[:, 0], d[:, 1] - a[:, 1])
        o3 = cross(cd[:, 0], cd[:, 1], a[:, 0] - c[:, 0], a[:, 1] - c[:, 1])
        o4 = cross(cd[:, 0], cd[:, 1], b[:, 0] - c[:, 0], b[:, 1] - c[:, 1])
        proper = (~shared & (np.abs(o1) > eps * lab) & (np.abs(o2) > eps * lab) & (np.abs(o3) > eps * lcd)
                  & (np.abs(o4) > eps * lcd) & (np.sign(o1) != np.sign(o2)) & (np.sign(o3) != np.sign(o4)))
        _check_cut_edges(len(ea), len(ea) + 2 * int(proper.sum()))  # before the crossings are made
        if proper.any():
            t = o3[proper] / (o3[proper] - o4[proper])
            x = a[proper] + t[:, None] * ab[proper]
            new_points.append(x)
            new_edges.append((i[proper], j[proper]))
        # end points of one edge on the interior of the other (both ways)
        for e, f in ((i, j), (j, i)):
            for end in (ea, eb):
                v = end[f]
                on = (v != ea[e]) & (v != eb[e])
                p, a, b = pts[v], A[e], B[e]
                d = b - a
                length2 = (d * d).sum(axis=1)
                t = ((p - a) * d).sum(axis=1) / length2
                dist = np.abs(cross(d[:, 0], d[:, 1], p[:, 0] - a[:, 0], p[:, 1] - a[:, 1])) / np.sqrt(length2)
                on &= (dist <= eps) & (t > 0.0) & (t < 1.0)
                split_edge.append(e[on])
                split_vid.append(v[on])
    if new_points:
        x = np.concatenate(new_points)
        ei = np.concatenate([p[0] for p in new_edges])
        ej = np.concatenate([p[1] for p in new_edges])
        # crossings at one place (three edges through a point) become one vertex; a crossing
        # within eps of an existing vertex is that vertex
        uniq, lab = _cluster(np.concatenate([pts, x]), eps)
        n0 = len(pts)
        # map every cluster to an existing vertex where it holds one, else to a new vertex
        rep = np.full(len(uniq), -1, dtype=np.int64)
        old_lab = lab[:n0]
        rep[old_lab] = np.arange(n0)  # existing vertices keep their ids (clusters of old ones: last wins)
        new_lab = lab[n0:]
        fresh = distinct(new_lab[rep[new_lab] < 0])
        rep[fresh] = n0 + np.arange(len(fresh))
        pts = np.concatenate([pts, uniq[fresh]])
        vid = rep[new_lab]
        split_edge += [ei, ej]
        split_vid += [vid, vid]
    if not split_edge or sum(len(s) for s in split_edge) == 0:
        return pts, ea, eb, w, None
    se = np.concatenate(split_edge)
    sv = np.concatenate(split_vid)
    # drop splits at an edge's own end points (a crossing snapped onto one)
    ok = (sv != ea[se]) & (sv != eb[se])
    se, sv = se[ok], sv[ok]
    if len(se) == 0:
        return pts, ea, eb, w, None
    a, b = pts[ea[se]], pts[eb[se]]
    d = b - a
    t = ((pts[sv] - a) * d).sum(axis=1) / (d * d).sum(axis=1)
    # every edge's chain: start (t = -1), splits by t, end (t = 2)
    m = len(ea)
    all_e = np.concatenate([np.arange(m), se, np.arange(m)])
    all_t = np.concatenate([np.full(m, -1.0), t, np.full(m, 2.0)])
    all_v = np.concatenate([ea, sv, eb])
    order = np.lexsort((all_t, all_e))
    all_e, all_v = all_e[order], all_v[order]
    same = all_e[1:] == all_e[:-1]
    u, v = all_v[:-1][same], all_v[1:][same]
    parent = all_e[:-1][same]
    ww = w[parent]
    cut = np.zeros(m, dtype=bool)
    cut[se] = True
    keep = u != v
    return pts, u[keep], v[keep], ww[keep], cut[parent][keep]


def merge_edges(ea, eb, w):
    """Sub-edges between the same vertices as one, with the signed sum of their multiplicities."""
    lo, hi = np.minimum(ea, eb), np.maximum(ea, eb)
    sign = np.where(ea < eb, 1, -1) * w
    n = int(max(ea.max(), eb.max())) + 1
    code, inverse = np.unique(lo * n + hi, return_inverse=True)
    total = np.zeros(len(code), dtype=np.int64)
    np.add.at(total, inverse.reshape(-1), sign)
    keep = total != 0
    code, total = code[keep], total[keep]
    return code // n, code % n, total  # edge lo -> hi counted ``total`` times
