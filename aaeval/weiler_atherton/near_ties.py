"""The scene format's near-tie rule for Weiler-Atherton, where pairwise depth tests fail.

The area sort compares two polygons at a time, and a tolerance makes that comparison
intransitive: in a stack of nearly coplanar polygons A may tie B (the later wins), B tie
C, while A is in front of C by more than the tolerance. Such a cycle removed every piece
of a region (four tilted copies of one quad lost 3% of their area, twelve up to 35%).

The rule is relative to the nearest depth at each point (``docs/scene_format.md``): of the
polygons within ``eps`` of the nearest, the latest listed is visible. Written as regions,
polygon ``i`` is visible on

    R_i = P_i  minus  U_j (P_j ∩ {z_j < z_i - eps})  minus  U_{j > i} R_j

(``P`` a polygon's outline): it is out where another polygon is more than ``eps``
nearer, and later polygons claim first. Every point under some polygon lands in exactly
one ``R_i``: the nearest polygon there is never more than ``eps`` behind another, so it
keeps the point unless a later tied one took it. That holds in floating point too, as
long as ``eps`` is far above the rounding of a plane evaluation, so the area is kept.

:func:`tie_groups` finds the polygons that need this: the groups (by overlapping boxes)
holding a pair whose planes are within :data:`NEAR_COPLANAR` x ``eps`` of each other over
their common box, but not everywhere within ``eps``. Every other group keeps the area sort,
where crossing planes are split where their depths are equal.
"""

from __future__ import annotations

import numpy as np

from aaeval.native.weiler_atherton import components, later_neighbours
from aaeval.native.weiler_atherton import solve_by_rule as _solve_by_rule
from aaeval.weiler_atherton.clipper import Shape, from_arrays, polygons

__all__ = ["NEAR_COPLANAR", "tie_groups", "solve_by_rule"]

#: two planes whose depths differ by at most this many eps over their common box are
#: solved by the rule (a 64-pixel quad tilted by up to about 3e-9 against another)
NEAR_COPLANAR = 1e4
#: common boxes narrower than this (pixels) are not looked at: there the depth slopes of
#: a near-coplanar pair may differ by up to 2 NEAR_COPLANAR eps / MIN_OVERLAP, and only
#: pairs whose slopes differ by less are compared box by box (a render's polygons are
#: not paired up unless some have nearly the same slopes)
MIN_OVERLAP = 1.0


def tie_groups(boxes: np.ndarray, planes: np.ndarray, sources: np.ndarray, eps_z: float) -> tuple[np.ndarray, np.ndarray]:
    """Split ``sources`` into (solved by the rule, solved by the area sort).

    The first part is every group of polygons connected by overlapping boxes that holds
    a near-coplanar pair (see :func:`_near_pairs`); the second the rest."""
    sources = np.asarray(sources, dtype=np.int64)
    tol = 2 * NEAR_COPLANAR * eps_z / MIN_OVERLAP
    alike = _similar_slopes(planes[sources], tol)
    alike &= _similar_depths(planes[sources], boxes[sources], alike, NEAR_COPLANAR * eps_z, tol)
    if alike.sum() < 2:
        return sources[:0], sources
    among_alike = _near_pairs(boxes, planes, sources[alike], eps_z)
    if not among_alike[2].any():
        return sources[:0], sources
    # every source alike (a stack of one plane): the pairs are those just found
    first, rows, near = among_alike if alike.all() else _near_pairs(boxes, planes, sources, eps_z)
    component = components(len(sources), first, rows)
    tied = np.isin(component, np.unique(component[first[near]]))
    return sources[tied], sources[~tied]


def _similar_slopes(planes: np.ndarray, tol: float) -> np.ndarray:
    """Which planes have another whose x slope and y slope are each within ``tol``
    (a superset of the near-coplanar pairs, found by sorting instead of pairing: in sorted
    order a slope's nearest others are its neighbours)."""
    alike = np.ones(len(planes), dtype=bool)
    for axis in (0, 1):
        idx = np.flatnonzero(alike)
        if len(idx) < 2:
            return np.zeros(len(planes), dtype=bool)
        order = np.argsort(planes[idx, axis])
        ordered = planes[idx[order], axis]
        # widened by a few ulps: a candidate filter may keep too many, never too few
        close = np.diff(ordered) <= tol * (1 + 1e-9) + 4 * np.spacing(np.abs(ordered).max())
        near = np.zeros(len(idx), dtype=bool)
        near[:-1] |= close
        near[1:] |= close
        alike[idx[order[~near]]] = False
    return alike


