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

from aaeval.weiler_atherton.clip_kernel import clip_arrays, grown, grouped, ring_area_of, shape_bbox
from aaeval.weiler_atherton.convex_kernel import edge_line_values, plane_line_values, split_convex, vertex_sides

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
def _reserve(arena, n, nr, source):
    """Room for a piece of n vertices in nr contours, its ranges and source recorded:
    (its index, its first vertex, its first contour start). The caller fills them and
    the box (:func:`_set_box`)."""
    floats, ints, meta, boxes, counts = arena
    k = counts[0]
    v0 = counts[1]
    r0 = counts[2]
    floats[0] = grown(floats[0], v0 + n)
    floats[1] = grown(floats[1], v0 + n)
    ints[0] = grown(ints[0], v0 + n)
    ints[1] = grown(ints[1], r0 + nr)
    meta[0] = _grown_rows(meta[0], k + 1)
    boxes[0] = _grown_rows(boxes[0], k + 1)
    m = meta[0]
    m[k, 0] = v0
    m[k, 1] = v0 + n
    m[k, 2] = r0
    m[k, 3] = r0 + nr
    m[k, 4] = source
    counts[0] = k + 1
    counts[1] = v0 + n
    counts[2] = r0 + nr
    return k, v0, r0


@njit(cache=True)
def _set_box(arena, k, xs, ys):
    x0, y0, x1, y1 = shape_bbox(xs, ys)
    b = arena[3][0]
    b[k, 0] = x0
    b[k, 1] = y0
    b[k, 2] = x1
    b[k, 3] = y1


@njit(cache=True)
def _add_piece(arena, xs, ys, labels, starts, source):
    """Store a piece; its index."""
    n = len(xs)
    nr = len(starts)
    k, v0, r0 = _reserve(arena, n, nr, source)
    arena[0][0][v0 : v0 + n] = xs
    arena[0][1][v0 : v0 + n] = ys
    arena[1][0][v0 : v0 + n] = labels
    arena[1][1][r0 : r0 + nr] = starts
    _set_box(arena, k, xs, ys)
    return k


@njit(cache=True)
def _add_contour(arena, xs, ys, labels, n, source):
    """Store a piece of one contour, the first n vertices of xs, ys, labels; its index."""
    k, v0, r0 = _reserve(arena, n, 2, source)
    arena[0][0][v0 : v0 + n] = xs[:n]
    arena[0][1][v0 : v0 + n] = ys[:n]
    arena[1][0][v0 : v0 + n] = labels[:n]
    arena[1][1][r0] = 0
    arena[1][1][r0 + 1] = n
    _set_box(arena, k, xs[:n], ys[:n])
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


# -- the short road for convex pairs (see :mod:`.convex_kernel`) ------------------------

WORK_VERTICES = 64  # a convex piece and outline with more vertices together take the paper's road


@njit(cache=True)
def _workspace():
    """Scratch rows for cutting one convex piece: floats (current x, y; left part x, y;
    right part x, y; line values) and labels (current, left, right)."""
    return np.empty((7, WORK_VERTICES)), np.empty((3, WORK_VERTICES), np.int64)


@njit(cache=True)
def _takes_convex_road(sx, sy, ss, extra):
    """Whether a piece is one convex contour small enough for the scratch rows, with
    ``extra`` vertices (those of the outline) added by the cuts."""
    return len(ss) == 2 and len(sx) + extra + 2 <= WORK_VERTICES and _is_convex(sx, sy)


@njit(cache=True)
def _load(fw, iw, sx, sy, sl):
    n = len(sx)
    fw[0, :n] = sx
    fw[1, :n] = sy
    iw[0, :n] = sl
    return n


@njit(cache=True)
def _keep_left(fw, iw, nl):
    """The left part becomes the current contour."""
    fw[0, :nl] = fw[2, :nl]
    fw[1, :nl] = fw[3, :nl]
    iw[0, :nl] = iw[1, :nl]
    return nl


