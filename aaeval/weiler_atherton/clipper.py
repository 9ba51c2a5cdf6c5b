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

import math
from typing import NamedTuple

import numpy as np

from aaeval.native.weiler_atherton import clip_arrays, first_crossing, ring_area_of, winding

__all__ = [
    "Shape",
    "InvalidShapeError",
    "clip",
    "shape_area",
    "ring_area",
    "oriented",
    "polygons",
    "tolerance",
    "to_arrays",
    "from_arrays",
]

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
    if len(ring) < 3:
        return 0.0
    xy = np.asarray(ring, dtype=np.float64)
    return float(ring_area_of(np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]), 0, len(ring)))


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


class InvalidShapeError(ValueError):
    """A shape the clipper cannot take: each contour needs 3 or more finite vertices, and
    no two edges may cross (a contour may touch itself or another one, not cross)."""


def to_arrays(shape: Shape):
    """The shape as the kernels' four arrays (xs, ys, labels, starts)."""
    lengths = [len(r) for r in shape.rings]
    starts = np.zeros(len(lengths) + 1, dtype=np.int64)
    np.cumsum(lengths, out=starts[1:])
    n = int(starts[-1])
    xy = np.array([p for r in shape.rings for p in r], dtype=np.float64).reshape(n, 2)
    labels = np.array([lab for labs in shape.labels for lab in labs], dtype=np.int64)
    return np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]), labels, starts


def from_arrays(xs, ys, labels, starts) -> Shape:
    """A shape (lists of point tuples) from the kernels' arrays."""
    pts = list(zip(xs.tolist(), ys.tolist()))
    labs = labels.tolist()
    bounds = starts.tolist()
    return Shape([pts[a:b] for a, b in zip(bounds, bounds[1:])], [labs[a:b] for a, b in zip(bounds, bounds[1:])])


def check_shape(shape: Shape, name: str, eps: float) -> None:
    """Refuse a shape the clipper would answer wrongly (see :class:`InvalidShapeError`)."""
    if len(shape.labels) != len(shape.rings):
        raise InvalidShapeError(f"{name}: {len(shape.rings)} contours but {len(shape.labels)} label lists")
    for i, (r, lab) in enumerate(zip(shape.rings, shape.labels)):
        if len(r) < 3:
            raise InvalidShapeError(f"{name}: contour {i} has {len(r)} vertices; a contour needs at least 3")
        if len(lab) != len(r):
            raise InvalidShapeError(f"{name}: contour {i} has {len(r)} vertices but {len(lab)} edge labels")
    xs, ys, _, starts = to_arrays(shape)
    if not (np.isfinite(xs).all() and np.isfinite(ys).all()):
        raise InvalidShapeError(f"{name}: vertex coordinates must be finite numbers")
    u, w = first_crossing(xs, ys, starts, eps)
    if u >= 0:
        ru = int(np.searchsorted(starts, u, side="right")) - 1
        rw = int(np.searchsorted(starts, w, side="right")) - 1
        raise InvalidShapeError(
            f"{name} is self-crossing: edge {u - starts[ru]} of contour {ru} crosses edge "
            f"{w - starts[rw]} of contour {rw} (contours must neither cross themselves nor each other)"
        )


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

    Raises
    ------
    InvalidShapeError
        A contour with fewer than 3 vertices, a non-finite coordinate, or two edges of
        one shape crossing (a self-crossing contour, or a hole crossing its main contour):
        no fill rule makes such input a region, so no answer would be right.
    """
    if eps is None:
        eps = tolerance(subject, clipper)
    check_shape(subject, "subject", eps)
    check_shape(clipper, "clip shape", eps)
    if not subject.rings:
        return Shape([], []), Shape([], [])
    if not clipper.rings:
        return Shape([], []), subject
    out = clip_arrays(*to_arrays(subject), *to_arrays(clipper), float(eps))
    return from_arrays(*out[:4]), from_arrays(*out[4:])


def _winding(px: float, py: float, rings) -> int:
    """Winding number of the point about the oriented contours (1 inside a shape)."""
    xs, ys, _, starts = to_arrays(Shape(rings, [[0] * len(r) for r in rings]))
    return int(winding(float(px), float(py), xs, ys, starts))


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
