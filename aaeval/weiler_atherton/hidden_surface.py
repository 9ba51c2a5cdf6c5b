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

Edge labels (see :mod:`.clipper`) record where each output edge came from:
:data:`EDGE_OWN` an edge of the piece's own polygon, :data:`EDGE_CROSSING` the line where
its plane crosses another polygon's, :data:`EDGE_CUT` a cut made by clipping (another
polygon's outline or a window border).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from aaeval.scenes import Scene
from aaeval.weiler_atherton.clipper import Shape, clip, oriented, ring_area

__all__ = ["Piece", "visible_pieces", "hidden_surface", "EDGE_OWN", "EDGE_CROSSING", "EDGE_CUT"]

EDGE_CUT = 0
EDGE_OWN = 1
EDGE_CROSSING = 2

FRONT, BEHIND = -1, 1


class Piece(NamedTuple):
    """Part of one scene polygon: oriented contours (holes included), its source index
    into ``scene.polygons`` and its bounding box ``(x0, y0, x1, y1)``."""

    shape: Shape
    source: int
    bbox: tuple[float, float, float, float]

    @classmethod
    def of(cls, shape: Shape, source: int) -> "Piece":
        # the box is kept with the piece: the x-y sort tests every piece against every
        # clip polygon, and recomputing boxes there was most of the run time
        return cls(shape, source, _shape_bbox(shape))

    @property
    def area(self) -> float:
        return sum(ring_area(r) for r in self.shape.rings)


class _Solver:
    """One hidden-surface problem: the original outlines and planes, and the tolerances."""

    def __init__(self, scene: Scene):
        self.planes = {}
        self.originals = {}
        self.bboxes = {}
        zmax = 0.0
        scale = 1.0 + max(scene.width, scene.height)
        for p in scene.polygons:
            if not np.isfinite(p.plane).all():
                continue  # seen edge-on: covers nothing
            self.planes[p.index] = tuple(float(v) for v in p.plane)
            shape = oriented([p.xy], label=EDGE_CUT)
            self.originals[p.index] = shape
            xs = [q[0] for q in shape.rings[0]]
            ys = [q[1] for q in shape.rings[0]]
            self.bboxes[p.index] = (min(xs), min(ys), max(xs), max(ys))
            zmax = max(zmax, float(np.abs(p.vertices[:, 2]).max()))
            scale = max(scale, float(np.abs(p.xy).max()))
        # same depth tolerance as the Catmull kernel: differences below it are one plane
        self.eps_z = 1e-11 * (1.0 + zmax)
        self.eps = 2e-14 * scale

    # -- step b: the x-y sort --------------------------------------------------------
    def clip_list(self, src: int, pieces: list[Piece]) -> tuple[list[Piece], list[Piece]]:
        cb = self.bboxes[src]
        clipper = self.originals[src]
        inside, outside = [], []
        for p in pieces:
            if p.source == src:  # a piece always lies in its own polygon's outline
                inside.append(p)
                continue
            bb = p.bbox
            if bb[0] >= cb[2] or bb[2] <= cb[0] or bb[1] >= cb[3] or bb[3] <= cb[1]:
                outside.append(p)
                continue
            ins, out = clip(p.shape, clipper, self.eps)
            if ins.rings:
                inside.append(Piece.of(ins, p.source))
            if out.rings:
                outside.append(Piece.of(out, p.source))
        return inside, outside

    # -- step c: depth comparison ---------------------------------------------------
    def relation(self, piece: Piece, src: int) -> int:
        """FRONT, BEHIND or 0 (planes cross inside the piece) relative to polygon src."""
        d = self._depth_differences(piece, src)
        front = any(v < -self.eps_z for v in d)
        behind = any(v > self.eps_z for v in d)
        if front and behind:
            return 0
        if front:
            return FRONT
        if behind:
            return BEHIND
        return FRONT if piece.source > src else BEHIND  # one plane: later in file in front

    def _depth_differences(self, piece: Piece, src: int):
        a, b, c = self.planes[piece.source]
        a2, b2, c2 = self.planes[src]
        da, db, dc = a - a2, b - b2, c - c2
        return [da * x + db * y + dc for r in piece.shape.rings for x, y in r]

    def depth_split(self, piece: Piece, src: int) -> list[tuple[Piece, int]]:
        """The piece as parts each wholly in front of or behind polygon src."""
        rel = self.relation(piece, src)
        if rel:
            return [(piece, rel)]
        a, b, c = self.planes[piece.source]
        a2, b2, c2 = self.planes[src]
        half = _half_plane(a - a2, b - b2, c - c2, piece.bbox)
        front, back = clip(piece.shape, half, self.eps)
        parts = []
        for shape, rel in ((front, FRONT), (back, BEHIND)):
            if shape.rings:
                parts.append((Piece.of(shape, piece.source), rel))
        return parts

    # -- steps b-d, recursively ----------------------------------------------------
    def solve(self, pieces: list[Piece], stack: tuple[int, ...] = ()) -> list[Piece]:
        visible = []
        while pieces:
            src = pieces[0].source
            inside, pieces = self.clip_list(src, pieces)
            visible.extend(self.resolve_inside(src, inside, stack))
        return visible

    def resolve_inside(self, src: int, inside: list[Piece], stack: tuple[int, ...]) -> list[Piece]:
        kept = []
        offenders = []
        for p in inside:
            if p.source == src:
                kept.append(p)
                continue
            for part, rel in self.depth_split(p, src):
                if rel == FRONT:
                    kept.append(part)
                    offenders.append(part)
        fresh = [p for p in offenders if p.source not in stack]
        if not fresh:
            # no offender, or only polygons on the stack (cyclic overlap): all that lay
            # behind them is gone already, so what is left does not overlap
            return kept
        first = fresh[0]
        return self.solve([first] + [p for p in kept if p is not first], stack + (src,))