@njit(cache=True)
def _cut_by_outline(arena, pid, source, cx, cy, cl, eps, fw, iw, inside, ni, outside, no):
    """Piece pid (one convex contour) clipped by a convex outline, edge line by edge
    line: the part beyond each line goes to the outside list, what is left at the end
    to the inside list (a part of area eps**2 or less is dropped, as the clipper drops
    it). A piece no line cuts goes whole to its list. The caller leaves room for one
    inside and ``len(cx)`` outside entries. Returns the lists and counts."""
    sx, sy, sl, _ = _piece(arena, pid)
    n = _load(fw, iw, sx, sy, sl)
    tiny = eps * eps
    m = len(cx)
    cut = False
    for i in range(m):
        j = i + 1 if i + 1 < m else 0
        tol = eps * edge_line_values(fw[0], fw[1], n, cx[i], cy[i], cx[j], cy[j], fw[6])
        below, above = vertex_sides(fw[6], n, tol)
        if not above:
            continue
        if not below:  # the rest lies beyond this edge: all of it outside
            outside[no] = _add_contour(arena, fw[0], fw[1], iw[0], n, source) if cut else pid
            return inside, ni, outside, no + 1
        nl, nr = split_convex(fw[0], fw[1], iw[0], n, fw[6], tol, cl[i], fw[2], fw[3], iw[1], fw[4], fw[5], iw[2])
        if ring_area_of(fw[4], fw[5], 0, nr) > tiny:
            outside[no] = _add_contour(arena, fw[4], fw[5], iw[2], nr, source)
            no += 1
        n = _keep_left(fw, iw, nl)
        cut = True
    if not cut:
        inside[ni] = pid
        ni += 1
    elif ring_area_of(fw[0], fw[1], 0, n) > tiny:
        inside[ni] = _add_contour(arena, fw[0], fw[1], iw[0], n, source)
        ni += 1
    return inside, ni, outside, no


@njit(cache=True)
def _cut_by_plane_line(arena, pid, source, a, b, c, eps, fw, iw):
    """The part a x + b y + c <= 0 of piece pid (one convex contour), its edge along the
    line labelled EDGE_CROSSING, stored as a new piece: its index, or -1 when it has
    area eps**2 or less. Only for a piece the line crosses (its relation is 0)."""
    sx, sy, sl, _ = _piece(arena, pid)
    n = _load(fw, iw, sx, sy, sl)
    tol = eps * plane_line_values(fw[0], fw[1], n, a, b, c, fw[6])
    below, above = vertex_sides(fw[6], n, tol)
    if not below:
        return -1
    if not above:
        return pid
    nl, _ = split_convex(fw[0], fw[1], iw[0], n, fw[6], tol, EDGE_CROSSING, fw[2], fw[3], iw[1], fw[4], fw[5], iw[2])
    if ring_area_of(fw[2], fw[3], 0, nl) <= eps * eps:
        return -1
    return _add_contour(arena, fw[2], fw[3], iw[1], nl, source)


@njit(cache=True)
def _clip_piece(arena, pid, box, convex, ox, oy, ol, os_, eps, convex_road, fw, iw, inside, ni, outside, no):
    """Piece pid (its box meeting the outline's box ``box``) split by an outline, its parts
    appended to the inside and outside lists (grown as needed). Returns the lists and
    their counts."""
    if ni + 1 > len(inside):
        inside = grown(inside, ni + 1)
    if no + len(ox) + 1 > len(outside):
        outside = grown(outside, no + len(ox) + 1)
    source = arena[2][0][pid, 4]
    sx, sy, sl, ss = _piece(arena, pid)
    if convex:
        side = _separation(sx, sy, ox, oy, eps)
        if side == OUTSIDE:
            outside[no] = pid
            return inside, ni, outside, no + 1
        if side == INSIDE:
            inside[ni] = pid
            return inside, ni + 1, outside, no
        if convex_road and _takes_convex_road(sx, sy, ss, len(ox)):
            return _cut_by_outline(arena, pid, source, ox, oy, ol, eps, fw, iw, inside, ni, outside, no)
    ix, iy, il, ist, qx, qy, ql, qst = clip_arrays(sx, sy, sl, ss, ox, oy, ol, os_, eps)
    if len(ist) > 1:
        inside[ni] = _add_piece(arena, ix, iy, il, ist, source)
        ni += 1
    if len(qst) > 1:
        outside[no] = _add_piece(arena, qx, qy, ql, qst, source)
        no += 1
    return inside, ni, outside, no


