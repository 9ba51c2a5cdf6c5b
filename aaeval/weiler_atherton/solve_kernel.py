"""Compiled hidden-surface loop of Weiler & Atherton (numba); :mod:`.hidden_surface` is
the API and describes the steps.

Pieces live in an arena (parallel typed lists: contours as the clipper's four arrays,
source polygon, bounding box) and are referred to by index. The paper's recursion
(solve the inside list again with an offending polygon as the clip polygon) becomes a
stack of tasks, each a list of piece indices and the stack of clip polygons still being
processed; a task's pieces are solved independently of every other task, and taking the
newest task first visits them in the order the recursion would.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, types
from numba.typed import List

from aaeval.weiler_atherton.clip_kernel import clip_arrays, grown, ring_area_of, shape_bbox

EDGE_CUT = 0
EDGE_OWN = 1
EDGE_CROSSING = 2

FRONT = -1
BEHIND = 1

OUTSIDE = 1
INSIDE = 2

_FLOATS = types.float64[::1]
_INTS = types.int64[::1]
_META = types.int64[:, ::1]
_BOXES = types.float64[:, ::1]


@njit(cache=True)
def _new_arena():
    """Empty piece storage: append-only pools of vertices (x, y, edge label), contour
    starts (relative to the piece's first vertex) and per piece its vertex range, contour
    range, source and box. (Typed lists of small arrays cost ~1 us a piece to fill.) Each
    pool is held in a one-item list so it can be replaced by a larger copy."""
    floats = List.empty_list(_FLOATS)
    floats.append(np.empty(1024))  # x
    floats.append(np.empty(1024))  # y
    ints = List.empty_list(_INTS)
    ints.append(np.empty(1024, np.int64))  # labels
    ints.append(np.empty(256, np.int64))  # contour starts
    meta = List.empty_list(_META)
    meta.append(np.empty((128, 5), np.int64))  # first vertex, end, first start, end, source
    boxes = List.empty_list(_BOXES)
    boxes.append(np.empty((128, 4)))
    counts = np.zeros(3, np.int64)  # pieces, vertices, contour starts
    return floats, ints, meta, boxes, counts


@njit(cache=True)
def _grown_rows(a, need):
    if need <= a.shape[0]:
        return a
    b = np.empty((max(2 * a.shape[0], need), a.shape[1]), a.dtype)
    b[: a.shape[0]] = a
    return b


@njit(cache=True)
def _add_piece(arena, xs, ys, labels, starts, source):
    """Store a piece; its index."""
    floats, ints, meta, boxes, counts = arena
    k = counts[0]
    v0 = counts[1]
    r0 = counts[2]
    n = len(xs)
    nr = len(starts)
    floats[0] = grown(floats[0], v0 + n)
    floats[1] = grown(floats[1], v0 + n)
    ints[0] = grown(ints[0], v0 + n)
    ints[1] = grown(ints[1], r0 + nr)
    meta[0] = _grown_rows(meta[0], k + 1)
    boxes[0] = _grown_rows(boxes[0], k + 1)
    floats[0][v0 : v0 + n] = xs
    floats[1][v0 : v0 + n] = ys
    ints[0][v0 : v0 + n] = labels
    ints[1][r0 : r0 + nr] = starts
    m = meta[0]
    m[k, 0] = v0
    m[k, 1] = v0 + n
    m[k, 2] = r0
    m[k, 3] = r0 + nr
    m[k, 4] = source
    x0, y0, x1, y1 = shape_bbox(xs, ys)
    b = boxes[0]
    b[k, 0] = x0
    b[k, 1] = y0
    b[k, 2] = x1
    b[k, 3] = y1
    counts[0] = k + 1
    counts[1] = v0 + n
    counts[2] = r0 + nr
    return k


@njit(cache=True)
def _piece(arena, k):
    """(xs, ys, labels, starts) of piece k (views into the pools)."""
    floats, ints, meta, _, _ = arena
    m = meta[0]
    v0 = m[k, 0]
    v1 = m[k, 1]
    return floats[0][v0:v1], floats[1][v0:v1], ints[0][v0:v1], ints[1][m[k, 2] : m[k, 3]]


@njit(cache=True)
def _disjoint(boxes, k, b):
    return boxes[k, 0] >= b[2] or boxes[k, 2] <= b[0] or boxes[k, 1] >= b[3] or boxes[k, 3] <= b[1]


@njit(cache=True)
def _within(bb, win):
    return bb[0] >= win[0] and bb[2] <= win[2] and bb[1] >= win[1] and bb[3] <= win[3]


# -- step b: the x-y sort ------------------------------------------------------------------


@njit(cache=True)
def _is_convex(xs, ys):
    """Whether the contour (positive area) turns left or goes straight at every vertex."""
    n = len(xs)
    for i in range(n):
        j = (i + 1) % n
        k = (i + 2) % n
        if (xs[j] - xs[i]) * (ys[k] - ys[j]) - (ys[j] - ys[i]) * (xs[k] - xs[j]) < 0:
            return False
    return True


@njit(cache=True)
def _separation(sx, sy, cx, cy, eps):
    """For a convex clip contour: OUTSIDE when every subject vertex lies farther than
    2 eps beyond one clip edge's line, INSIDE when every one lies farther than 2 eps
    inside every edge's line, else 0. In both decided cases the clipper would find no
    contact at all (no vertex within eps of the other shape) and hand the subject whole
    to one side, so the answer is the same without clipping."""
    n = len(cx)
    inside = True
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        ex = cx[j] - cx[i]
        ey = cy[j] - cy[i]
        margin = 2.0 * eps * math.hypot(ex, ey)
        beyond = True
        for v in range(len(sx)):
            d = ex * (sy[v] - cy[i]) - ey * (sx[v] - cx[i])  # > 0: left, the inner side
            if d >= -margin:
                beyond = False
            if d <= margin:
                inside = False
            if not beyond and not inside:
                break
        if beyond:
            return OUTSIDE
    return INSIDE if inside else 0


@njit(cache=True)
def _clip_list(arena, ids, src, ox, oy, ol, os_, obb, eps):
    """The task's pieces split by polygon src's original outline: (inside, outside)."""
    psrc = arena[2][0][:, 4]  # new pieces are added past the ids read here: these stay valid
    pbb = arena[3][0]
    inside = np.empty(len(ids), np.int64)
    outside = np.empty(len(ids), np.int64)
    ni = 0
    no = 0
    cb = obb[src]
    box = (cb[0], cb[1], cb[2], cb[3])
    convex = _is_convex(ox, oy)
    for pid in ids:
        if psrc[pid] == src:  # a piece always lies in its own polygon's outline
            inside[ni] = pid
            ni += 1
            continue
        if _disjoint(pbb, pid, box):
            outside[no] = pid
            no += 1
            continue
        sx, sy, sl, ss = _piece(arena, pid)
        if convex:
            side = _separation(sx, sy, ox, oy, eps)
            if side == OUTSIDE:
                outside[no] = pid
                no += 1
                continue
            if side == INSIDE:
                inside[ni] = pid
                ni += 1
                continue
        ix, iy, il, ist, qx, qy, ql, qst = clip_arrays(sx, sy, sl, ss, ox, oy, ol, os_, eps)
        if len(ist) > 1:
            inside[ni] = _add_piece(arena, ix, iy, il, ist, psrc[pid])
            ni += 1
        if len(qst) > 1:
            outside[no] = _add_piece(arena, qx, qy, ql, qst, psrc[pid])
            no += 1
    return inside[:ni].copy(), outside[:no].copy()


# -- step c: depth comparison --------------------------------------------------------------


@njit(cache=True)
def _relation(xs, ys, source, src, planes, eps_z):
    """FRONT, BEHIND or 0 (planes cross inside the piece) relative to polygon src."""
    da = planes[source, 0] - planes[src, 0]
    db = planes[source, 1] - planes[src, 1]
    dc = planes[source, 2] - planes[src, 2]
    front = False
    behind = False
    for i in range(len(xs)):
        d = da * xs[i] + db * ys[i] + dc
        if d < -eps_z:
            front = True
        elif d > eps_z:
            behind = True
    if front and behind:
        return 0
    if front:
        return FRONT
    if behind:
        return BEHIND
    return FRONT if source > src else BEHIND  # one plane: later in file in front


@njit(cache=True)
def half_plane(a, b, c, bbox):
    """The part ``a x + b y + c <= 0`` of the bounding box (grown by one unit), as a
    convex shape whose edge along the line is labelled EDGE_CROSSING."""
    x0 = bbox[0] - 1
    y0 = bbox[1] - 1
    x1 = bbox[2] + 1
    y1 = bbox[3] + 1
    bx = np.array([x0, x1, x1, x0])
    by = np.array([y0, y0, y1, y1])  # positive shoelace area already
    xs = np.empty(8)
    ys = np.empty(8)
    on_line = np.zeros(8, np.bool_)
    n = 0
    for k in range(4):
        j = (k + 1) % 4
        dp = a * bx[k] + b * by[k] + c
        dq = a * bx[j] + b * by[j] + c
        if dp <= 0:
            xs[n] = bx[k]
            ys[n] = by[k]
            on_line[n] = dp == 0
            n += 1
        if (dp < 0 < dq) or (dq < 0 < dp):
            t = dp / (dp - dq)
            xs[n] = bx[k] + t * (bx[j] - bx[k])
            ys[n] = by[k] + t * (by[j] - by[k])
            on_line[n] = True
            n += 1
    labels = np.empty(n, np.int64)
    for k in range(n):
        labels[k] = EDGE_CROSSING if on_line[k] and on_line[(k + 1) % n] else EDGE_CUT
    starts = np.array([0, n], np.int64)
    return xs[:n].copy(), ys[:n].copy(), labels, starts


@njit(cache=True)
def _on_stack(stack, source):
    for s in stack:
        if s == source:
            return True
    return False


@njit(cache=True)
def _resolve_inside(arena, src, inside, planes, eps, eps_z):
    """Step c: inside pieces behind polygon src dropped, those crossing its plane split
    along the crossing line. Returns (kept pieces, pieces of other polygons in front)."""
    psrc = arena[2][0][:, 4]
    pbb = arena[3][0]
    kept = np.empty(2 * len(inside), np.int64)
    offenders = np.empty(2 * len(inside), np.int64)
    nk = 0
    nf = 0
    for pid in inside:
        source = psrc[pid]
        if source == src:
            kept[nk] = pid
            nk += 1
            continue
        sx, sy, sl, ss = _piece(arena, pid)
        rel = _relation(sx, sy, source, src, planes, eps_z)
        if rel == FRONT:
            kept[nk] = pid
            offenders[nf] = pid
            nk += 1
            nf += 1
        elif rel == 0:
            hx, hy, hl, hs = half_plane(
                planes[source, 0] - planes[src, 0],
                planes[source, 1] - planes[src, 1],
                planes[source, 2] - planes[src, 2],
                (pbb[pid, 0], pbb[pid, 1], pbb[pid, 2], pbb[pid, 3]),
            )
            fx, fy, fl, fs, _, _, _, _ = clip_arrays(sx, sy, sl, ss, hx, hy, hl, hs, eps)
            if len(fs) > 1:
                f = _add_piece(arena, fx, fy, fl, fs, source)
                kept[nk] = f
                offenders[nf] = f
                nk += 1
                nf += 1
    return kept[:nk].copy(), offenders[:nf].copy()


# -- steps b-d over a stack of tasks -------------------------------------------------------


@njit(cache=True)
def _solve(arena, first_task, ox, oy, ol, ost, obb, planes, eps, eps_z):
    """Indices of the visible pieces (they do not overlap)."""
    visible = List()
    visible.append(0)
    visible.pop()
    task_ids = List()
    task_stack = List()
    task_ids.append(first_task)
    task_stack.append(np.empty(0, np.int64))
    while len(task_ids) > 0:
        ids = task_ids.pop()
        stack = task_stack.pop()
        if len(ids) == 0:
            continue
        src = arena[2][0][ids[0], 4]
        a = ost[src]
        b = ost[src + 1]
        cx = ox[a:b].copy()
        cy = oy[a:b].copy()
        cl = ol[a:b].copy()
        inside, outside = _clip_list(arena, ids, src, cx, cy, cl, np.array([0, b - a]), obb, eps)
        # the rest of this list after the inside list (pushed first: taken last)
        task_ids.append(outside)
        task_stack.append(stack)
        kept, offenders = _resolve_inside(arena, src, inside, planes, eps, eps_z)
        first = -1
        psrc = arena[2][0][:, 4]
        for pid in offenders:
            if not _on_stack(stack, psrc[pid]):
                first = pid
                break
        if first < 0:
            # no offender, or only polygons on the stack (cyclic overlap): all that lay
            # behind them is gone already, so what is left does not overlap
            for pid in kept:
                visible.append(pid)
            continue
        again = np.empty(len(kept), np.int64)
        again[0] = first
        k = 1
        for pid in kept:
            if pid != first:
                again[k] = pid
                k += 1
        deeper = np.empty(len(stack) + 1, np.int64)
        deeper[: len(stack)] = stack
        deeper[len(stack)] = src
        task_ids.append(again[:k].copy())
        task_stack.append(deeper)
    out = np.empty(len(visible), np.int64)
    for i in range(len(visible)):
        out[i] = visible[i]
    return out


@njit(cache=True)
def _window_pieces(arena, ox, oy, ost, obb, order, win, eps):
    """Each polygon (in depth order) clipped to the window, its edges labelled EDGE_OWN."""
    wx = np.array([win[0], win[2], win[2], win[0]])
    wy = np.array([win[1], win[1], win[3], win[3]])
    wl = np.full(4, EDGE_CUT, np.int64)
    ws = np.array([0, 4], np.int64)
    ids = np.empty(len(order), np.int64)
    k = 0
    for s in order:
        a = ost[s]
        b = ost[s + 1]
        xs = ox[a:b].copy()
        ys = oy[a:b].copy()
        labels = np.full(b - a, EDGE_OWN, np.int64)
        starts = np.array([0, b - a], np.int64)
        bb = obb[s]
        if not _within((bb[0], bb[1], bb[2], bb[3]), win):
            xs, ys, labels, starts, _, _, _, _ = clip_arrays(xs, ys, labels, starts, wx, wy, wl, ws, eps)
        if len(starts) > 1:
            ids[k] = _add_piece(arena, xs, ys, labels, starts, s)
            k += 1
    return ids[:k].copy()


@njit(cache=True)
def originals(vertices, start, length, planes):
    """Every polygon's outline as the solver takes it: consecutive repeats in (x, y)
    dropped, turned to positive shoelace area; polygons seen edge-on (NaN plane) get an
    empty outline. Returns (xs, ys, starts, boxes, nearest depth, largest |x|, |y| and
    largest |z| over the polygons kept)."""
    n = len(start)
    xs = np.empty(len(vertices))
    ys = np.empty(len(vertices))
    ost = np.zeros(n + 1, np.int64)
    boxes = np.zeros((n, 4))
    zmin = np.zeros(n)
    scale = 0.0
    zmax = 0.0
    m = 0
    for p in range(n):
        a = start[p]
        b = a + length[p]
        zmin[p] = vertices[a:b, 2].min()
        if not (np.isfinite(planes[p, 0]) and np.isfinite(planes[p, 1]) and np.isfinite(planes[p, 2])):
            ost[p + 1] = m
            continue
        first = m
        for i in range(a, b):
            j = b - 1 if i == a else i - 1
            if vertices[i, 0] != vertices[j, 0] or vertices[i, 1] != vertices[j, 1]:
                xs[m] = vertices[i, 0]
                ys[m] = vertices[i, 1]
                m += 1
        if m == first:  # all one point
            xs[m] = vertices[a, 0]
            ys[m] = vertices[a, 1]
            m += 1
        if ring_area_of(xs, ys, first, m) < 0:
            xs[first:m] = xs[first:m][::-1].copy()
            ys[first:m] = ys[first:m][::-1].copy()
        ost[p + 1] = m
        boxes[p, 0] = xs[first:m].min()
        boxes[p, 1] = ys[first:m].min()
        boxes[p, 2] = xs[first:m].max()
        boxes[p, 3] = ys[first:m].max()
        for i in range(a, b):
            scale = max(scale, abs(vertices[i, 0]), abs(vertices[i, 1]))
            zmax = max(zmax, abs(vertices[i, 2]))
    return xs[:m].copy(), ys[:m].copy(), ost, boxes, zmin, scale, zmax


@njit(cache=True)
def solve_window(ox, oy, ost, obb, planes, order, win, eps, eps_z):
    """Visible pieces of the polygons ``order`` (depth-sorted) inside window ``win``.

    ``ox, oy, ost``: every polygon's original outline (polygon p is vertices
    ``ost[p]:ost[p + 1]``, positive area); ``obb`` their boxes, ``planes`` their depth
    planes. Returns the pieces flattened: (xs, ys, labels, contour starts, first contour
    of each piece (one more entry than pieces), source of each piece)."""
    ol = np.full(len(ox), EDGE_CUT, np.int64)
    arena = _new_arena()
    first = _window_pieces(arena, ox, oy, ost, obb, order, win, eps)
    visible = _solve(arena, first, ox, oy, ol, ost, obb, planes, eps, eps_z)
    return _flatten(arena, visible)


@njit(cache=True)
def _flatten(arena, visible):
    meta = arena[2][0]
    nv = 0
    nr = 0
    for pid in visible:
        nv += meta[pid, 1] - meta[pid, 0]
        nr += meta[pid, 3] - meta[pid, 2] - 1
    xs = np.empty(nv)
    ys = np.empty(nv)
    labels = np.empty(nv, np.int64)
    starts = np.empty(nr + 1, np.int64)
    piece_rings = np.empty(len(visible) + 1, np.int64)
    sources = np.empty(len(visible), np.int64)
    v = 0
    r = 0
    for i in range(len(visible)):
        pid = visible[i]
        piece_rings[i] = r
        sources[i] = meta[pid, 4]
        px, py, pl, st = _piece(arena, pid)
        n = len(px)
        xs[v : v + n] = px
        ys[v : v + n] = py
        labels[v : v + n] = pl
        for j in range(len(st) - 1):
            starts[r] = v + st[j]
            r += 1
        v += n
    starts[r] = v
    piece_rings[len(visible)] = r
    return xs, ys, labels, starts, piece_rings, sources


__all__ = ["solve_window", "half_plane", "ring_area_of", "EDGE_CUT", "EDGE_OWN", "EDGE_CROSSING"]
