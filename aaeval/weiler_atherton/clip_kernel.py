"""Compiled stages of the Weiler-Atherton clipper (numba); :mod:`.clipper` is the API.

A shape is four arrays here: ``xs``, ``ys`` (the vertices, contour after contour),
``labels`` (``labels[v]`` labels the edge from vertex v to the next one of its contour)
and ``starts`` (contour i is vertices ``starts[i]:starts[i + 1]``). Contours are oriented
as in :mod:`.clipper`: main contours positive shoelace area, holes negative.

Inside :func:`clip_arrays` every vertex is a *point id*: the index of its coordinates in
the sorted list of distinct points of both shapes and their crossings. Vertices that
coincide share one id, so the shared vertices and edges the paper links the two contour
chains through are found by comparing integers.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["clip_arrays", "ring_area_of", "winding", "shape_bbox", "first_crossing"]

TWO_PI = 2.0 * math.pi
SMALL_SORT = 24  # below this many keys an insertion sort beats numpy's argsort


# -- geometry predicates -------------------------------------------------------------------


@njit(cache=True)
def ring_area_of(xs, ys, a, b):
    """Shoelace area of the contour made of vertices a..b-1 (positive: main contour)."""
    if b - a < 3:
        return 0.0
    x0 = xs[a]
    y0 = ys[a]
    s = 0.0
    for i in range(a + 1, b - 1):
        s += (xs[i] - x0) * (ys[i + 1] - y0) - (xs[i + 1] - x0) * (ys[i] - y0)
    return 0.5 * s


@njit(cache=True)
def _winds(px, py, x0, y0, x1, y1):
    """What edge (x0, y0)-(x1, y1) adds to the winding number of the point: +1 crossing
    its horizontal line upwards with the point on the left, -1 downwards on the right."""
    if y0 <= py:
        if y1 > py and (x1 - x0) * (py - y0) - (px - x0) * (y1 - y0) > 0:
            return 1
    elif y1 <= py and (x1 - x0) * (py - y0) - (px - x0) * (y1 - y0) < 0:
        return -1
    return 0


@njit(cache=True)
def winding(px, py, xs, ys, starts):
    """Winding number of the point about the oriented contours (1 inside a shape)."""
    w = 0
    for r in range(len(starts) - 1):
        a = starts[r]
        b = starts[r + 1]
        for i in range(a, b):
            j = b - 1 if i == a else i - 1
            w += _winds(px, py, xs[j], ys[j], xs[i], ys[i])
    return w


@njit(cache=True)
def shape_bbox(xs, ys):
    return xs.min(), ys.min(), xs.max(), ys.max()


@njit(cache=True)
def _next_in_ring(v, a, b):
    """The vertex after v in the contour of vertices a..b-1."""
    return a if v + 1 == b else v + 1


@njit(cache=True)
def proper_crossing(p0x, p0y, p1x, p1y, q0x, q0y, q1x, q1y, eps):
    """(True, x, y) where two segments cross strictly inside both (each end farther than
    eps from the other line); else (False, 0, 0)."""
    dpx = p1x - p0x
    dpy = p1y - p0y
    dqx = q1x - q0x
    dqy = q1y - q0y
    d0 = dpx * (q0y - p0y) - dpy * (q0x - p0x)
    d1 = dpx * (q1y - p0y) - dpy * (q1x - p0x)
    if (d0 >= 0.0 and d1 >= 0.0) or (d0 <= 0.0 and d1 <= 0.0):  # fails below too: skip hypot
        return False, 0.0, 0.0
    e0 = dqx * (p0y - q0y) - dqy * (p0x - q0x)
    e1 = dqx * (p1y - q0y) - dqy * (p1x - q0x)
    if (e0 >= 0.0 and e1 >= 0.0) or (e0 <= 0.0 and e1 <= 0.0):
        return False, 0.0, 0.0
    lp = math.hypot(dpx, dpy)
    lq = math.hypot(dqx, dqy)
    if not ((d0 > eps * lp and d1 < -eps * lp) or (d0 < -eps * lp and d1 > eps * lp)):
        return False, 0.0, 0.0
    if not ((e0 > eps * lq and e1 < -eps * lq) or (e0 < -eps * lq and e1 > eps * lq)):
        return False, 0.0, 0.0
    tp = e0 / (e0 - e1)
    tq = d0 / (d0 - d1)
    # compute the point from the shorter parametrisation's nearer end (less rounding)
    if min(tp, 1 - tp) * lp <= min(tq, 1 - tq) * lq:
        if tp <= 0.5:
            return True, p0x + tp * dpx, p0y + tp * dpy
        return True, p1x - (1 - tp) * dpx, p1y - (1 - tp) * dpy
    if tq <= 0.5:
        return True, q0x + tq * dqx, q0y + tq * dqy
    return True, q1x - (1 - tq) * dqx, q1y - (1 - tq) * dqy


@njit(cache=True)
def on_segment(qx, qy, p0x, p0y, p1x, p1y, eps):
    """Parameter t in (0, 1) of q on segment p0-p1 when q lies on it strictly between the
    ends (distance <= eps from the line, > eps from both ends); else -1."""
    dx = p1x - p0x
    dy = p1y - p0y
    ll = dx * dx + dy * dy
    if ll == 0.0:
        return -1.0
    rx = qx - p0x
    ry = qy - p0y
    cr = dx * ry - dy * rx
    if cr * cr > eps * eps * ll:
        return -1.0
    t = (dx * rx + dy * ry) / ll
    tol = eps / math.sqrt(ll)
    if t <= tol or t >= 1.0 - tol:
        return -1.0
    return t


@njit(cache=True)
def first_crossing(xs, ys, starts, eps):
    """The first pair of edges (global vertex indices of their starts) of one shape that
    cross properly, each strictly inside the other; (-1, -1) when none do. Touching
    (a hole at a vertex of its main contour, shared collinear stretches) is allowed: the
    clipper's own output does that."""
    n = len(xs)
    # edges sorted by their left end: only edges whose x ranges overlap are compared
    e0 = np.empty(n, np.int64)
    e1 = np.empty(n, np.int64)
    lo = np.empty(n)
    for r in range(len(starts) - 1):
        a = starts[r]
        b = starts[r + 1]
        for v in range(a, b):
            w = _next_in_ring(v, a, b)
            e0[v] = v
            e1[v] = w
            lo[v] = min(xs[v], xs[w])
    order = np.argsort(lo, kind="mergesort")
    for i in range(n):
        u = order[i]
        a0 = e0[u]
        a1 = e1[u]
        hi = max(xs[a0], xs[a1])
        for j in range(i + 1, n):
            w = order[j]
            if lo[w] > hi + eps:
                break
            b0 = e0[w]
            b1 = e1[w]
            if max(ys[b0], ys[b1]) < min(ys[a0], ys[a1]) - eps or min(ys[b0], ys[b1]) > max(ys[a0], ys[a1]) + eps:
                continue
            hit, _, _ = proper_crossing(xs[a0], ys[a0], xs[a1], ys[a1], xs[b0], ys[b0], xs[b1], ys[b1], eps)
            if hit:
                return min(u, w), max(u, w)
    return -1, -1


