"""Filled regions from outlines: fill rules and strokes resolved by Skia's path operations.

The curves are flattened by :mod:`aaeval.importers.flatten` before Skia sees them, and
Skia's output (a stroke's round joins and caps) is flattened the same way, so every
vertex count is ours. ``skia.Simplify`` turns a path under its fill rule (nonzero or
even-odd) into contours that neither cross nor overlap; :func:`nest` sorts those into
outer rings and holes. Skia holds coordinates as float32, so imported vertices are
float32 values (a few 1e-6 px off the flattened curve at a few hundred px).
"""

from __future__ import annotations

from typing import Iterable, NamedTuple

import numpy as np
import skia

from aaeval.importers.flatten import bezier_points, conic_points
from aaeval.scenes.holes import points_inside, ring_area

__all__ = ["Subpath", "Region", "fill_regions", "stroke_regions", "nest", "STROKE_CAPS", "STROKE_JOINS"]

# Rings smaller than this (px^2) are Skia's rounding crumbs, not content.
CRUMB_AREA = 1e-9

STROKE_CAPS = {"butt": skia.Paint.kButt_Cap, "round": skia.Paint.kRound_Cap, "square": skia.Paint.kSquare_Cap}
STROKE_JOINS = {"miter": skia.Paint.kMiter_Join, "round": skia.Paint.kRound_Join, "bevel": skia.Paint.kBevel_Join}


class Subpath(NamedTuple):
    """A flattened subpath: points (n, 2) float64, and whether it is closed."""

    points: np.ndarray
    closed: bool


class Region(NamedTuple):
    """A simple outer ring with the holes inside it, each (n, 2)."""

    outer: np.ndarray
    holes: list


def fill_regions(subpaths: Iterable[Subpath], rule: str) -> list[Region]:
    """The area a set of subpaths fills under ``rule`` (``"nonzero"`` or ``"evenodd"``)."""
    if rule not in ("nonzero", "evenodd"):
        raise ValueError(f"unknown fill rule {rule!r}; use nonzero or evenodd")
    path = _skia_path((s.points, True) for s in subpaths)
    path.setFillType(skia.PathFillType.kWinding if rule == "nonzero" else skia.PathFillType.kEvenOdd)
    return _regions_of(path)


def stroke_regions(
    subpaths: Iterable[Subpath], width: float, *, cap: str = "butt", join: str = "miter",
    miter_limit: float = 4.0, tol: float,
) -> list[Region]:
    """The area a stroke of ``width`` along the subpaths covers (SVG stroke geometry)."""
    path = _skia_path((s.points, s.closed) for s in subpaths)
    paint = skia.Paint(
        Style=skia.Paint.kStroke_Style, StrokeWidth=float(width), StrokeCap=STROKE_CAPS[cap],
        StrokeJoin=STROKE_JOINS[join], StrokeMiter=float(miter_limit),
    )
    outline = skia.Path()
    paint.getFillPath(path, outline)
    flat = _skia_path((ring, True) for ring in flatten_skia_path(outline, tol))
    flat.setFillType(skia.PathFillType.kWinding)  # a stroke covers where any part of it is
    return _regions_of(flat)


def flatten_skia_path(path: skia.Path, tol: float) -> list[np.ndarray]:
    """Every contour of a Skia path as a closed ring of points, curves flattened to ``tol``."""
    rings, current = [], []
    iterator = skia.Path.Iter(path, True)
    while True:
        verb, points = iterator.next()
        if verb == skia.Path.kDone_Verb:
            break
        pts = np.array([(p.x(), p.y()) for p in points], dtype=np.float64)
        if verb == skia.Path.kMove_Verb:
            if len(current) >= 3:
                rings.append(np.array(current))
            current = [pts[0]]
        elif verb == skia.Path.kLine_Verb:
            current.append(pts[1])
        elif verb == skia.Path.kQuad_Verb or verb == skia.Path.kCubic_Verb:
            current.extend(bezier_points(pts, tol))
        elif verb == skia.Path.kConic_Verb:
            current.extend(conic_points(pts[0], pts[1], pts[2], iterator.conicWeight(), tol))
        elif verb == skia.Path.kClose_Verb:
            if len(current) >= 3:
                rings.append(np.array(current))
            current = []
    if len(current) >= 3:
        rings.append(np.array(current))
    return [r for r in (_clean(r) for r in rings) if r is not None]


def nest(rings: list[np.ndarray]) -> list[Region]:
    """Sort non-crossing rings into outer rings (even nesting depth) and their holes.

    A ring lies inside another when most of its vertices do (rings from ``Simplify`` may
    touch at a vertex, never cross); its container is the smallest ring holding it.
    """
    order = sorted(range(len(rings)), key=lambda i: -abs(ring_area(rings[i])))
    lo = [r.min(axis=0) for r in rings]
    hi = [r.max(axis=0) for r in rings]
    depth, regions, region_of = {}, [], {}
    placed: list[int] = []
    for i in order:
        container = None
        for j in reversed(placed):  # smallest first
            if np.all(lo[j] <= lo[i]) and np.all(hi[i] <= hi[j]) and points_inside(rings[i], rings[j]).mean() > 0.5:
                container = j
                break
        depth[i] = 0 if container is None else depth[container] + 1
        if depth[i] % 2 == 0:
            region_of[i] = len(regions)
            regions.append(Region(rings[i], []))
        else:
            regions[region_of[container]].holes.append(rings[i])
        placed.append(i)
    return regions


def _skia_path(contours) -> skia.Path:
    path = skia.Path()
    for points, closed in contours:
        if len(points) < 2:
            continue
        path.moveTo(float(points[0][0]), float(points[0][1]))
        for x, y in points[1:]:
            path.lineTo(float(x), float(y))
        if closed:
            path.close()
    return path


def _regions_of(path: skia.Path) -> list[Region]:
    simple = skia.Simplify(path)
    if simple is None:
        raise ValueError("Skia could not resolve the fill of a path")
    # Simplify's output is made of lines only (its input was), so tol is never used
    return nest(flatten_skia_path(simple, tol=1.0))


def _clean(ring: np.ndarray) -> np.ndarray | None:
    """Drop repeated vertices (the closing one too); None for a ring without area."""
    keep = np.any(ring != np.roll(ring, 1, axis=0), axis=1)
    ring = ring[keep]
    if len(ring) < 3 or abs(ring_area(ring)) <= CRUMB_AREA:
        return None
    return ring
