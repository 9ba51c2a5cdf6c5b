"""Weiler & Atherton (1977) general polygon clipper.

A *shape* is a list of closed contours, each a list of ``(x, y)`` tuples. Contours are
oriented: a main contour has positive shoelace area and a hole negative area. In image
coordinates (y down) positive shoelace area is clockwise on the screen, so this is the
paper's convention: main contours clockwise, holes counter-clockwise, the interior always
on the same side of the walk. Every edge carries an integer *label* (the edge from vertex
k to k+1 has ``labels[k]``) that follows it into the output, so a caller can tell which
output edges came from which input edges (hidden lines use this).

:func:`clip` cuts a subject shape by a clip shape into an *inside* and an *outside* shape,
following the paper's steps:

1. Intersections of the two boundaries become vertices of both contour chains: one float
   point is computed once and inserted into both, so the two chains share it exactly and
   it links them. Degenerate contact is decided with a distance tolerance: vertices that
   coincide are snapped together, a vertex on the other polygon's edge is inserted into
   that edge, collinear overlaps become shared edges.
2. Contours without intersections go whole to the inside or outside holding list; clip
   contours inside the subject go to both lists, once reversed (they cut a hole).
3.-4. The new contours are traced: follow the subject chain while it is inside (outside),
   at each intersection vertex turn onto the clip chain (walked backwards for the outside
   list), and so on until the start is reached. Where several chains meet in one vertex
   the walk takes the first edge clockwise from the way it came (interior on the left,
   shoelace sense), which keeps every traced contour free of crossings.
5. Holes are attached to their main contours by :func:`polygons`.
"""

from __future__ import annotations

import bisect
import math
from typing import NamedTuple

__all__ = ["Shape", "clip", "shape_area", "ring_area", "oriented", "polygons", "tolerance"]

Point = tuple[float, float]


class Shape(NamedTuple):
    """Oriented contours with a label per edge (``labels[i][k]``: edge k of contour i)."""

    rings: list[list[Point]]
    labels: list[list[int]]

    @classmethod
    def of(cls, rings, label: int = 0) -> "Shape":
        """A shape from contours given as sequences of points, all edges labelled ``label``."""
        rs = [[(float(x), float(y)) for x, y in r] for r in rings]
        return cls(rs, [[label] * len(r) for r in rs])


def ring_area(ring: list[Point]) -> float:
    """Shoelace area (positive for a main contour)."""
    n = len(ring)
    if n < 3:
        return 0.0
    x0, y0 = ring[0]
    s = 0.0
    for i in range(1, n - 1):
        ax, ay = ring[i]
        bx, by = ring[i + 1]
        s += (ax - x0) * (by - y0) - (bx - x0) * (ay - y0)
    return 0.5 * s


def shape_area(shape: Shape) -> float:
    """Area of a shape: main contours minus holes."""
    return sum(ring_area(r) for r in shape.rings)


def oriented(rings, label: int = 0) -> Shape:
    """A shape from an outer contour and holes in any winding: the first contour is made
    the main contour (positive area), the others holes (negative area)."""
    out = []
    for i, r in enumerate(rings):
        r = _without_repeats([(float(x), float(y)) for x, y in r])
        a = ring_area(r)
        if (a < 0) == (i == 0):
            r = r[::-1]
        out.append(r)
    return Shape(out, [[label] * len(r) for r in out])


def _without_repeats(ring: list[Point]) -> list[Point]:
    out = [p for i, p in enumerate(ring) if p != ring[i - 1]]
    return out if out else ring[:1]


def tolerance(*shapes: Shape) -> float:
    """Distance under which two points count as one and a point as lying on a line:
    ~100 float64 ulps of the largest coordinate, far below any area the tests resolve."""
    m = 1.0
    for s in shapes:
        for r in s.rings:
            for x, y in r:
                m = max(m, abs(x), abs(y))
    return 2e-14 * m


def _bbox(shape: Shape):
    xs = [p[0] for r in shape.rings for p in r]
    ys = [p[1] for r in shape.rings for p in r]
    return min(xs), min(ys), max(xs), max(ys)


def _winding(px: float, py: float, rings) -> int:
    """Winding number of the point about the oriented contours (1 inside a shape)."""
    w = 0
    for r in rings:
        n = len(r)
        x0, y0 = r[n - 1]
        for i in range(n):
            x1, y1 = r[i]
            if y0 <= py:
                if y1 > py and (x1 - x0) * (py - y0) - (px - x0) * (y1 - y0) > 0:
                    w += 1
            elif y1 <= py and (x1 - x0) * (py - y0) - (px - x0) * (y1 - y0) < 0:
                w -= 1
            x0, y0 = x1, y1
    return w


