"""Catmull's pixel integrator in plain Python: what the native one does, for reading and tests.

One pixel, the polygons over it (already cut to the pixel square) front to back at the
pixel centre, the background square last. Catmull 1978, "The Pixel Integrator":

1. Take the list's front polygon F.
2. If F has an edge that is not yet a clipping line (a *free* edge), clip every polygon of
   the list by that edge's line into two lists (3.) and resolve each (4.): on one side F
   fills its region up to its edges, on the other F is absent.
3. F without a free edge covers its list's whole region. If a polygon of the list is
   nearer than F everywhere on itself, it moves to the front and the list is looked at
   again; if one crosses F's depth plane inside itself, the list is split along the line
   where the two planes meet; else F is visible over the region.

Every visible region is emitted with its polygon. The native integrator
(``src/catmull/integrator.hpp``) adds bookkeeping this one leaves out where it can (flat
buffers, one stack, growth), and the same guards: rounding remnants (a front polygon with
no free edge much smaller than its region) are dropped, and a cycle of near ties (depth
ties are not transitive) ends after as many moves as the list has members.

A polygon here is a list of ``(x, y, free)`` vertices, ``free`` saying whether the edge
to the next vertex may still be clipped along; depth planes are ``z = a x + b y + c``
(smaller z nearer) and the source ``-1`` is the background, behind everything.
"""

from __future__ import annotations

import math

__all__ = ["EPS_LINE", "pixel_areas", "integrate_pixel", "clip", "area"]

EPS_LINE = 1e-11  # points this close to a clipping line lie on it (both sides)
AREA_EMPTY = 1e-15  # smaller pieces are rounding slivers
SLIVER_SLACK = EPS_LINE
BACKGROUND = -1


def area(poly):
    """Shoelace area (positive for the kernel's orientation, y down)."""
    return 0.5 * sum(x0 * y1 - x1 * y0 for (x0, y0, _), (x1, y1, _) in zip(poly, poly[1:] + poly[:1]))


def clip(poly, a, b, c):
    """The parts of a polygon on side A (``a x + b y + c < 0``) and side B of a line.

    Vertices within EPS_LINE of the line belong to both; edges along the line are no
    longer free. A part with fewer than 3 vertices is empty.
    """
    sides = ([], [])
    n = len(poly)
    for i in range(n):
        x0, y0, free0 = poly[i - 1]
        x1, y1, free1 = poly[i]
        d0, d1 = a * x0 + b * y0 + c, a * x1 + b * y1 + c
        s0, s1 = _side(d0), _side(d1)
        if s0 * s1 < 0:  # the edge crosses the line: the crossing point joins both parts
            t = d0 / (d0 - d1)
            point = (x0 + t * (x1 - x0), y0 + t * (y1 - y0), free0, True)
            sides[0].append(point)
            sides[1].append(point)
        if s1 <= 0:
            sides[0].append((x1, y1, free1, s1 == 0))
        if s1 >= 0:
            sides[1].append((x1, y1, free1, s1 == 0))
    # an edge is on the line when both its ends are
    return tuple([(x, y, free and not (on and nxt[3])) for (x, y, free, on), nxt in zip(part, part[1:] + part[:1])]
                 if len(part) >= 3 else [] for part in sides)


def _side(d):
    return -1 if d < -EPS_LINE else (1 if d > EPS_LINE else 0)


def _relation(q, f, eps_z):
    """Where polygon q lies in depth against f's plane: 0 behind, 1 in front, 2 crossing
    (tested on q's vertices' distance to the line where the planes meet)."""
    (pq, sq), (pf, sf) = (q[2], q[1]), (f[2], f[1])
    da, db, dc = pq[0] - pf[0], pq[1] - pf[1], pq[2] - pf[2]
    g = math.hypot(da, db)
    d = [da * x + db * y + dc for x, y, _ in q[0]]
    lo, hi = min(d), max(d)
    if g <= eps_z:  # parallel planes: a shared one puts the later polygon in front
        return int(sq > sf) if hi <= eps_z and lo >= -eps_z else int(hi < 0.0)
    lo, hi = lo / g, hi / g
    if lo >= -EPS_LINE and hi <= EPS_LINE:
        return int(lo + hi < 0.0)
    return 0 if lo >= -EPS_LINE else (1 if hi <= EPS_LINE else 2)