# -- small growable buffers and sorts ------------------------------------------------------


@njit(cache=True)
def grown(a, need):
    """The 1-D array itself if it holds ``need`` items, else a copy at least twice as long."""
    if need <= len(a):
        return a
    b = np.empty(max(2 * len(a) + 8, need), a.dtype)
    b[: len(a)] = a
    return b


@njit(cache=True)
def grouped(keys, n):
    """Item indices grouped by key (0 <= key < n), each group in input order (a counting
    sort): (group starts, n + 1 entries; the indices)."""
    starts = np.zeros(n + 1, np.int64)
    for k in keys:
        starts[k + 1] += 1
    for i in range(n):
        starts[i + 1] += starts[i]
    fill = starts[:n].copy()
    order = np.empty(len(keys), np.int64)
    for e in range(len(keys)):
        order[fill[keys[e]]] = e
        fill[keys[e]] += 1
    return starts, order


@njit(cache=True)
def _lex_order(px, py, n):
    """Permutation sorting the first n points by x, then y."""
    if n <= SMALL_SORT:
        o = np.arange(n)
        for i in range(1, n):
            k = o[i]
            j = i - 1
            while j >= 0 and (px[o[j]] > px[k] or (px[o[j]] == px[k] and py[o[j]] > py[k])):
                o[j + 1] = o[j]
                j -= 1
            o[j + 1] = k
        return o
    o = np.argsort(py[:n], kind="mergesort")
    o2 = np.argsort(px[:n][o], kind="mergesort")
    return o[o2]