def _snap_vertices(subject: Shape, clipper: Shape, eps: float) -> Shape:
    """The clip shape with each vertex that coincides with a subject vertex replaced by
    it, so shared vertices are bitwise equal."""
    sub = {}
    for r in subject.rings:
        for p in r:
            sub[p] = p
    pts = list(sub)
    rings = []
    for r in clipper.rings:
        nr = []
        for q in r:
            if q not in sub:
                for p in pts:
                    if abs(p[0] - q[0]) <= eps and abs(p[1] - q[1]) <= eps:
                        q = p
                        break
            nr.append(q)
        rings.append(nr)
    return Shape(rings, clipper.labels)


def _edges(shape: Shape):
    """(ring, k, p0, p1, bbox) for every edge."""
    out = []
    for i, r in enumerate(shape.rings):
        n = len(r)
        for k in range(n):
            p0 = r[k]
            p1 = r[(k + 1) % n]
            out.append((i, k, p0, p1, min(p0[0], p1[0]), min(p0[1], p1[1]), max(p0[0], p1[0]), max(p0[1], p1[1])))
    return out


def _on_segment(q: Point, p0: Point, p1: Point, eps: float):
    """Parameter t in (0, 1) of q on segment p0-p1 when q lies on it strictly between the
    ends (distance <= eps from the line, > eps from both ends); else None."""
    dx = p1[0] - p0[0]
    dy = p1[1] - p0[1]
    ll = dx * dx + dy * dy
    if ll == 0.0:
        return None
    qx = q[0] - p0[0]
    qy = q[1] - p0[1]
    cr = dx * qy - dy * qx
    if cr * cr > eps * eps * ll:
        return None
    t = (dx * qx + dy * qy) / ll
    tol = eps / math.sqrt(ll)
    if t <= tol or t >= 1.0 - tol:
        return None
    return t


def _intersections(subject: Shape, clipper: Shape, eps: float):
    """Split points for every edge of both shapes: ``{(ring, k): [(t, point), ...]}``.

    Crossings of a subject edge with a clip edge are computed once and shared by both;
    then every vertex and crossing point lying on any edge (of either shape, its own
    contours included: a hole may touch its main contour) is inserted into that edge.
    """
    s_edges = _edges(subject)
    c_edges = _edges(clipper)
    points = {p for r in subject.rings for p in r} | {q for r in clipper.rings for q in r}
    for _, _, p0, p1, sx0, sy0, sx1, sy1 in s_edges:
        for _, _, q0, q1, cx0, cy0, cx1, cy1 in c_edges:
            if cx0 > sx1 + eps or cx1 < sx0 - eps or cy0 > sy1 + eps or cy1 < sy0 - eps:
                continue
            x = _proper_crossing(p0, p1, q0, q1, eps)
            if x is not None:
                points.add(x)
    pts = sorted(points)
    xs = [p[0] for p in pts]
    return _node(s_edges, pts, xs, eps), _node(c_edges, pts, xs, eps)


def _node(edges, pts, xs, eps):
    """Points of ``pts`` (sorted by x) lying strictly inside each edge."""
    splits: dict = {}
    for i, k, p0, p1, x0, y0, x1, y1 in edges:
        lo = bisect.bisect_left(xs, x0 - eps)
        hi = bisect.bisect_right(xs, x1 + eps)
        for j in range(lo, hi):
            q = pts[j]
            if q[1] < y0 - eps or q[1] > y1 + eps or q == p0 or q == p1:
                continue
            t = _on_segment(q, p0, p1, eps)
            if t is not None:
                splits.setdefault((i, k), []).append((t, q))
    return splits


