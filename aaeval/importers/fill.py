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

1. Candidate edge pairs from a uniform grid over the edges' boxes, swept in x within
   each cell (refused beyond :data:`MAX_PAIRS` pairs sharing a cell, a stated limit
   instead of a quadratic run).
2. For each pair: an end point within the snap distance of the other edge's interior
   splits that edge at the end point itself; two edges crossing properly are both split
   at their intersection (refused first if that would leave more than :data:`MAX_EDGES`
   edges). Collinear overlaps split each other at their end points. This
   is repeated on the pieces until nothing more is cut (an intersection rounded to float64
   can cross a nearly parallel neighbour; the second pass cuts it).
3. Sub-edges between the same two vertices are merged, their directions summed as a
   signed multiplicity (edges whose copies cancel disappear).
4. The winding number on each side of each edge: a ray from the edge's midpoint (along
   +x, or +y for an edge nearer horizontal than vertical) counts the signed crossings of every other edge with
   the half-open rule, in bands of the ray coordinate (about E^1.5 work).
5. Rings are traced through the kept edges; where several meet in one vertex the walk
   takes the first edge clockwise from the way it came, so rings never cross (they may
   touch at a vertex).
"""

from __future__ import annotations

import math

import numpy as np

from aaeval.scenes.simplicity import ring_contact

__all__ = ["resolve_fill", "snap_distance", "FillError", "MAX_PAIRS", "MAX_EDGES"]

# Stated limits: an outline with more edges (as given, or once its crossings would be cut:
# checked before the cut), or whose edges' boxes overlap in more pairs (a quadratic number
# of crossings), is refused instead of running for hours.
MAX_EDGES = 300_000
MAX_PAIRS = 40_000_000
# A ring thinner than this (area over its extent squared) is a rounding crumb of a
# crossing: the scene format refuses it as degenerate, and it covers nothing.
CRUMB_RTOL = 2e-12
# Cutting passes: the second finds the rare crossing that a rounded intersection point
# made with a nearly parallel neighbour; later ones are a safeguard.
MAX_PASSES = 6


class FillError(ValueError):
    """An outline too large or too complex to resolve within the stated limits."""


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
    pts, ea, eb, keep = _vertices(a, b, eps)
    w = w[keep]
    active = None
    for _ in range(MAX_PASSES):  # a crossing rounded to float64 may cross a neighbour: cut again
        pts, ea, eb, w, active = _split(pts, ea, eb, w, eps, active)
        if active is None or not active.any():
            break
    ea, eb, w = _merge(ea, eb, w)
    if len(ea) == 0:
        return []
    left, right = _side_windings(pts, ea, eb, w)
    fill = _filled(rule)
    fl, fr = fill(left), fill(right)
    keep = fl != fr
    src = np.where(fl[keep], ea[keep], eb[keep])  # filled side on the left
    dst = np.where(fl[keep], eb[keep], ea[keep])
    rings_out = _trace(pts, src, dst)
    return _nest(rings_out)


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


def _vertices(a, b, eps):
    """Unique vertices (within eps) and each edge's end point ids."""
    uniq, lab = _cluster(np.concatenate([a, b]), eps)
    used, ids = np.unique(lab, return_inverse=True)
    pts = uniq[used]
    n = len(a)
    ea, eb = ids[:n], ids[n:]
    keep = ea != eb
    return pts, ea[keep], eb[keep], keep


def _candidate_pairs(lo, hi, eps, active=None):
    """Pairs (i < j) of boxes that overlap (with ``eps`` slack), from a uniform grid."""
    n = len(lo)
    if n < 2:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
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
    code = np.unique(i[ok] * n + j[ok])
    return code // n, code % n


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


def _check_cut_edges(before: int, after: int) -> None:
    """Refuse a cut that would leave more than :data:`MAX_EDGES` edges (each crossing cuts
    two edges in two) before it is made: the next pass over them would hold a cell entry
    and candidate pair per close edge (a 2000-point star: 3 million edges, 1.3 GB)."""
    if after > MAX_EDGES:
        raise FillError(f"an outline of {before} edges crosses itself into {after} edges, over the limit of "
                        f"{MAX_EDGES} (split it into simpler paths)")


def _cross(ux, uy, vx, vy):
    return ux * vy - uy * vx