@njit(cache=True)
def _lower_bound(a, v):
    """First index i with a[i] >= v in a sorted array (np.searchsorted allocates on
    numba's scalar path, which cost more than the rest of a small clip)."""
    lo = 0
    hi = len(a)
    while lo < hi:
        mid = (lo + hi) >> 1
        if a[mid] < v:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True)
def _upper_bound(a, v):
    """First index i with a[i] > v in a sorted array."""
    lo = 0
    hi = len(a)
    while lo < hi:
        mid = (lo + hi) >> 1
        if a[mid] <= v:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True)
def _contains(sorted_keys, key):
    i = _lower_bound(sorted_keys, key)
    return i < len(sorted_keys) and sorted_keys[i] == key


# -- step 1: snapping, crossings, point ids ------------------------------------------------


@njit(cache=True)
def _snap(sx, sy, cx, cy, eps):
    """Clip vertices with each one that coincides with a subject vertex replaced by it,
    so shared vertices are bitwise equal."""
    ox = cx.copy()
    oy = cy.copy()
    ns = len(sx)
    for j in range(len(cx)):
        qx = cx[j]
        qy = cy[j]
        exact = False
        for i in range(ns):
            if sx[i] == qx and sy[i] == qy:
                exact = True
                break
        if exact:
            continue
        for i in range(ns):
            if abs(sx[i] - qx) <= eps and abs(sy[i] - qy) <= eps:
                ox[j] = sx[i]
                oy[j] = sy[i]
                break
    return ox, oy


@njit(cache=True)
def _points(sx, sy, ss, cx, cy, cs, eps):
    """Every vertex of both shapes and every proper crossing of a subject edge with a
    clip edge (computed once, shared by both), as (all_x, all_y, count)."""
    ns = len(sx)
    nc = len(cx)
    cap = ns + nc + 8
    px = np.empty(cap)
    py = np.empty(cap)
    px[:ns] = sx
    py[:ns] = sy
    px[ns : ns + nc] = cx
    py[ns : ns + nc] = cy
    n = ns + nc
    for r in range(len(ss) - 1):
        a = ss[r]
        b = ss[r + 1]
        for v in range(a, b):
            w = _next_in_ring(v, a, b)
            p0x = sx[v]
            p0y = sy[v]
            p1x = sx[w]
            p1y = sy[w]
            sx0 = min(p0x, p1x)
            sx1 = max(p0x, p1x)
            sy0 = min(p0y, p1y)
            sy1 = max(p0y, p1y)
            for rc in range(len(cs) - 1):
                ca = cs[rc]
                cb = cs[rc + 1]
                for u in range(ca, cb):
                    z = _next_in_ring(u, ca, cb)
                    q0x = cx[u]
                    q0y = cy[u]
                    q1x = cx[z]
                    q1y = cy[z]
                    if min(q0x, q1x) > sx1 + eps or max(q0x, q1x) < sx0 - eps:
                        continue
                    if min(q0y, q1y) > sy1 + eps or max(q0y, q1y) < sy0 - eps:
                        continue
                    hit, x, y = proper_crossing(p0x, p0y, p1x, p1y, q0x, q0y, q1x, q1y, eps)
                    if hit:
                        px = grown(px, n + 1)
                        py = grown(py, n + 1)
                        px[n] = x
                        py[n] = y
                        n += 1
    return px, py, n


