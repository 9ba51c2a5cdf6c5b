"""Filled regions from outlines: fill rules and strokes resolved in float64.

Fill rules (nonzero, even-odd) are resolved by :func:`aaeval.importers.fill.resolve_fill`
(an arrangement of the flattened outline's edges in float64: straight-edged input keeps
its exact coordinates, a crossing is one vertex rounded once). Strokes are built from the
true segments by :mod:`aaeval.importers.stroke` (offsets sampled to the tolerance, joins
decided on the true tangents) and their pieces united the same way. Skia is no longer
used here: its path operations round every coordinate to float32.
"""

from __future__ import annotations

from typing import Iterable, NamedTuple

import numpy as np

from aaeval.importers.fill import resolve_fill
from aaeval.importers.fillrings import ring_area
from aaeval.importers.limits import charge
from aaeval.importers.stroke import Seg, stroke_pieces

__all__ = ["Subpath", "Region", "fill_regions", "stroke_regions", "clip_regions", "STROKE_CAPS", "STROKE_JOINS",
           "Seg"]

STROKE_CAPS = ("butt", "round", "square")
STROKE_JOINS = ("miter", "round", "bevel")


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
    return [Region(outer, holes) for outer, holes in resolve_fill([s.points for s in subpaths], rule)]


def stroke_regions(
    subpaths, width: float, *, cap: str = "butt", join: str = "miter", miter_limit: float = 4.0, tol: float,
    transform=None,
) -> list[Region]:
    """The area a stroke of ``width`` along the subpaths covers (SVG stroke geometry).

    ``subpaths`` is a sequence of (list of :class:`Seg`, closed): the true segments, so
    joins are decided on true tangents and offsets sampled to ``tol``. ``transform``
    (optional) maps each piece's (n, 2) points: the stroke is outlined where the segments
    are (user space) and then transformed, as SVG draws a stroke under any transform.
    """
    pieces = stroke_pieces(subpaths, width, cap=cap, join=join, miter_limit=miter_limit, tol=tol, budget=charge)
    if transform is not None:  # a reflection reverses every piece alike: their union stays nonzero
        pieces = [transform(p) for p in pieces]
    # every piece is positively oriented: their union is the nonzero fill
    return [Region(outer, holes) for outer, holes in resolve_fill(pieces, "nonzero")]


def clip_regions(regions: list[Region], clip: list[Region]) -> list[Region]:
    """The part of ``regions`` inside ``clip`` (regions too: a viewport's rectangle, a
    clip path), resolved in float64.

    Regions inside a clip that is one convex ring come back unchanged. Otherwise the
    rings are resolved with the clip's rings and a frame around everything (weight -1)
    under winding > 0: a point counts 1 inside the regions, 1 inside the clip and -1 for
    the frame, so only the intersection is left.
    """
    rings = [ring for region in regions for ring in (region.outer, *region.holes)]
    clip_rings = [np.asarray(ring, dtype=np.float64) for region in clip for ring in (region.outer, *region.holes)]
    if not rings or not clip_rings:
        return []
    if len(clip_rings) == 1:
        ring = clip_rings[0] if ring_area(clip_rings[0]) > 0 else clip_rings[0][::-1]
        clip_rings = [ring]
        if _convex(ring) and _inside_convex(np.concatenate(rings), ring):
            return list(regions)
    every = np.concatenate([*rings, *clip_rings])
    lo, hi = every.min(axis=0) - 1.0, every.max(axis=0) + 1.0
    frame = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    weights = [1] * (len(rings) + len(clip_rings)) + [-1]
    return [Region(outer, holes) for outer, holes in resolve_fill([*rings, *clip_rings, frame], "positive", weights)]


def _convex(ring: np.ndarray) -> bool:
    """Whether a positively oriented ring turns left (or goes straight) at every vertex."""
    a, b, c = ring, np.roll(ring, -1, axis=0), np.roll(ring, -2, axis=0)
    turn = (b[:, 0] - a[:, 0]) * (c[:, 1] - b[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - b[:, 0])
    return bool((turn >= 0).all())


def _inside_convex(points: np.ndarray, polygon: np.ndarray) -> bool:
    """Whether every point lies in the positively oriented convex polygon (edges included)."""
    a, b = polygon, np.roll(polygon, -1, axis=0)
    cross = ((b[:, 0] - a[:, 0])[None, :] * (points[:, 1:2] - a[None, :, 1])
             - (b[:, 1] - a[:, 1])[None, :] * (points[:, 0:1] - a[None, :, 0]))
    return bool((cross >= 0).all())