def _proper_crossing(p0, p1, q0, q1, eps):
    """The point where two segments cross strictly inside both (each end farther than
    eps from the other line); else None."""
    dpx = p1[0] - p0[0]
    dpy = p1[1] - p0[1]
    dqx = q1[0] - q0[0]
    dqy = q1[1] - q0[1]
    lp = math.hypot(dpx, dpy)
    lq = math.hypot(dqx, dqy)
    d0 = dpx * (q0[1] - p0[1]) - dpy * (q0[0] - p0[0])
    d1 = dpx * (q1[1] - p0[1]) - dpy * (q1[0] - p0[0])
    if not ((d0 > eps * lp and d1 < -eps * lp) or (d0 < -eps * lp and d1 > eps * lp)):
        return None
    e0 = dqx * (p0[1] - q0[1]) - dqy * (p0[0] - q0[0])
    e1 = dqx * (p1[1] - q0[1]) - dqy * (p1[0] - q0[0])
    if not ((e0 > eps * lq and e1 < -eps * lq) or (e0 < -eps * lq and e1 > eps * lq)):
        return None
    tp = e0 / (e0 - e1)
    tq = d0 / (d0 - d1)
    # compute the point from the shorter parametrisation's nearer end (less rounding)
    if min(tp, 1 - tp) * lp <= min(tq, 1 - tq) * lq:
        x = (p0[0] + tp * dpx, p0[1] + tp * dpy) if tp <= 0.5 else (p1[0] - (1 - tp) * dpx, p1[1] - (1 - tp) * dpy)
    else:
        x = (q0[0] + tq * dqx, q0[1] + tq * dqy) if tq <= 0.5 else (q1[0] - (1 - tq) * dqx, q1[1] - (1 - tq) * dqy)
    return x


def _split_rings(shape: Shape, splits: dict):
    """The shape's contours with the split points inserted (ordered along each edge)."""
    rings = []
    labels = []
    for i, r in enumerate(shape.rings):
        nr = []
        nl = []
        lab = shape.labels[i]
        for k, p in enumerate(r):
            nr.append(p)
            nl.append(lab[k])
            pts = splits.get((i, k))
            if pts:
                pts.sort()
                for _, q in pts:
                    if q != nr[-1]:
                        nr.append(q)
                        nl.append(lab[k])
        # drop a closing duplicate (a split point equal to the first vertex)
        while len(nr) > 1 and nr[-1] == nr[0]:
            nr.pop()
            nl.pop()
        rings.append(nr)
        labels.append(nl)
    return rings, labels


def _directed_edges(rings, labels):
    out = []
    for r, lab in zip(rings, labels):
        n = len(r)
        for k in range(n):
            a = r[k]
            b = r[(k + 1) % n]
            if a != b:
                out.append((a, b, lab[k]))
    return out


def _trace(edges) -> list[tuple[list[Point], list[int]]]:
    """Link directed edges into closed contours, turning at shared vertices onto the first
    edge clockwise from the way the walk came (keeps contours free of crossings)."""
    outgoing: dict = {}
    for e in edges:
        outgoing.setdefault(e[0], []).append(e)
    used = set()
    contours = []
    for e0 in edges:
        if id(e0) in used:
            continue
        ring = []
        labs = []
        e = e0
        while True:
            used.add(id(e))
            ring.append(e[0])
            labs.append(e[2])
            v = e[1]
            cands = [f for f in outgoing.get(v, ()) if id(f) not in used]
            if not cands:
                break
            if len(cands) > 1:
                back = math.atan2(e[0][1] - v[1], e[0][0] - v[0])
                best = None
                for f in cands:
                    turn = (back - math.atan2(f[1][1] - v[1], f[1][0] - v[0])) % (2 * math.pi)
                    if turn == 0.0:
                        turn = 2 * math.pi
                    if best is None or turn < best[0]:
                        best = (turn, f)
                f = best[1]
            else:
                f = cands[0]
            e = f
        if len(ring) >= 3:
            contours.append((ring, labs))
    return contours


def _clean(contours, eps: float) -> Shape:
    """Contours without the zero-area leftovers of degenerate contact."""
    rings = []
    labels = []
    for r, lab in contours:
        if abs(ring_area(r)) > eps * eps:
            rings.append(r)
            labels.append(lab)
    return Shape(rings, labels)