def _shape_bbox(shape: Shape):
    xs = [p[0] for r in shape.rings for p in r]
    ys = [p[1] for r in shape.rings for p in r]
    return min(xs), min(ys), max(xs), max(ys)


def _half_plane(a: float, b: float, c: float, bbox) -> Shape:
    """The part ``a x + b y + c <= 0`` of the bounding box (grown by one unit), as a
    convex shape whose edge along the line is labelled EDGE_CROSSING."""
    x0, y0, x1, y1 = bbox[0] - 1, bbox[1] - 1, bbox[2] + 1, bbox[3] + 1
    box = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    if ring_area(box) < 0:
        box = box[::-1]
    pts, on_line = [], []
    for k in range(4):
        p, q = box[k], box[(k + 1) % 4]
        dp = a * p[0] + b * p[1] + c
        dq = a * q[0] + b * q[1] + c
        if dp <= 0:
            pts.append(p)
            on_line.append(dp == 0)
        if (dp < 0 < dq) or (dq < 0 < dp):
            t = dp / (dp - dq)
            pts.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
            on_line.append(True)
    n = len(pts)
    labels = [EDGE_CROSSING if on_line[k] and on_line[(k + 1) % n] else EDGE_CUT for k in range(n)]
    return Shape([pts], [labels])


def _rect(x0: float, y0: float, x1: float, y1: float) -> Shape:
    return Shape([[(x0, y0), (x1, y0), (x1, y1), (x0, y1)]], [[EDGE_CUT] * 4])


def _depth_order(scene: Scene, sources) -> list[int]:
    """Rough depth sort: nearest z first, the later polygon first on a tie."""
    return sorted(sources, key=lambda s: (float(scene.polygons[s].vertices[:, 2].min()), -s))


def hidden_surface(scene: Scene, window: tuple[float, float, float, float] | None = None, sources=None) -> list[Piece]:
    """Visible pieces of the scene inside one window (default: the image), no subdivision."""
    solver = _Solver(scene)
    return _solve_window(scene, solver, window or (0.0, 0.0, float(scene.width), float(scene.height)), sources)


def _solve_window(scene: Scene, solver: _Solver, window, sources=None) -> list[Piece]:
    rect = _rect(*window)
    if sources is None:
        sources = list(solver.originals)
    pieces = []
    for s in _depth_order(scene, sources):
        own = Shape(solver.originals[s].rings, [[EDGE_OWN] * len(r) for r in solver.originals[s].rings])
        ins = own if _within(solver.bboxes[s], window) else clip(own, rect, solver.eps)[0]
        if ins.rings:
            pieces.append(Piece.of(ins, s))
    return solver.solve(pieces)


def visible_pieces(scene: Scene, *, window: int = 0) -> list[Piece]:
    """Non-overlapping visible pieces of every polygon inside the image.

    Parameters
    ----------
    scene : Scene
    window : int
        Screen subdivision: largest number of polygons a window may hold before it is cut
        into four (0: solve the whole image at once). Windows stop shrinking at one pixel,
        or where cutting them no longer separates their polygons (see ``SPLIT_GAIN``).
    """
    if window < 0:
        raise ValueError(f"window must be >= 0, got {window}")
    solver = _Solver(scene)
    full = (0, 0, scene.width, scene.height)
    if window == 0:
        return _solve_window(scene, solver, full)
    out = []
    todo = [(full, [s for s in solver.originals if _overlaps(solver.bboxes[s], full)])]
    while todo:
        win, here = todo.pop()
        children = _quarters(win)
        parts = [(w, [s for s in here if _overlaps(solver.bboxes[s], w)]) for w in children]
        crowded = sum(len(c) for _, c in parts) > SPLIT_GAIN * len(children) * len(here)
        if len(here) <= window or len(children) == 1 or crowded:
            out.extend(_solve_window(scene, solver, win, here))
            continue
        todo.extend((w, c) for w, c in parts if c)
    return out


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


def _within(bb, win) -> bool:
    return bb[0] >= win[0] and bb[2] <= win[2] and bb[1] >= win[1] and bb[3] <= win[3]


def _overlaps(bb, win) -> bool:
    return bb[0] < win[2] and bb[2] > win[0] and bb[1] < win[3] and bb[3] > win[1]
