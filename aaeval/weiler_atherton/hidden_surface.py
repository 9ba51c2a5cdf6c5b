"""Weiler & Atherton (1977) hidden-surface removal by polygon area sorting.

The steps of the paper, per window:

a) a rough depth sort (nearest z first; on a tie the later polygon in the file first);
b) the first polygon's *original, unclipped* outline clips every piece on the list into
   an inside and an outside list (the x-y sort);
c) inside pieces behind the clip polygon are removed; a piece whose depth plane crosses
   the clip polygon's is first split along the line where the planes cross;
d) a piece left in front of the clip polygon means the depth sort was wrong: the inside
   list is solved again recursively with that piece's polygon as the clip polygon,
   unless its polygon is on the stack of clip polygons still being processed (cyclic
   overlap: everything behind it has already been removed).

Then the outside list is processed the same way until it is empty. The output pieces do
not overlap. :func:`visible_pieces` adds the paper's screen subdivision: the image is cut
Warnock-style into windows holding at most ``window`` polygons, each solved separately.

Each window is solved by the native solver (``aaeval.native.weiler_atherton.solve_window``,
C++ in ``src/weiler_atherton/solver.cpp`` on the clipper of ``clipper.cpp``, and for
convex pieces clipped by convex outlines the shorter road of ``convex.hpp``); this module
prepares the problem and hands back the pieces, as flat arrays (:func:`visible_arrays`,
for the renderer) or as :class:`Piece` objects.

Edge labels (see :mod:`.clipper`) record where each output edge came from:
:data:`EDGE_OWN` an edge of the piece's own polygon, :data:`EDGE_CROSSING` the line where
its plane crosses another polygon's, :data:`EDGE_CUT` a cut made by clipping (another
polygon's outline or a window border).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from aaeval.native.weiler_atherton import EDGE_CROSSING, EDGE_CUT, EDGE_OWN, originals, solve_window
from aaeval.scenes import Scene
from aaeval.scenes.depth import depth_tolerance
from aaeval.weiler_atherton.clipper import Shape, from_arrays, ring_area, to_arrays
from aaeval.weiler_atherton.near_ties import solve_by_rule, tie_groups

__all__ = [
    "Piece",
    "VisibleArrays",
    "visible_pieces",
    "visible_arrays",
    "hidden_surface",
    "EDGE_OWN",
    "EDGE_CROSSING",
    "EDGE_CUT",
]


class Piece(NamedTuple):
    """Part of one scene polygon: oriented contours (holes included), its source index
    into ``scene.polygons`` and its bounding box ``(x0, y0, x1, y1)``."""

    shape: Shape
    source: int
    bbox: tuple[float, float, float, float]

    @property
    def area(self) -> float:
        return sum(ring_area(r) for r in self.shape.rings)


class VisibleArrays(NamedTuple):
    """The visible pieces flattened, as the compiled solver returns them: contour k is
    vertices ``starts[k]:starts[k + 1]`` (``labels[v]`` labels the edge leaving vertex v),
    piece i is contours ``piece_rings[i]:piece_rings[i + 1]`` of polygon ``sources[i]``."""

    xs: np.ndarray
    ys: np.ndarray
    labels: np.ndarray
    starts: np.ndarray
    piece_rings: np.ndarray
    sources: np.ndarray

    @staticmethod
    def concatenate(parts: list["VisibleArrays"]) -> "VisibleArrays":
        if len(parts) == 1:
            return parts[0]
        xs, ys, labels, starts, piece_rings, sources = [], [], [], [np.zeros(1, np.int64)], [np.zeros(1, np.int64)], []
        nv = nr = 0
        for p in parts:
            xs.append(p.xs)
            ys.append(p.ys)
            labels.append(p.labels)
            starts.append(p.starts[1:] + nv)
            piece_rings.append(p.piece_rings[1:] + nr)
            sources.append(p.sources)
            nv += len(p.xs)
            nr += len(p.starts) - 1
        cat = np.concatenate
        return VisibleArrays(cat([np.zeros(0)] + xs), cat([np.zeros(0)] + ys), cat([np.zeros(0, np.int64)] + labels),
                             cat(starts), cat(piece_rings), cat([np.zeros(0, np.int64)] + sources))

    @staticmethod
    def of_shapes(regions: list[tuple[int, Shape]]) -> "VisibleArrays":
        """Flat arrays of ``[(source, shape), ...]``."""
        parts = []
        for source, shape in regions:
            xs, ys, labels, starts = to_arrays(shape)
            parts.append(VisibleArrays(xs, ys, labels, starts, np.array([0, len(starts) - 1], np.int64),
                                       np.array([source], np.int64)))
        return VisibleArrays.concatenate(parts) if parts else VisibleArrays.concatenate([])

    def pieces(self) -> list[Piece]:
        out = []
        for i, source in enumerate(self.sources.tolist()):
            r0, r1 = self.piece_rings[i], self.piece_rings[i + 1]
            v0, v1 = self.starts[r0], self.starts[r1]
            shape = from_arrays(self.xs[v0:v1], self.ys[v0:v1], self.labels[v0:v1], self.starts[r0 : r1 + 1] - v0)
            xs, ys = self.xs[v0:v1], self.ys[v0:v1]
            out.append(Piece(shape, source, (float(xs.min()), float(ys.min()), float(xs.max()), float(ys.max()))))
        return out


class _Problem:
    """One hidden-surface problem as the compiled solver takes it: every polygon's
    original outline (oriented, positive area), box, depth plane, and the tolerances.
    Polygons seen edge-on cover nothing and are left out (an empty outline)."""

    def __init__(self, scene: Scene):
        arrays = scene.arrays
        self.planes = np.ascontiguousarray(arrays.planes, dtype=np.float64)
        vertices = np.ascontiguousarray(arrays.vertices, dtype=np.float64).reshape(-1, 3)
        self.xs, self.ys, self.starts, self.bboxes, self.zmin, scale, _ = originals(
            vertices, np.ascontiguousarray(arrays.start, dtype=np.int64),
            np.ascontiguousarray(arrays.length, dtype=np.int64), self.planes
        )
        self.sources = np.flatnonzero(np.diff(self.starts) > 0)
        # the scene format's tie band, as every method uses it
        self.eps_z = depth_tolerance(vertices[:, 2])
        self.eps = 2e-14 * max(1.0 + max(scene.width, scene.height), scale)
        # the file's polygon each one stands for (a polygon with holes stands as abutting
        # pieces, which the solver need not clip against each other)
        self.group = np.arange(len(self.planes), dtype=np.int64)
        for h in scene.holed:
            self.group[h.first : h.first + h.count] = h.first

    def depth_order(self, sources) -> np.ndarray:
        """A rough depth sort: nearest z first, the later polygon first on a tie."""
        sources = np.asarray(sources, dtype=np.int64)
        return sources[np.lexsort((-sources, self.zmin[sources]))]

    def solve(self, window, sources=None, convex: bool = True) -> VisibleArrays:
        """Visible pieces inside ``window``: near-coplanar groups by the tie rule
        (:mod:`.near_ties`), the rest by the area sort."""
        tied, rest = tie_groups(self.bboxes, self.planes, self.sources if sources is None else sources, self.eps_z)
        order = self.depth_order(rest)
        win = tuple(float(v) for v in window)
        sorted_ = VisibleArrays(*solve_window(self.xs, self.ys, self.starts, self.bboxes, self.planes, order, win,
                                              self.eps, self.eps_z, bool(convex), self.group))
        if len(tied):
            regions = solve_by_rule(self.xs, self.ys, self.starts, self.bboxes, self.planes, win, tied, self.eps,
                                    self.eps_z)
            sorted_ = VisibleArrays.concatenate([sorted_, VisibleArrays.of_shapes(regions)])
        return sorted_


def hidden_surface(scene: Scene, window: tuple[float, float, float, float] | None = None, sources=None) -> list[Piece]:
    """Visible pieces of the scene inside one window (default: the image), no subdivision."""
    return _Problem(scene).solve(window or (0.0, 0.0, float(scene.width), float(scene.height)), sources).pieces()


def visible_pieces(scene: Scene, *, window: int = 0, convex: bool = True) -> list[Piece]:
    """Non-overlapping visible pieces of every polygon inside the image.

    Parameters
    ----------
    scene : Scene
    window : int
        Screen subdivision: largest number of polygons a window may hold before it is cut
        into four (0: solve the whole image at once). Windows stop shrinking at one pixel,
        or where cutting them no longer separates their polygons (see ``SPLIT_GAIN``).
    convex : bool
        Clip a convex piece by a convex outline edge line by edge line, the outside then
        coming as convex pieces (``src/weiler_atherton/convex.hpp``; the same regions, faster); False
        clips every pair with the paper's clipper.
    """
    return visible_arrays(scene, window=window, convex=convex).pieces()


def visible_arrays(scene: Scene, *, window: int = 0, convex: bool = True) -> VisibleArrays:
    """:func:`visible_pieces` as flat arrays (what the renderer needs, without building
    Python contours)."""
    if window < 0:
        raise ValueError(f"window must be >= 0, got {window}")
    problem = _Problem(scene)
    full = (0, 0, scene.width, scene.height)
    if window == 0:
        return problem.solve(full, convex=convex)
    out = []
    boxes = problem.bboxes
    todo = [(full, [s for s in problem.sources if _overlaps(boxes[s], full)])]
    while todo:
        win, here = todo.pop()
        children = _quarters(win)
        parts = [(w, [s for s in here if _overlaps(boxes[s], w)]) for w in children]
        crowded = sum(len(c) for _, c in parts) > SPLIT_GAIN * len(children) * len(here)
        if len(here) <= window or len(children) == 1 or crowded:
            out.append(problem.solve(win, here, convex))
            continue
        todo.extend((w, c) for w, c in parts if c)
    return VisibleArrays.concatenate(out) if out else problem.solve(full, [], convex)


# a window is split only while that separates its polygons: when its quarters would still
# hold on average more than this share of them (polygons larger than the window, the
# case of deep scenes), splitting on down to single pixels only multiplies the clipping
# (1000 triangles of 60 px in 256x256 with window=8: 62 s instead of 4 s unsplit)
SPLIT_GAIN = 0.75


def _quarters(win) -> list[tuple[int, int, int, int]]:
    """The window cut in two along each side longer than one pixel (itself if neither)."""
    x0, y0, x1, y1 = win
    xm = (x0 + x1) // 2 if x1 - x0 > 1 else None
    ym = (y0 + y1) // 2 if y1 - y0 > 1 else None
    xs = [(x0, xm), (xm, x1)] if xm is not None else [(x0, x1)]
    ys = [(y0, ym), (ym, y1)] if ym is not None else [(y0, y1)]
    return [(a, c, b, d) for a, b in xs for c, d in ys]


def _overlaps(bb, win) -> bool:
    return bb[0] < win[2] and bb[2] > win[0] and bb[1] < win[3] and bb[3] > win[1]