@njit(cache=True)
def _point_ids(px, py, n):
    """Distinct points sorted by (x, y) and the id of each of the n input points."""
    o = _lex_order(px, py, n)
    ux = np.empty(n)
    uy = np.empty(n)
    ids = np.empty(n, np.int64)
    u = -1
    for i in range(n):
        k = o[i]
        if u < 0 or px[k] != ux[u] or py[k] != uy[u]:
            u += 1
            ux[u] = px[k]
            uy[u] = py[k]
        ids[k] = u
    return ux[: u + 1], uy[: u + 1], ids


# -- steps 1 (cont.) and 3: splitting the contours at every point on them ------------------


@njit(cache=True)
def _split(vid, labels, starts, ux, uy, eps):
    """The contours (as point ids) with every point lying strictly inside an edge inserted
    into it, ordered along the edge; (ids, labels, starts, number of points inserted)."""
    nu = len(ux)
    nv = len(vid)
    cap = nv + 8
    out = np.empty(cap, np.int64)
    lab = np.empty(cap, np.int64)
    ost = np.empty(len(starts), np.int64)
    ts = np.empty(8)
    qs = np.empty(8, np.int64)
    m = 0
    inserted = 0
    for r in range(len(starts) - 1):
        a = starts[r]
        b = starts[r + 1]
        ost[r] = m
        first = m
        for v in range(a, b):
            i0 = vid[v]
            i1 = vid[_next_in_ring(v, a, b)]
            p0x = ux[i0]
            p0y = uy[i0]
            p1x = ux[i1]
            p1y = uy[i1]
            x0 = min(p0x, p1x)
            x1 = max(p0x, p1x)
            y0 = min(p0y, p1y)
            y1 = max(p0y, p1y)
            lo = _lower_bound(ux, x0 - eps)
            hi = _upper_bound(ux, x1 + eps)
            k = 0
            for j in range(lo, min(hi, nu)):
                if uy[j] < y0 - eps or uy[j] > y1 + eps or j == i0 or j == i1:
                    continue
                t = on_segment(ux[j], uy[j], p0x, p0y, p1x, p1y, eps)
                if t < 0.0:
                    continue
                if k == len(ts):  # (checked here: a call per item costs reference counting)
                    ts = grown(ts, k + 1)
                    qs = grown(qs, k + 1)
                # insertion by (t, id): ordered along the edge
                z = k
                while z > 0 and (ts[z - 1] > t or (ts[z - 1] == t and qs[z - 1] > j)):
                    ts[z] = ts[z - 1]
                    qs[z] = qs[z - 1]
                    z -= 1
                ts[z] = t
                qs[z] = j
                k += 1
            inserted += k
            if m + 1 + k > len(out):
                out = grown(out, m + 1 + k)
                lab = grown(lab, m + 1 + k)
            out[m] = i0
            lab[m] = labels[v]
            m += 1
            for z in range(k):
                if qs[z] != out[m - 1]:
                    out[m] = qs[z]
                    lab[m] = labels[v]
                    m += 1
        # drop a closing duplicate (a split point equal to the first vertex)
        while m - first > 1 and out[m - 1] == out[first]:
            m -= 1
    ost[len(starts) - 1] = m
    return out[:m], lab[:m], ost, inserted


# -- step 3-4: tracing the inside and outside contours -------------------------------------


