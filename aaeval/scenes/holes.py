"""Polygons with holes (the ``holes`` key of the scene format): checks and pieces.

A polygon with holes is checked ring by ring (each ring with the format's own
simplicity check), then the rings against each other: every hole strictly inside the
outer ring, holes disjoint, all in the polygon's plane. It is then cut by ear clipping
(mapbox-earcut, which takes holes) into triangles that share the rings' own vertices,
and the triangles are merged back into convex pieces across every shared edge that can go
(Hertel & Mehlhorn), so the pieces abut exactly, their union is exactly the polygon, and
there are about half as many of them as triangles. Those pieces stand in
``Scene.polygons`` in the polygon's place, which is how every exact method renders holes
without seams and without knowing about them; :class:`HoledPolygon` keeps the rings for
methods that fill whole shapes (Skia's paths, Mitsuba's meshes), where pieces would
show seams or stack coplanar nudges.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from itertools import chain
from typing import Any

import numpy as np

from aaeval.scenes.simplicity import rings_contact
from aaeval.scenes.format import (
    check_planar,
    MAX_COORDINATE,
    PLANARITY_RTOL,
    Polygon,
    SceneError,
    check_no_repeats,
    check_simple,
    next_vertices,
    parse_polygon,
    point_list,
)

__all__ = ["HoledPolygon", "polygons_with_holes", "ring_area", "points_inside"]

# Triangles smaller than this (relative to the polygon's size squared) are rounding
# leftovers of collinear vertices: they cover nothing and only burden the clippers.
SLIVER_RTOL = 1e-13
# The pieces must cover the polygon's area to this relative tolerance, or the cut failed.
CUT_RTOL = 1e-9


@dataclass(frozen=True)
class HoledPolygon:
    """A polygon of the file that has holes.

    Attributes
    ----------
    rings : tuple of ndarray, each (n, 3)
        The outer ring first, then every hole, as in the file (x, y, z).
    color : ndarray, shape (3,)
    plane : ndarray, shape (3,)
        The outer ring's depth plane (NaN when seen edge-on); every piece has it.
    file_index : int
        Position in the file's ``[[polygons]]``.
    first, count : int
        Its pieces are ``scene.polygons[first : first + count]``.
    """

    rings: tuple[np.ndarray, ...]
    color: np.ndarray
    plane: np.ndarray
    file_index: int
    first: int
    count: int

    @property
    def pieces(self) -> range:
        return range(self.first, self.first + self.count)

    def translated(self, shift: np.ndarray) -> "HoledPolygon":
        rings = tuple(np.column_stack([r[:, :2] + shift, r[:, 2]]) for r in self.rings)
        a, b, c = self.plane
        return replace(self, rings=rings, plane=np.array([a, b, c - a * shift[0] - b * shift[1]]))


def ring_area(xy: np.ndarray) -> float:
    """Signed area of a closed ring (shoelace; positive counter-clockwise in y-up axes)."""
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.sum(x * next_vertices(y) - next_vertices(x) * y))


def polygons_with_holes(raw_polygons: list, source: str) -> tuple[tuple[Polygon, ...], tuple[HoledPolygon, ...]]:
    """Every ``[[polygons]]`` entry checked; polygons with holes replaced by their pieces.

    A file without ``holes`` gives exactly the polygons it always gave (index = file
    position) and no :class:`HoledPolygon`.
    """
    plain = _plain_polygons(raw_polygons, source)
    if plain is not None:
        return plain, ()
    polygons: list[Polygon] = []
    holed: list[HoledPolygon] = []
    for i, raw in enumerate(raw_polygons):
        polygon = parse_polygon(raw, i, source)  # every rule of the outer ring and the other keys
        first = len(polygons)
        if "holes" not in raw:
            polygons.append(polygon if polygon.index == first else replace(polygon, index=first))
            continue
        where = f"{source}: polygons[{i}]"
        holes = _hole_rings(raw["holes"], polygon.vertices, where)
        pieces = _cut_into_pieces(polygon, holes, where) if holes else [polygon.vertices]
        polygons.extend(
            Polygon(vertices=v, color=polygon.color, index=first + k, plane=polygon.plane)
            for k, v in enumerate(pieces)
        )
        holed.append(HoledPolygon((polygon.vertices, *holes), polygon.color, polygon.plane, i, first, len(pieces)))
    return tuple(polygons), tuple(holed)


# A scene of many small polygons without holes (100,000 triangles) is checked polygon by
# polygon array-wide: the same rules, in numpy over (polygons, k, 3) stacks, one stack a
# vertex count k. Up to 7 vertices only, where numpy sums the k terms of a mean or of
# Newell's normal one after another as the single-polygon code does (pairwise summation
# starts at 8 terms), so every plane has the bits parse_polygon gives it (tested).
PLAIN_BATCH_MIN = 64
PLAIN_BATCH_MAX_VERTICES = 7
_PLAIN_KEYS = {"color", "vertices"}


def _floats(rows, *shape: int) -> np.ndarray:
    """Nested lists of numbers (checked to be float or int, every list of the shape's length)
    as a float64 array of that shape: the innermost numbers read one after another, each
    converted as ``float()`` does (OverflowError past float64's range), in a fifth of
    ``np.array``'s time on 100,000 triangles (it looks at every list to find the shape)."""
    numbers = chain.from_iterable(rows)
    for _ in range(len(shape) - 2):
        numbers = chain.from_iterable(numbers)
    return np.fromiter(numbers, dtype=np.float64, count=math.prod(shape)).reshape(shape)


def _plain_polygons(raw_polygons: list, source: str) -> tuple[Polygon, ...] | None:
    """Every polygon checked at once, or None when the batch does not apply (fewer than
    PLAIN_BATCH_MIN polygons, holes, over PLAIN_BATCH_MAX_VERTICES vertices, anything not
    plain lists of numbers) or when a polygon breaks a rule: the polygon-by-polygon path
    then runs and names the first broken rule in the file's words."""
    n = len(raw_polygons)
    if n < PLAIN_BATCH_MIN:
        return None
    if not all(type(r) is dict and r.keys() == _PLAIN_KEYS for r in raw_polygons):
        return None
    verts = [r["vertices"] for r in raw_polygons]
    colors = [r["color"] for r in raw_polygons]
    if not all(type(v) is list and 3 <= len(v) <= PLAIN_BATCH_MAX_VERTICES for v in verts):
        return None
    if not all(type(c) is list and len(c) == 3 for c in colors):
        return None
    points = list(chain.from_iterable(verts))  # (iterated in C: a Python loop over 300,000 points took a second)
    if set(map(type, points)) != {list} or set(map(len, points)) != {3}:
        return None
    if not set(map(type, chain.from_iterable(points))) | set(map(type, chain.from_iterable(colors))) <= {float, int}:
        return None
    try:
        color = _floats(colors, n, 3)
    except OverflowError:
        return None
    if not (np.isfinite(color).all() and (color >= 0.0).all() and (color <= 1.0).all()):
        return None
    lengths = np.fromiter((len(v) for v in verts), dtype=np.int64, count=n)
    vertices: list = [None] * n
    planes = np.empty((n, 3))
    one_by_one = []  # fits too thin for the batch's SVD test, or outlines of 4+ vertices to check for crossings
    for k in np.unique(lengths).tolist():
        idx = np.flatnonzero(lengths == k)
        try:
            v = _floats([verts[i] for i in idx.tolist()], len(idx), k, 3)
        except OverflowError:
            return None
        if not np.isfinite(v).all() or np.abs(v).max() > MAX_COORDINATE:
            return None
        if np.all(v == np.roll(v, -1, axis=1), axis=2).any():  # a repeated vertex
            return None
        centre = v.mean(axis=1)
        centred = v - centre[:, None, :]
        size = np.ptp(v, axis=1).max(axis=1)
        if k == 3:
            # the fit is thinner than 1e-12 of its length only for a sliver; a triangle of
            # area above 1e-6 size^2 is far from that, and the rest (few) take the
            # single-polygon test, SVD and exact collinearity (an SVD of each of 100,000
            # triangles was a second)
            cross = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
            one_by_one.extend(idx[np.sqrt(np.einsum("mj,mj->m", cross, cross)) <= 1e-6 * size * size].tolist())
        else:
            _, sing, axes = np.linalg.svd(centred, full_matrices=False)
            thin = (size == 0.0) | (sing[:, 1] <= 1e-12 * sing[:, 0])
            distance = np.abs(np.einsum("mkj,mj->mk", centred, axes[:, 2, :]))
            if (distance.max(axis=1)[~thin] > PLANARITY_RTOL * size[~thin]).any():
                return None
            one_by_one.extend(idx.tolist())
        # the plane as _plane_of computes it (Newell's normal about the mean)
        nxt = np.roll(centred, -1, axis=1)
        normal = np.stack([
            np.sum((centred[:, :, 1] - nxt[:, :, 1]) * (centred[:, :, 2] + nxt[:, :, 2]), axis=1),
            np.sum((centred[:, :, 2] - nxt[:, :, 2]) * (centred[:, :, 0] + nxt[:, :, 0]), axis=1),
            np.sum((centred[:, :, 0] - nxt[:, :, 0]) * (centred[:, :, 1] + nxt[:, :, 1]), axis=1),
        ], axis=1)
        extent = np.ptp(v[:, :, :2], axis=1).max(axis=1)
        edge_on = np.abs(normal[:, 2]) <= 1e-12 * np.maximum(extent, 1.0) ** 2
        with np.errstate(divide="ignore", invalid="ignore"):
            a, b = -normal[:, 0] / normal[:, 2], -normal[:, 1] / normal[:, 2]
            plane = np.stack([a, b, centre[:, 2] - a * centre[:, 0] - b * centre[:, 1]], axis=1)
        plane[edge_on] = np.nan
        planes[idx] = plane
        for i, row in zip(idx.tolist(), v):
            vertices[i] = row
    for i in sorted(one_by_one):  # the rules the batch leaves to the single-polygon checks
        try:
            check_simple(check_planar(vertices[i], ""), "")
        except SceneError:
            return None
    return tuple(map(Polygon, vertices, color, range(n), planes))


# --- checks -------------------------------------------------------------------------


def _hole_rings(raw: Any, outer: np.ndarray, where: str) -> list[np.ndarray]:
    """The holes as (n, 3) arrays, after every rule of the format's ``holes`` key."""
    if not isinstance(raw, list):
        raise SceneError(f"{where}.holes: expected a list of rings, each a list of [x, y, z] points")
    centre = outer.mean(axis=0)
    _, _, axes = np.linalg.svd(outer - centre, full_matrices=False)
    size = float(np.ptp(outer, axis=0).max())
    flat = [(outer - centre) @ axes[:2].T]  # every ring in the outer ring's own plane
    rings = []
    for h, ring_raw in enumerate(raw):
        here = f"{where}.holes[{h}]"
        ring = _ring(ring_raw, here)
        distance = np.abs((ring - centre) @ axes[2])
        if distance.max() > PLANARITY_RTOL * size:
            j = int(distance.argmax())
            raise SceneError(f"{here}: hole is not in the polygon's plane (vertex {j} lies {distance.max():.3g} from it)")
        xy = (ring - centre) @ axes[:2].T
        check_simple(xy, here)
        if abs(ring_area(xy)) <= SLIVER_RTOL * size * size:
            raise SceneError(f"{here}: degenerate hole (no area)")
        rings.append(ring)
        flat.append(xy)
    _check_rings_apart(flat, where)
    return rings


def _ring(raw: Any, where: str) -> np.ndarray:
    if not isinstance(raw, list):
        raise SceneError(f"{where}: expected a list of [x, y, z] points")
    if len(raw) < 3:
        raise SceneError(f"{where}: a hole needs at least 3 vertices, got {len(raw)}")
    ring = point_list(raw, where)
    if np.abs(ring).max() > MAX_COORDINATE:
        raise SceneError(f"{where}: coordinates beyond +-{MAX_COORDINATE:g} are not supported")
    check_no_repeats(ring, where)
    return ring


def _check_rings_apart(flat: list[np.ndarray], where: str) -> None:
    """Holes strictly inside the outer ring (``flat[0]``), and holes apart from each other.

    Rings that neither cross nor touch are nested or disjoint, so one vertex decides:
    a hole's first vertex must lie inside the outer ring and outside every other hole.

    The rules are those of every pair (hole a, ring b < a), and the error is the first
    broken pair in that order; but only pairs whose boxes overlap can break one (rings with
    disjoint boxes neither meet nor hold each other's vertices), and one sweep over all the
    rings (``rings_contact``) says whether any two meet at all. So a valid polygon costs a
    sweep, one point-in-ring test per hole against the outer ring, and a test per pair of
    holes with overlapping boxes, found by sorting the boxes: 2,000 holes took minutes
    pair by pair. Only a polygon that breaks a rule is walked pair by pair, over those
    pairs, to name the first.
    """
    if len(flat) < 2:
        return
    boxes = np.array([np.concatenate([r[:, :2].min(axis=0), r[:, :2].max(axis=0)]) for r in flat])
    partners = _overlapping_boxes(boxes[1:])  # among the holes (hole indices from 0)
    firsts = np.array([r[0, :2] for r in flat[1:]])
    inside_outer = np.concatenate([points_inside(firsts[k : k + 256], flat[0]) for k in range(0, len(firsts), 256)])
    nested = any(_inside(flat[1 + a][0], flat[1 + b]) or _inside(flat[1 + b][0], flat[1 + a]) for a, b in partners)
    if inside_outer.all() and not nested and rings_contact(flat) is None:
        return
    later: dict[int, list[int]] = {}
    for a, b in partners:
        later.setdefault(a + 1, []).append(b + 1)
    names = ["the outer ring"] + [f"holes[{h}]" for h in range(len(flat) - 1)]
    for a in range(1, len(flat)):
        for b in [0, *sorted(later.get(a, []))]:
            meet = _rings_meet(flat[a], flat[b])
            if meet is not None:
                raise SceneError(
                    f"{where}.{names[a]}: hole crosses or touches {names[b]} (its edge {meet[0]} meets edge {meet[1]})"
                )
            inside = _inside(flat[a][0], flat[b])
            if b == 0 and not inside:
                raise SceneError(f"{where}.{names[a]}: hole lies outside the outer ring")
            if b > 0 and (inside or _inside(flat[b][0], flat[a])):
                raise SceneError(f"{where}.{names[a]}: hole overlaps {names[b]} (one lies inside the other)")


def _overlapping_boxes(boxes: np.ndarray) -> list[tuple[int, int]]:
    """Pairs ``(a, b)``, ``b < a``, of boxes (x0, y0, x1, y1) that overlap or touch: sorted
    by x0, each box meets only those after it that start before it ends."""
    order = np.argsort(boxes[:, 0], kind="stable")
    x0 = boxes[order, 0]
    ends = np.searchsorted(x0, boxes[order, 2], side="right")
    pairs = []
    for i in range(len(order)):
        p = order[i]
        for q in order[i + 1 : ends[i]].tolist():
            if boxes[q, 1] <= boxes[p, 3] and boxes[p, 1] <= boxes[q, 3]:
                pairs.append((max(p, q), min(p, q)))
    return pairs


def _rings_meet(p: np.ndarray, q: np.ndarray) -> tuple[int, int] | None:
    """The first (edge of p, edge of q) pair that shares a point, or None (both rings simple)."""
    if (p.min(axis=0) > q.max(axis=0)).any() or (q.min(axis=0) > p.max(axis=0)).any():
        return None
    hit = rings_contact([p, q])  # O(n log n) sweep line, shared with the format's simplicity check
    if hit is None:
        return None
    ring_a, edge_a, _, edge_b = hit
    return (edge_a, edge_b) if ring_a == 0 else (edge_b, edge_a)


def _inside(point: np.ndarray, ring: np.ndarray) -> bool:
    """Even-odd test of a point not on the ring's boundary."""
    return bool(points_inside(np.asarray(point)[None, :2], ring)[0])


def points_inside(points: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Even-odd test of many points (m, 2) against a ring (n, 2); a point on the
    boundary may come out either way."""
    x, y = points[:, 0, None], points[:, 1, None]
    a, b = ring[None, :, :2], next_vertices(ring)[None, :, :2]
    straddle = (a[..., 1] > y) != (b[..., 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        cross_x = a[..., 0] + (y - a[..., 1]) * (b[..., 0] - a[..., 0]) / (b[..., 1] - a[..., 1])
    return (np.count_nonzero(straddle & (cross_x > x), axis=1) % 2).astype(bool)


# --- pieces -------------------------------------------------------------------------


def _cut_into_pieces(polygon: Polygon, holes: list[np.ndarray], where: str) -> list[np.ndarray]:
    """Convex pieces (each (k, 3), x y z) sharing the rings' vertices, covering exactly the polygon."""
    import mapbox_earcut

    rings = [polygon.vertices, *holes]
    if not np.isfinite(polygon.plane).all():
        return [polygon.vertices]  # seen edge-on: covers nothing, one piece keeps it listed
    points = np.concatenate(rings)
    ends = np.cumsum([len(r) for r in rings]).astype(np.uint32)
    faces = mapbox_earcut.triangulate_float64(np.ascontiguousarray(points[:, :2]), ends).reshape(-1, 3)
    tri = points[faces]  # (m, 3, 3)
    e1, e2 = tri[:, 1, :2] - tri[:, 0, :2], tri[:, 2, :2] - tri[:, 0, :2]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    size = float(np.ptp(polygon.xy, axis=0).max())
    expected = abs(ring_area(polygon.xy)) - sum(abs(ring_area(h[:, :2])) for h in holes)
    if abs(area.sum() - expected) > CUT_RTOL * max(expected, size * size):
        raise SceneError(
            f"{where}: could not be cut into pieces (triangles cover {area.sum():.12g}, the polygon {expected:.12g})"
        )
    keep = area > SLIVER_RTOL * size * size
    return [points[cycle] for cycle in convex_pieces(points[:, :2], faces[keep])]


def convex_pieces(xy: np.ndarray, faces: np.ndarray) -> list[list[int]]:
    """Triangles merged across their shared edges into convex pieces (Hertel & Mehlhorn).

    A shared edge is removed when both of its end points stay convex in the merged piece,
    so every piece stays convex, and there are at most four times as many pieces as the
    fewest convex pieces could be: far fewer polygons and edges for the renderers than
    the triangles, with the same vertices, so the pieces still abut exactly.
    Returns each piece as a counter-clockwise (y up) cycle of indices into ``xy``.
    """

    xs, ys = xy[:, 0].tolist(), xy[:, 1].tolist()  # Python floats: the same float64 arithmetic, no array indexing

    def cross(o, a, b):
        return (xs[a] - xs[o]) * (ys[b] - ys[o]) - (ys[a] - ys[o]) * (xs[b] - xs[o])

    # every triangle counter-clockwise, at once (elementwise float64: the bits of ``cross``)
    x, y = xy[faces, 0], xy[faces, 1]
    turn = (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (y[:, 1] - y[:, 0]) * (x[:, 2] - x[:, 0])
    cycles = np.where((turn > 0)[:, None], faces, faces[:, [0, 2, 1]])
    pieces: dict[int, list[int]] = dict(enumerate(cycles.tolist()))
    starts, ends = cycles.ravel().tolist(), cycles[:, [1, 2, 0]].ravel().tolist()
    owner: dict[tuple[int, int], int] = dict(zip(zip(starts, ends), np.repeat(np.arange(len(faces)), 3).tolist()))  # directed edge -> piece
    for a, b in list(owner):
        p, q = owner.get((a, b)), owner.get((b, a))
        if p is None or q is None or p == q:
            continue
        P, Q = pieces[p], pieces[q]
        i, j = P.index(a), Q.index(b)
        ring_p = P[i + 1 :] + P[: i + 1]  # b ... a
        ring_q = Q[j + 1 :] + Q[: j + 1]  # a ... b
        merged = ring_p + ring_q[1:-1]
        n = len(merged)
        if len(set(merged)) != n:
            continue
        ia = len(ring_p) - 1  # a; b is at 0
        if cross(merged[ia - 1], a, merged[(ia + 1) % n]) < 0 or cross(merged[-1], b, merged[1]) < 0:
            continue
        pieces[p] = merged
        del pieces[q]
        owner.pop((a, b))
        owner.pop((b, a))
        for k in range(n):
            owner[(merged[k], merged[(k + 1) % n])] = p
    return list(pieces.values())