def _similar_depths(planes: np.ndarray, boxes: np.ndarray, alike: np.ndarray, band: float, tol: float) -> np.ndarray:
    """Which of the ``alike`` planes have another whose depth at one reference point (the
    middle of their boxes' common bounding box) is near enough for the two to be within
    ``band`` somewhere in their common box.

    A near-coplanar pair is within ``band`` at some point p of its common box, and its
    slopes differ by at most ``tol`` on each axis, so at the reference point r their
    depths differ by at most band + tol (|px - rx| + |py - ry|) <= band + tol (W + H) / 2,
    W x H the bounding box (which holds p). In sorted order a depth's nearest others are
    its neighbours: a filter like :func:`_similar_slopes`, found by sorting, that keeps
    too many, never too few, and drops every polygon of a stack of distinct layers."""
    out = np.zeros(len(planes), dtype=bool)
    idx = np.flatnonzero(alike)
    if len(idx) < 2:
        return out
    b = boxes[idx]
    x0, y0, x1, y1 = b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max()
    if not np.isfinite([x0, y0, x1, y1]).all():
        return alike.copy()
    rx, ry = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    # polygons on one and the same plane are never a near-coplanar pair (their depths differ
    # by 0 everywhere): each plane once, kept when another plane is near it
    unique, inverse = _unique_rows(planes[idx])
    if len(unique) < 2:
        return out
    a, bb, c = unique[:, 0], unique[:, 1], unique[:, 2]
    z = a * rx + bb * ry + c
    # widened by the rounding of the evaluation (a few ulps of its largest term) and of the bound
    size = max(float(np.nanmax(np.abs(a * rx), initial=0.0)), float(np.nanmax(np.abs(bb * ry), initial=0.0)),
               float(np.nanmax(np.abs(c), initial=0.0)))
    window = (band + tol * 0.5 * ((x1 - x0) + (y1 - y0))) * (1 + 1e-9) + 8 * np.spacing(size)
    order = np.argsort(z)
    close = np.diff(z[order]) <= window
    near = np.zeros(len(unique), dtype=bool)
    near[order[:-1][close]] = True
    near[order[1:][close]] = True
    out[idx[near[inverse.ravel()]]] = True
    return out