@njit(cache=True)
def _clip_list(arena, ids, src, ox, oy, ol, os_, obb, eps, convex_road):
    """The task's pieces split by polygon src's original outline: (inside, outside)."""
    psrc = arena[2][0][:, 4]  # new pieces are added past the ids read here: these stay valid
    pbb = arena[3][0]
    inside = np.empty(len(ids), np.int64)
    outside = np.empty(len(ids), np.int64)
    ni = np.int64(0)  # typed int64, not as the literal 0: one compiled _clip_piece for every caller
    no = np.int64(0)
    cb = obb[src]
    box = (cb[0], cb[1], cb[2], cb[3])
    convex = _is_convex(ox, oy)
    fw, iw = _workspace()
    for pid in ids:
        if psrc[pid] == src:  # a piece always lies in its own polygon's outline
            inside[ni] = pid
            ni += 1
        elif _disjoint(pbb, pid, box):
            if no == len(outside):
                outside = grown(outside, no + 1)
            outside[no] = pid
            no += 1
        else:
            inside, ni, outside, no = _clip_piece(arena, pid, box, convex, ox, oy, ol, os_, eps, convex_road, fw, iw,
                                                  inside, ni, outside, no)
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
def _resolve_inside(arena, src, inside, planes, eps, eps_z, convex_road):
    """Step c: inside pieces behind polygon src dropped, those crossing its plane split
    along the crossing line. Returns (kept pieces, pieces of other polygons in front)."""
    psrc = arena[2][0][:, 4]
    pbb = arena[3][0]
    kept = np.empty(2 * len(inside), np.int64)
    offenders = np.empty(2 * len(inside), np.int64)
    nk = 0
    nf = 0
    fw, iw = _workspace()
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
        elif rel == 0 and convex_road and _takes_convex_road(sx, sy, ss, 0):
            f = _cut_by_plane_line(arena, pid, source, planes[source, 0] - planes[src, 0],
                                   planes[source, 1] - planes[src, 1], planes[source, 2] - planes[src, 2], eps, fw, iw)
            if f >= 0:
                kept[nk] = f
                offenders[nf] = f
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


# -- steps b-d: the first list, then a stack of tasks for the inside lists ---------------


@njit(cache=True)
def later_neighbours(obb, order):
    """For each position p of the depth order, the later positions whose polygons' boxes
    overlap polygon order[p]'s (touching is not overlapping, as in :func:`_disjoint`), in
    ascending order: (row starts, positions). A sweep over the boxes sorted by left side."""
    n = len(order)
    bx = obb[order]
    by_x = np.argsort(bx[:, 0], kind="mergesort")
    lo = np.empty(16, np.int64)
    hi = np.empty(16, np.int64)
    m = 0
    for i in range(n):
        p = by_x[i]
        for j in range(i + 1, n):
            q = by_x[j]
            if bx[q, 0] >= bx[p, 2]:
                break
            if bx[q, 1] >= bx[p, 3] or bx[q, 3] <= bx[p, 1] or bx[q, 2] <= bx[p, 0]:
                continue
            if m == len(lo):
                lo = grown(lo, m + 1)
                hi = grown(hi, m + 1)
            lo[m] = min(p, q)
            hi[m] = max(p, q)
            m += 1
    starts, by_lo = grouped(lo[:m], n)
    rows = hi[by_lo]
    for p in range(n):
        rows[starts[p] : starts[p + 1]].sort()
    return starts, rows


@njit(cache=True)
def _settle(arena, src, inside, stack, planes, eps, eps_z, convex_road, visible, task_ids, task_stack):
    """Steps c and d for the inside list of polygon src: the visible pieces appended, or
    the list pushed as a task with its first offender as the clip polygon."""
    kept, offenders = _resolve_inside(arena, src, inside, planes, eps, eps_z, convex_road)
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
        return
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


@njit(cache=True)
def _outline(ox, oy, ol, ost, src):
    a = ost[src]
    b = ost[src + 1]
    return ox[a:b].copy(), oy[a:b].copy(), ol[a:b].copy(), np.array([0, b - a])


@njit(cache=True)
def _run_tasks(arena, ox, oy, ol, ost, obb, planes, eps, eps_z, convex_road, visible, task_ids, task_stack):
    """Solve the stacked tasks (an inside list and what it spawns) to the end."""
    while len(task_ids) > 0:
        ids = task_ids.pop()
        stack = task_stack.pop()
        if len(ids) == 0:
            continue
        src = arena[2][0][ids[0], 4]
        cx, cy, cl, cs = _outline(ox, oy, ol, ost, src)
        inside, outside = _clip_list(arena, ids, src, cx, cy, cl, cs, obb, eps, convex_road)
        # the rest of this list after the inside list (pushed first: taken last)
        task_ids.append(outside)
        task_stack.append(stack)
        _settle(arena, src, inside, stack, planes, eps, eps_z, convex_road, visible, task_ids, task_stack)