def clip(subject: Shape, clipper: Shape, eps: float | None = None) -> tuple[Shape, Shape]:
    """Clip ``subject`` by ``clipper`` into (inside, outside) shapes.

    Parameters
    ----------
    subject, clipper : Shape
        Oriented contours (main contours positive area, holes negative); see
        :func:`oriented`. Edge labels of the subject follow its edges into both outputs;
        boundary taken from the clip shape keeps the clip shape's labels.
    eps : float, optional
        Contact tolerance (distance); default :func:`tolerance` of both shapes.

    Returns
    -------
    inside, outside : Shape
        ``subject ∩ clipper`` and ``subject \\ clipper``, as oriented contours.
    """
    if not subject.rings:
        return Shape([], []), Shape([], [])
    if not clipper.rings:
        return Shape([], []), subject
    if eps is None:
        eps = tolerance(subject, clipper)
    sb = _bbox(subject)
    cb = _bbox(clipper)
    if cb[0] >= sb[2] - eps or cb[2] <= sb[0] + eps or cb[1] >= sb[3] - eps or cb[3] <= sb[1] + eps:
        return Shape([], []), subject

    clipper = _snap_vertices(subject, clipper, eps)
    s_split, c_split = _intersections(subject, clipper, eps)
    shared_vertex = bool({p for r in subject.rings for p in r} & {q for r in clipper.rings for q in r})
    if not s_split and not c_split and not shared_vertex:
        return _holding_lists(subject, clipper)

    s_rings, s_labels = _split_rings(subject, s_split)
    c_rings, c_labels = _split_rings(clipper, c_split)
    s_edges = _directed_edges(s_rings, s_labels)
    c_edges = _directed_edges(c_rings, c_labels)
    s_set = {(a, b) for a, b, _ in s_edges}
    c_set = {(a, b) for a, b, _ in c_edges}

    inside = []
    outside = []
    for a, b, lab in s_edges:
        if (a, b) in c_set:  # shared, same side: interior of both on the same side
            inside.append((a, b, lab))
        elif (b, a) in c_set:  # shared, opposite sides: boundary of the outside part
            outside.append((a, b, lab))
        elif _winding(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), c_rings) > 0:
            inside.append((a, b, lab))
        else:
            outside.append((a, b, lab))
    for a, b, lab in c_edges:
        if (a, b) in s_set or (b, a) in s_set:
            continue
        if _winding(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), s_rings) > 0:
            inside.append((a, b, lab))
            outside.append((b, a, lab))  # walked backwards: it bounds the outside part
    return _clean(_trace(inside), eps), _clean(_trace(outside), eps)


def _holding_lists(subject: Shape, clipper: Shape) -> tuple[Shape, Shape]:
    """The paper's step 2 when no boundaries meet: whole contours to the holding lists."""
    ins = Shape([], [])
    out = Shape([], [])
    for r, lab in zip(subject.rings, subject.labels):
        a, b = r[0], r[1]
        target = ins if _winding(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), clipper.rings) > 0 else out
        target.rings.append(r)
        target.labels.append(lab)
    for r, lab in zip(clipper.rings, clipper.labels):
        a, b = r[0], r[1]
        if _winding(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), subject.rings) > 0:
            ins.rings.append(r)
            ins.labels.append(lab)
            out.rings.append(r[::-1])
            out.labels.append(lab[-2::-1] + lab[-1:])
    return ins, out


def polygons(shape: Shape) -> list[Shape]:
    """Split a shape into polygons, each one main contour followed by its holes.

    Each hole goes to the smallest main contour that contains it.
    """
    mains = [i for i, r in enumerate(shape.rings) if ring_area(r) > 0]
    holes = [i for i, r in enumerate(shape.rings) if ring_area(r) <= 0]
    owned = {i: [] for i in mains}
    areas = {i: ring_area(shape.rings[i]) for i in mains}
    for h in holes:
        ring = shape.rings[h]
        probe = _inner_point(ring)
        best = None
        for m in mains:
            if _winding(probe[0], probe[1], [shape.rings[m]]) != 0 and (best is None or areas[m] < areas[best]):
                best = m
        if best is not None:
            owned[best].append(h)
    return [
        Shape([shape.rings[i]] + [shape.rings[h] for h in owned[i]], [shape.labels[i]] + [shape.labels[h] for h in owned[i]])
        for i in mains
    ]


def _inner_point(hole: list[Point]) -> Point:
    """A point just inside the hole's opening (right of its longest edge), off every
    contour a touching hole may share with its main contour."""
    n = len(hole)
    k = max(range(n), key=lambda i: math.dist(hole[i], hole[(i + 1) % n]))
    a, b = hole[k], hole[(k + 1) % n]
    dx, dy = b[0] - a[0], b[1] - a[1]
    length = math.hypot(dx, dy)
    area = abs(ring_area(hole))
    off = 1e-3 * area / length  # well inside a hole that thin
    # holes have negative area: their opening lies to the right of each edge (shoelace sense)
    return (0.5 * (a[0] + b[0]) + off * dy / length, 0.5 * (a[1] + b[1]) - off * dx / length)