def _unique_rows(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct rows and, for each row, the index of its distinct row (np.unique with
    axis=0, by one lexsort instead of a structured view: a fraction of its time)."""
    order = np.lexsort(rows.T[::-1])
    ordered = rows[order]
    new = np.ones(len(rows), dtype=bool)
    new[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    inverse = np.empty(len(rows), dtype=np.int64)
    inverse[order] = np.cumsum(new) - 1
    return ordered[new], inverse


def _near_pairs(boxes, planes, sources, eps_z):
    """Pairs of ``sources`` (positions ``first``, ``rows``) whose boxes overlap, and
    which of them are near-coplanar: apart by more than eps somewhere in their common
    box and by at most NEAR_COPLANAR eps everywhere in it."""
    if len(sources) < 2:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, bool)
    starts, rows = later_neighbours(boxes, sources)
    first = np.repeat(np.arange(len(sources)), np.diff(starts))
    i, j = sources[first], sources[rows]
    bi, bj = boxes[i], boxes[j]
    x0, y0 = np.maximum(bi[:, 0], bj[:, 0]), np.maximum(bi[:, 1], bj[:, 1])
    x1, y1 = np.minimum(bi[:, 2], bj[:, 2]), np.minimum(bi[:, 3], bj[:, 3])
    d = planes[j] - planes[i]
    corners = np.stack([d[:, 0] * x + d[:, 1] * y + d[:, 2] for x, y in ((x0, y0), (x1, y0), (x0, y1), (x1, y1))])
    spread = np.abs(corners).max(axis=0)
    # a pair within eps over its whole common box is tied everywhere there, and cannot
    # start a cycle alone; one apart by more than eps somewhere, but by at most
    # NEAR_COPLANAR eps everywhere, can, with a third polygon tied to both (depths 0,
    # 0.8 eps, 1.6 eps: A ties B, B ties C, A is before C). Crossing planes are apart by
    # more than that except in a strip along their crossing some eps / slope wide.
    wide = (x1 - x0 >= MIN_OVERLAP) & (y1 - y0 >= MIN_OVERLAP)
    return first, rows, wide & (spread > eps_z) & (spread <= NEAR_COPLANAR * eps_z)


def solve_by_rule(xs, ys, starts, boxes, planes, window, sources, eps, eps_z):
    """Visible regions of ``sources`` inside ``window`` by the rule (module docstring).

    Polygon s's outline is vertices ``starts[s]:starts[s + 1]`` of ``xs, ys`` (positive
    area), its box ``boxes[s]``. Returns [(source, Shape), ...], each shape one main
    contour and its holes, edges of a polygon's own outline labelled EDGE_OWN. The regions
    are cut in the native code (``src/weiler_atherton/near_ties.cpp``), clip after clip on
    the clipper's flat arrays: for each polygon, later ones first, its outline inside the
    window, less every other polygon's part more than ``eps_z`` nearer (a half-plane of its
    plane against this one's), less what later polygons claimed. The region of a stack of
    120 polygons takes some 30000 clips."""
    f64 = np.float64
    regions = _solve_by_rule(np.ascontiguousarray(xs, dtype=f64), np.ascontiguousarray(ys, dtype=f64),
                             np.ascontiguousarray(starts, dtype=np.int64), np.ascontiguousarray(boxes, dtype=f64),
                             np.ascontiguousarray(planes, dtype=f64), np.ascontiguousarray(sources, dtype=np.int64),
                             tuple(float(v) for v in window), float(eps), float(eps_z))
    out = []
    for source, *region in regions:
        out.extend((source, part) for part in polygons(from_arrays(*region)))
    return out


def resolve_flat_arrays(start, length, x, y, planes, source, eps_z):
    """Flat polygon arrays (the Catmull kernel's inputs: outlines ``start``/``length`` into
    ``x``/``y``, a plane and a scene index ``source`` each) with every near-coplanar group
    replaced by its visible regions under the rule, cut into triangles on the regions'
    own vertices. The groups overlap nothing else, so the rest keeps its polygons and
    the kernel sees only polygons it can sort pairwise. Unchanged (the same arrays) when
    the scene has no such group."""
    n = len(start)
    if n < 2:
        return start, length, x, y, planes, source
    ends = start + length
    boxes = _boxes(start, length, x, y)
    tied, rest = tie_groups(boxes, planes, np.arange(n), eps_z)
    if len(tied) == 0:
        return start, length, x, y, planes, source

    window = (boxes[tied, 0].min(), boxes[tied, 1].min(), boxes[tied, 2].max(), boxes[tied, 3].max())
    eps = 2e-14 * max(1.0, float(np.abs(x).max()), float(np.abs(y).max()))
    regions = solve_by_rule(x, y, np.append(start, ends[-1]), boxes, planes, window, tied, eps, eps_z)
    xs = [x[start[k]:ends[k]] for k in rest]
    ys = [y[start[k]:ends[k]] for k in rest]
    owner = list(rest)
    for k, shape in regions:
        for tri in _triangles(shape):
            xs.append(tri[:, 0])
            ys.append(tri[:, 1])
            owner.append(k)
    owner = np.asarray(owner, dtype=np.int64)
    new_length = np.array([len(v) for v in xs], dtype=np.int64)
    new_start = np.zeros(len(xs), dtype=np.int64)
    new_start[1:] = np.cumsum(new_length)[:-1]
    return (new_start, new_length, np.concatenate(xs), np.concatenate(ys),
            np.ascontiguousarray(planes[owner]), source[owner])


def _boxes(start, length, x, y) -> np.ndarray:
    """Each outline's box ``(n, 4)``: x0, y0, x1, y1 (outlines of one length, all
    triangles say, as rows of a 2D array: min and max are exact either way)."""
    rows = (len(start), int(length[0]))
    if rows[0] * rows[1] == len(x) and (start == np.arange(rows[0]) * rows[1]).all() and (length == rows[1]).all():
        xs, ys = x.reshape(rows), y.reshape(rows)
        box = np.stack([xs[:, 0], ys[:, 0], xs[:, 0], ys[:, 0]], axis=1)
        for j in range(1, rows[1]):  # column by column: numpy reduces short rows slowly
            np.minimum(box[:, 0], xs[:, j], out=box[:, 0])
            np.minimum(box[:, 1], ys[:, j], out=box[:, 1])
            np.maximum(box[:, 2], xs[:, j], out=box[:, 2])
            np.maximum(box[:, 3], ys[:, j], out=box[:, 3])
        return box
    return np.stack([np.minimum.reduceat(x, start), np.minimum.reduceat(y, start),
                     np.maximum.reduceat(x, start), np.maximum.reduceat(y, start)], axis=1)


def _triangles(shape: Shape) -> np.ndarray:
    """A main contour and its holes as triangles (m, 3, 2) on their own vertices, each
    of positive shoelace area."""
    import mapbox_earcut

    points = np.array([p for ring in shape.rings for p in ring], dtype=np.float64)
    ends = np.cumsum([len(r) for r in shape.rings]).astype(np.uint32)
    tri = points[mapbox_earcut.triangulate_float64(points, ends).reshape(-1, 3)]
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    area2 = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    tri[area2 < 0] = tri[area2 < 0][:, ::-1]
    return tri[area2 != 0]