def _free_edge_line(poly):
    """The line ``(a, b, c)`` (unit normal) of the polygon's first free edge that is not
    degenerate, or None."""
    for (x0, y0, free), (x1, y1, _) in zip(poly, poly[1:] + poly[:1]):
        e = math.hypot(x1 - x0, y1 - y0)
        if free and e > EPS_LINE:
            a, b = (y1 - y0) / e, -(x1 - x0) / e
            return a, b, -(a * x0 + b * y0)
    return None


def _nearer_or_crossing(lst, eps_z):
    """``(i, None)``: polygon i of the list is nearer than its front F everywhere on itself;
    ``(None, line)``: the first polygon crossing F's depth plane, and the line where the
    planes meet; ``(None, None)``: F is in front of them all."""
    front = lst[0]
    for i, q in enumerate(lst[1:], 1):
        if q[1] == BACKGROUND:
            continue
        rel = _relation(q, front, eps_z)
        if rel == 1:
            return i, None
        if rel == 2:
            da, db = q[2][0] - front[2][0], q[2][1] - front[2][1]
            g = math.hypot(da, db)
            return None, (da / g, db / g, (q[2][2] - front[2][2]) / g)
    return None, None


def integrate_pixel(items, eps_z):
    """Visible ``(source, polygon)`` pieces of a pixel's list ``items``: ``(polygon, source,
    plane)`` front to back, the background (plane None) last, covering the pixel."""
    visible = []
    stack = [(list(items), 0)]  # a list and how many times in a row its front was replaced
    while stack:
        lst, moves = stack.pop()
        front = lst[0]
        line = _free_edge_line(front[0]) if len(lst) > 1 else None
        if line is None and len(lst) > 1:
            # F has no free edge left: it covers the list's region, unless it is a remnant
            region = max(area(p[0]) for p in lst)
            if region - area(front[0]) > max(region * 1e-9, SLIVER_SLACK):
                stack.append((lst[1:], 0))
                continue
            if moves < len(lst):  # (more moves than members: a cycle of near ties, F stays)
                nearer, line = _nearer_or_crossing(lst, eps_z)
                if nearer:  # it moves to the front and the list is looked at again
                    stack.append(([lst[nearer]] + lst[:nearer] + lst[nearer + 1:], moves + 1))
                    continue
        if line is None:  # F is visible over the whole region
            visible.append((front[1], front[0]))
            continue
        parts = [clip(p[0], *line) for p in lst]
        for side in (0, 1):
            kept = [(part[side], p[1], p[2]) for part, p in zip(parts, lst) if area(part[side]) > AREA_EMPTY]
            if kept:
                stack.append((kept, 0))
    return visible


def pixel_areas(polygons, planes, col, row, eps_z):
    """Visible area of each source in pixel ``(col, row)``: ``{source: area}``.

    ``polygons[k]`` is kernel polygon k's outline (``(x, y)`` pairs, positive area) with
    depth plane ``planes[k]``; the pixel's list is every polygon cut to the pixel square,
    front to back at the pixel centre (on a shared plane the later one first), then the
    background square.
    """
    square = [(col, row, False), (col + 1.0, row, False), (col + 1.0, row + 1.0, False), (col, row + 1.0, False)]
    items = []
    for k, (outline, plane) in enumerate(zip(polygons, planes)):
        poly = [(float(x), float(y), True) for x, y in outline]
        for a, b, c in ((-1.0, 0.0, col), (1.0, 0.0, -col - 1.0), (0.0, -1.0, row), (0.0, 1.0, -row - 1.0)):
            poly = clip(poly, a, b, c)[0]
        if area(poly) > AREA_EMPTY:
            items.append((poly, k, tuple(plane)))
    centre = (col + 0.5, row + 0.5)
    items.sort(key=lambda it: (it[2][0] * centre[0] + it[2][1] * centre[1] + it[2][2], -it[1]))
    items.append((square, BACKGROUND, None))
    areas = {}
    for source, poly in integrate_pixel(items, eps_z):
        areas[source] = areas.get(source, 0.0) + area(poly)
    return areas