@njit(cache=True)
def _solve(arena, first, order, ox, oy, ol, ost, obb, planes, eps, eps_z, convex_road):
    """Indices of the visible pieces (they do not overlap).

    The first list (every polygon's piece in depth order) is kept as one chain of pieces
    per polygon, so that a clip polygon meets only the polygons whose boxes overlap its
    own (:func:`later_neighbours`) instead of the whole list; the pieces it meets and
    their order are those of the list, so the result is the same."""
    visible = List()
    visible.append(0)
    visible.pop()
    task_ids = List()
    task_stack = List()
    task_ids.append(np.empty(0, np.int64))
    task_stack.append(np.empty(0, np.int64))
    task_ids.pop()
    task_stack.pop()
    n = len(order)
    position = np.empty(len(ost) - 1, np.int64)
    for p in range(n):
        position[order[p]] = p
    head = np.full(n, -1, np.int64)
    link = np.full(2 * len(first) + 16, -1, np.int64)  # next piece of the same polygon
    for i in range(len(first) - 1, -1, -1):
        pid = first[i]
        p = position[arena[2][0][pid, 4]]
        link[pid] = head[p]
        head[p] = pid
    starts, rows = later_neighbours(obb, order)
    fw, iw = _workspace()
    inside = np.empty(16, np.int64)
    parts = np.empty(16, np.int64)
    empty = np.empty(0, np.int64)
    for p in range(n):
        if head[p] < 0:
            continue
        src = order[p]
        cx, cy, cl, cs = _outline(ox, oy, ol, ost, src)
        cb = obb[src]
        box = (cb[0], cb[1], cb[2], cb[3])
        convex = _is_convex(cx, cy)
        ni = np.int64(0)
        pid = head[p]
        while pid >= 0:  # a piece always lies in its own polygon's outline
            if ni == len(inside):
                inside = grown(inside, ni + 1)
            inside[ni] = pid
            ni += 1
            pid = link[pid]
        head[p] = -1
        pbb = arena[3][0]  # read once per clip polygon: the pieces added below are not visited
        for r in range(starts[p], starts[p + 1]):
            q = rows[r]
            prev = -1
            pid = head[q]
            while pid >= 0:
                after = link[pid]
                if _disjoint(pbb, pid, box):
                    prev = pid
                    pid = after
                    continue
                inside, ni, parts, nparts = _clip_piece(arena, pid, box, convex, cx, cy, cl, cs, eps, convex_road,
                                                        fw, iw, inside, ni, parts, np.int64(0))
                # the piece's outside parts take its place in its polygon's chain
                link = grown(link, arena[4][0] + 1)
                for k in range(nparts):
                    if prev < 0:
                        head[q] = parts[k]
                    else:
                        link[prev] = parts[k]
                    prev = parts[k]
                if prev < 0:
                    head[q] = after
                else:
                    link[prev] = after
                pid = after
        _settle(arena, src, inside[:ni].copy(), empty, planes, eps, eps_z, convex_road, visible, task_ids, task_stack)
        _run_tasks(arena, ox, oy, ol, ost, obb, planes, eps, eps_z, convex_road, visible, task_ids, task_stack)
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
def solve_window(ox, oy, ost, obb, planes, order, win, eps, eps_z, convex_road=True):
    """Visible pieces of the polygons ``order`` (depth-sorted) inside window ``win``.

    ``ox, oy, ost``: every polygon's original outline (polygon p is vertices
    ``ost[p]:ost[p + 1]``, positive area); ``obb`` their boxes, ``planes`` their depth
    planes. Returns the pieces flattened: (xs, ys, labels, contour starts, first contour
    of each piece (one more entry than pieces), source of each piece). ``convex_road``:
    clip convex pieces by convex outlines with :mod:`.convex_kernel` (False: every pair
    by the paper's clipper)."""
    ol = np.full(len(ox), EDGE_CUT, np.int64)
    arena = _new_arena()
    first = _window_pieces(arena, ox, oy, ost, obb, order, win, eps)
    visible = _solve(arena, first, order, ox, oy, ol, ost, obb, planes, eps, eps_z, convex_road)
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


__all__ = ["solve_window", "half_plane", "later_neighbours", "ring_area_of", "EDGE_CUT", "EDGE_OWN", "EDGE_CROSSING"]
