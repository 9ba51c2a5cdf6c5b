"""Convex pieces cut by lines (numba): the hidden-surface loop's short road.

Where a piece and the outline clipping it are both one convex contour (every piece of a
scene of triangles), the clip comes down to cutting by the outline's edge lines one after
another: what lies beyond an edge's line is a convex piece of the outside, what lies
within goes on to the next edge, and what is left after the last edge is the inside (the
intersection of two convex polygons). The outside is then up to one convex piece per
outline edge instead of the paper's single polygon (perhaps with a hole): the same region,
cut into convex parts, so the next clip of those parts takes this road again. The cuts
carry the outline's edge label (EDGE_CUT), so hidden-line drawings leave them out.

A piece split along the line where its plane crosses another polygon's (step c) is cut
the same way by that one line.

:mod:`.clip_kernel` (the paper's clipper) handles every other pair; ``convex=False`` in
:func:`.solve_kernel.solve_window` sends every pair there, and the tests compare the two.
"""

from __future__ import annotations

import math

from numba import njit

__all__ = ["split_convex", "edge_line_values", "plane_line_values", "vertex_sides"]


@njit(cache=True)
def _side(d, tol):
    if d > tol:
        return 1
    if d < -tol:
        return -1
    return 0


@njit(cache=True)
def vertex_sides(d, n, tol):
    """(has a vertex below -tol, has a vertex above tol) among d[:n]."""
    below = False
    above = False
    for k in range(n):
        if d[k] < -tol:
            below = True
        elif d[k] > tol:
            above = True
    return below, above


@njit(cache=True)
def edge_line_values(xs, ys, n, ax, ay, bx, by, d):
    """d[k] for the first n vertices: minus the cross product of the edge a->b with the
    vertex's offset from a (negative left of the edge, inside a positive contour); the
    tolerance that goes with it (eps in distance) is returned."""
    ex = bx - ax
    ey = by - ay
    for k in range(n):
        d[k] = ey * (xs[k] - ax) - ex * (ys[k] - ay)
    return math.hypot(ex, ey)


@njit(cache=True)
def plane_line_values(xs, ys, n, a, b, c, d):
    """d[k] = a x + b y + c for the first n vertices; returns |(a, b)| (see above)."""
    for k in range(n):
        d[k] = a * xs[k] + b * ys[k] + c
    return math.hypot(a, b)


@njit(cache=True)
def _crossing(x0, y0, d0, x1, y1, d1):
    """Where the edge between two vertices on opposite sides meets the line (d = 0),
    computed from the lexicographically first end, so that an edge walked either way (by
    the pieces on both sides of it) gives the same bits."""
    if x1 < x0 or (x1 == x0 and y1 < y0):
        x0, y0, d0, x1, y1, d1 = x1, y1, d1, x0, y0, d0
    t = d0 / (d0 - d1)
    return x0 + t * (x1 - x0), y0 + t * (y1 - y0)


@njit(cache=True)
def split_convex(xs, ys, labels, n, d, tol, line_label, lx, ly, ll, rx, ry, rl):
    """Split a convex contour (its first n vertices, positive area) by a line, given the
    line's value d[k] at every vertex: the part where d <= 0 goes to (lx, ly, ll), the
    part where d >= 0 to (rx, ry, rl), both positive area; returns their vertex counts.

    Vertices with |d| <= tol lie on the line and belong to both parts; an edge from one
    side to the other is cut at one point shared by both. ``labels[k]`` labels the edge
    leaving vertex k; a part's new edge along the line gets ``line_label``. Call it only
    where vertices lie strictly on both sides (:func:`vertex_sides`)."""
    nl = 0
    nr = 0
    for k in range(n):
        j = k + 1 if k + 1 < n else 0
        sk = _side(d[k], tol)
        sj = _side(d[j], tol)
        if sk <= 0:
            lx[nl] = xs[k]
            ly[nl] = ys[k]
            ll[nl] = line_label if sk == 0 and sj > 0 else labels[k]
            nl += 1
        if sk >= 0:
            rx[nr] = xs[k]
            ry[nr] = ys[k]
            rl[nr] = line_label if sk == 0 and sj < 0 else labels[k]
            nr += 1
        if sk * sj < 0:
            x, y = _crossing(xs[k], ys[k], d[k], xs[j], ys[j], d[j])
            lx[nl] = x
            ly[nl] = y
            ll[nl] = line_label if sk < 0 else labels[k]
            nl += 1
            rx[nr] = x
            ry[nr] = y
            rl[nr] = line_label if sk > 0 else labels[k]
            nr += 1
    return nl, nr