def _split(pts, ea, eb, w, eps, active=None):
    """Cut edges where another edge's end point lies on them or where two edges cross
    (only pairs with an ``active`` edge, if given). Returns the new edges, whether any was
    cut, and which new edges come from cut ones."""
    A, B = pts[ea], pts[eb]
    lo, hi = np.minimum(A, B), np.maximum(A, B)
    i, j = _candidate_pairs(lo, hi, eps, active)
    split_edge, split_vid, new_points, new_edges = [], [], [], []
    if len(i):
        # end points of one edge on the interior of the other (both ways)
        for e, f in ((i, j), (j, i)):
            for end in (ea, eb):
                v = end[f]
                on = (v != ea[e]) & (v != eb[e])
                p, a, b = pts[v], A[e], B[e]
                d = b - a
                length2 = (d * d).sum(axis=1)
                t = ((p - a) * d).sum(axis=1) / length2
                dist = np.abs(_cross(d[:, 0], d[:, 1], p[:, 0] - a[:, 0], p[:, 1] - a[:, 1])) / np.sqrt(length2)
                on &= (dist <= eps) & (t > 0.0) & (t < 1.0)
                split_edge.append(e[on])
                split_vid.append(v[on])
        # proper crossings: no end point of one on the other (those are splits above)
        a, b, c, d = A[i], B[i], A[j], B[j]
        shared = (ea[i] == ea[j]) | (ea[i] == eb[j]) | (eb[i] == ea[j]) | (eb[i] == eb[j])
        ab, cd = b - a, d - c
        lab, lcd = np.hypot(ab[:, 0], ab[:, 1]), np.hypot(cd[:, 0], cd[:, 1])
        o1 = _cross(ab[:, 0], ab[:, 1], c[:, 0] - a[:, 0], c[:, 1] - a[:, 1])
        o2 = _cross(ab[:, 0], ab[:, 1], d[:, 0] - a[:, 0], d[:, 1] - a[:, 1])
        o3 = _cross(cd[:, 0], cd[:, 1], a[:, 0] - c[:, 0], a[:, 1] - c[:, 1])
        o4 = _cross(cd[:, 0], cd[:, 1], b[:, 0] - c[:, 0], b[:, 1] - c[:, 1])
        proper = (~shared & (np.abs(o1) > eps * lab) & (np.abs(o2) > eps * lab) & (np.abs(o3) > eps * lcd)
                  & (np.abs(o4) > eps * lcd) & (np.sign(o1) != np.sign(o2)) & (np.sign(o3) != np.sign(o4)))
        _check_cut_edges(len(ea), len(ea) + 2 * int(proper.sum()))  # before the crossings are made
        if proper.any():
            t = o3[proper] / (o3[proper] - o4[proper])
            x = a[proper] + t[:, None] * ab[proper]
            new_points.append(x)
            new_edges.append((i[proper], j[proper]))
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
        fresh = np.unique(new_lab[rep[new_lab] < 0])
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


def _merge(ea, eb, w):
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


def _side_windings(pts, ea, eb, w):
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
            side = _cross((b[:, 0] - a[:, 0])[None, :], (b[:, 1] - a[:, 1])[None, :],
                          px - a[:, 0][None, :], py - a[:, 1][None, :])
            own = cand[None, :] == queries[rows][:, None]
            hit_up = up & (side > 0) & ~own
            hit_down = down & (side < 0) & ~own
            wc = w[cand][None, :]
            out[rows] = (np.where(hit_up, wc, 0) - np.where(hit_down, wc, 0)).sum(axis=1)
    return out


def _trace(pts, src, dst):
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
    """The signed area of a closed ring of (x, y) rows (the shoelace formula; positive counter-clockwise in x-right, y-up axes)."""
    x, y = r[:, 0], r[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _inside(p, ring) -> bool:
    x, y = ring[:, 0], ring[:, 1]
    x2, y2 = np.roll(x, -1), np.roll(y, -1)
    up = (y <= p[1]) & (p[1] < y2)
    down = (y2 <= p[1]) & (p[1] < y)
    side = (x2 - x) * (p[1] - y) - (y2 - y) * (p[0] - x)
    return int(np.sum(up & (side > 0)) - np.sum(down & (side < 0))) != 0


def _nest(rings):
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