@njit(cache=True)
def _trace(edges, ux, uy, eps):
    """Link directed edges (rows from, to, label) into closed contours, turning at shared
    vertices onto the first edge clockwise from the way the walk came (keeps contours free
    of crossings); drop the zero-area leftovers of degenerate contact. Returns a shape
    (xs, ys, labels, starts)."""
    ea = edges[0]
    eb = edges[1]
    m = edges.shape[1]
    nu = len(ux)
    # outgoing edges of each point, in edge order
    head, out_edges = grouped(ea, nu)
    used = np.zeros(m, np.bool_)
    xs = np.empty(m)
    ys = np.empty(m)
    labels = np.empty(m, np.int64)
    starts = np.empty(m + 1, np.int64)
    nr = 0
    n = 0
    for e0 in range(m):
        if used[e0]:
            continue
        first = n
        e = e0
        while True:
            used[e] = True
            xs[n] = ux[ea[e]]
            ys[n] = uy[ea[e]]
            labels[n] = edges[2, e]
            n += 1
            v = eb[e]
            best = -1
            count = 0
            best_turn = 0.0
            back = 0.0
            for k in range(head[v], head[v + 1]):
                f = out_edges[k]
                if used[f]:
                    continue
                count += 1
                if count == 1:
                    best = f
                    continue
                if count == 2:
                    back = math.atan2(uy[ea[e]] - uy[v], ux[ea[e]] - ux[v])
                    best_turn = _turn(back, best, eb, ux, uy, v)
                turn = _turn(back, f, eb, ux, uy, v)
                if turn < best_turn:
                    best_turn = turn
                    best = f
            if best < 0:
                break
            e = best
        if n - first >= 3 and abs(ring_area_of(xs, ys, first, n)) > eps * eps:
            starts[nr] = first
            nr += 1
        else:
            n = first  # too short or zero area: dropped
    starts[nr] = n
    return xs[:n], ys[:n], labels[:n], starts[: nr + 1]


@njit(cache=True)
def _turn(back, f, eb, ux, uy, v):
    t = (back - math.atan2(uy[eb[f]] - uy[v], ux[eb[f]] - ux[v])) % TWO_PI
    return TWO_PI if t == 0.0 else t


# -- step 2: no boundaries meet ------------------------------------------------------------


@njit(cache=True)
def _append_ring(xs, ys, labels, a, b, reverse, ox, oy, ol, n):
    """Copy contour a..b-1 to the output at n (reversed: walked backwards, each edge
    keeping its label)."""
    k = b - a
    for i in range(k):
        if reverse:
            src = b - 1 - i
            ox[n + i] = xs[src]
            oy[n + i] = ys[src]
            # reversed edge i runs from vertex b-1-i to b-2-i: the original edge b-2-i
            ol[n + i] = labels[b - 2 - i] if i < k - 1 else labels[b - 1]
        else:
            ox[n + i] = xs[a + i]
            oy[n + i] = ys[a + i]
            ol[n + i] = labels[a + i]
    return n + k


