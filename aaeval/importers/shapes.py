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
from aaeval.importers.limits import charge
from aaeval.importers.stroke import Seg, stroke_pieces

__all__ = ["Subpath", "Region", "fill_regions", "stroke_regions", "STROKE_CAPS", "STROKE_JOINS", "Seg"]

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
) -> list[Region]:
    """The area a stroke of ``width`` along the subpaths covers (SVG stroke geometry).

    ``subpaths`` is a sequence of (list of :class:`Seg`, closed): the true segments, so
    joins are decided on true tangents and offsets sampled to ``tol``.
    """
    pieces = stroke_pieces(subpaths, width, cap=cap, join=join, miter_limit=miter_limit, tol=tol, budget=charge)
    # every piece is positively oriented: their union is the nonzero fill
    return [Region(outer, holes) for outer, holes in resolve_fill(pieces, "nonzero")]