@njit(cache=True)
def _holding_lists(sx, sy, sl, ss, cx, cy, cl, cs):
    """The paper's step 2 when no boundaries meet: whole contours to the holding lists;
    clip contours inside the subject go to both, reversed for the outside (a hole)."""
    ns_r = len(ss) - 1
    nc_r = len(cs) - 1
    s_in = np.empty(ns_r, np.bool_)
    c_in = np.empty(nc_r, np.bool_)
    n_in = 0
    r_in = 0
    for r in range(ns_r):
        a = ss[r]
        s_in[r] = winding(0.5 * (sx[a] + sx[a + 1]), 0.5 * (sy[a] + sy[a + 1]), cx, cy, cs) > 0
        if s_in[r]:
            n_in += ss[r + 1] - a
            r_in += 1
    n_c = 0
    r_c = 0
    for r in range(nc_r):
        a = cs[r]
        c_in[r] = winding(0.5 * (cx[a] + cx[a + 1]), 0.5 * (cy[a] + cy[a + 1]), sx, sy, ss) > 0
        if c_in[r]:
            n_c += cs[r + 1] - a
            r_c += 1
    n_out = len(sx) - n_in + n_c
    ix = np.empty(n_in + n_c)
    iy = np.empty(n_in + n_c)
    il = np.empty(n_in + n_c, np.int64)
    ist = np.empty(r_in + r_c + 1, np.int64)
    ox = np.empty(n_out)
    oy = np.empty(n_out)
    ol = np.empty(n_out, np.int64)
    ost = np.empty(ns_r - r_in + r_c + 1, np.int64)
    ni = 0
    no = 0
    ri = 0
    ro = 0
    for r in range(ns_r):
        if s_in[r]:
            ist[ri] = ni
            ri += 1
            ni = _append_ring(sx, sy, sl, ss[r], ss[r + 1], False, ix, iy, il, ni)
        else:
            ost[ro] = no
            ro += 1
            no = _append_ring(sx, sy, sl, ss[r], ss[r + 1], False, ox, oy, ol, no)
    for r in range(nc_r):
        if c_in[r]:
            ist[ri] = ni
            ri += 1
            ni = _append_ring(cx, cy, cl, cs[r], cs[r + 1], False, ix, iy, il, ni)
            ost[ro] = no
            ro += 1
            no = _append_ring(cx, cy, cl, cs[r], cs[r + 1], True, ox, oy, ol, no)
    ist[ri] = ni
    ost[ro] = no
    return ix, iy, il, ist, ox, oy, ol, ost


# -- the clipper ---------------------------------------------------------------------------


@njit(cache=True)
def _empty_shape():
    return np.empty(0), np.empty(0), np.empty(0, np.int64), np.zeros(1, np.int64)


@njit(cache=True)
def _edge_keys(ids, starts, nu):
    """Sorted keys ``from * nu + to`` of the contours' edges of positive length."""
    keys = np.empty(len(ids), np.int64)
    m = 0
    for r in range(len(starts) - 1):
        a = starts[r]
        b = starts[r + 1]
        for v in range(a, b):
            w = ids[_next_in_ring(v, a, b)]
            if ids[v] != w:
                keys[m] = ids[v] * nu + w
                m += 1
    keys = keys[:m]
    if m <= SMALL_SORT:
        for i in range(1, m):  # insertion sort: numpy's sort costs more on a few keys
            k = keys[i]
            j = i - 1
            while j >= 0 and keys[j] > k:
                keys[j + 1] = keys[j]
                j -= 1
            keys[j + 1] = k
    else:
        keys.sort()
    return keys


@njit(cache=True)
def _winding_ids(px, py, ids, starts, ux, uy):
    """:func:`winding` about contours given as point ids."""
    w = 0
    for r in range(len(starts) - 1):
        a = starts[r]
        b = starts[r + 1]
        for i in range(a, b):
            j = ids[b - 1] if i == a else ids[i - 1]
            w += _winds(px, py, ux[j], uy[j], ux[ids[i]], uy[ids[i]])
    return w


@njit(cache=True)
def _classify(s_ids, s_lab, s_st, c_ids, c_lab, c_st, ux, uy):
    """The directed edges (from, to, label) of the inside and outside contours, as rows of
    two (3, m) arrays: subject edges by where they lie (shared edges by the side the clip
    shape's interior is on), clip edges inside the subject to both, walked backwards for
    the outside."""
    nu = len(ux)
    s_keys = _edge_keys(s_ids, s_st, nu)
    c_keys = _edge_keys(c_ids, c_st, nu)
    cap = len(s_ids) + len(c_ids)
    ins = np.empty((3, cap), np.int64)
    outs = np.empty((3, cap), np.int64)
    ni = 0
    no = 0
    for r in range(len(s_st) - 1):
        ra = s_st[r]
        rb = s_st[r + 1]
        for v in range(ra, rb):
            a = s_ids[v]
            b = s_ids[_next_in_ring(v, ra, rb)]
            if a == b:
                continue
            if _contains(c_keys, a * nu + b):
                inside = True  # shared, same side: interior of both on the same side
            elif _contains(c_keys, b * nu + a):
                inside = False  # shared, opposite sides: boundary of the outside part
            else:
                inside = _winding_ids(0.5 * (ux[a] + ux[b]), 0.5 * (uy[a] + uy[b]), c_ids, c_st, ux, uy) > 0
            if inside:
                ins[0, ni] = a
                ins[1, ni] = b
                ins[2, ni] = s_lab[v]
                ni += 1
            else:
                outs[0, no] = a
                outs[1, no] = b
                outs[2, no] = s_lab[v]
                no += 1
    for r in range(len(c_st) - 1):
        ra = c_st[r]
        rb = c_st[r + 1]
        for v in range(ra, rb):
            a = c_ids[v]
            b = c_ids[_next_in_ring(v, ra, rb)]
            if a == b or _contains(s_keys, a * nu + b) or _contains(s_keys, b * nu + a):
                continue
            if _winding_ids(0.5 * (ux[a] + ux[b]), 0.5 * (uy[a] + uy[b]), s_ids, s_st, ux, uy) > 0:
                ins[0, ni] = a
                ins[1, ni] = b
                ins[2, ni] = c_lab[v]
                ni += 1
                outs[0, no] = b  # walked backwards: it bounds the outside part
                outs[1, no] = a
                outs[2, no] = c_lab[v]
                no += 1
    return ins[:, :ni], outs[:, :no]


@njit(cache=True)
def _shares_a_point(s_ids, c_ids, nu):
    mark = np.zeros(nu, np.bool_)
    for i in s_ids:
        mark[i] = True
    for i in c_ids:
        if mark[i]:
            return True
    return False


@njit(cache=True)
def clip_arrays(sx, sy, sl, ss, cx, cy, cl, cs, eps):
    """Clip the subject shape by the clip shape: (inside shape, outside shape), eight
    arrays; see :func:`aaeval.weiler_atherton.clipper.clip`. No validation here."""
    if len(ss) < 2 or len(sx) == 0:
        e = _empty_shape()
        return e[0], e[1], e[2], e[3], e[0], e[1], e[2], e[3]
    if len(cs) < 2 or len(cx) == 0:
        e = _empty_shape()
        return e[0], e[1], e[2], e[3], sx, sy, sl, ss
    s0, s1, s2, s3 = shape_bbox(sx, sy)
    c0, c1, c2, c3 = shape_bbox(cx, cy)
    if c0 >= s2 - eps or c2 <= s0 + eps or c1 >= s3 - eps or c3 <= s1 + eps:
        e = _empty_shape()
        return e[0], e[1], e[2], e[3], sx, sy, sl, ss
    cx, cy = _snap(sx, sy, cx, cy, eps)
    px, py, n = _points(sx, sy, ss, cx, cy, cs, eps)
    ux, uy, ids = _point_ids(px, py, n)
    ns = len(sx)
    s_ids = ids[:ns]
    c_ids = ids[ns : ns + len(cx)]
    s_ids2, s_lab2, s_st2, s_ins = _split(s_ids, sl, ss, ux, uy, eps)
    c_ids2, c_lab2, c_st2, c_ins = _split(c_ids, cl, cs, ux, uy, eps)
    if s_ins == 0 and c_ins == 0 and not _shares_a_point(s_ids, c_ids, len(ux)):
        return _holding_lists(sx, sy, sl, ss, cx, cy, cl, cs)
    ins, outs = _classify(s_ids2, s_lab2, s_st2, c_ids2, c_lab2, c_st2, ux, uy)
    ix, iy, ilab, ist = _trace(ins, ux, uy, eps)
    ox, oy, olab, ost = _trace(outs, ux, uy, eps)
    return ix, iy, ilab, ist, ox, oy, olab, ost
