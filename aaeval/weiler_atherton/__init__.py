"""Weiler & Atherton (1977): hidden surfaces solved in object space with a general
polygon clipper; the output is the visible polygons themselves.

- :mod:`.clipper`: concave polygons with holes clipped against each other.
- :mod:`.hidden_surface`: polygon area sorting, recursive subdivision, cyclic overlap,
  interpenetration, screen subdivision.
- :mod:`.convex_kernel`: the short road for a convex piece clipped by a convex outline
  (cut edge line by edge line; the paper's clipper takes every other pair).
- :mod:`.raster`: exact box filter of the visible polygons.
- :mod:`.lines`: visible edges (hidden-line drawings).
"""

from aaeval.weiler_atherton.clipper import InvalidShapeError, Shape, clip, oriented, polygons, ring_area, shape_area
from aaeval.weiler_atherton.hidden_surface import Piece, VisibleArrays, visible_arrays, visible_pieces
from aaeval.weiler_atherton.raster import box_filter, coverage

__all__ = [
    "Shape",
    "InvalidShapeError",
    "clip",
    "oriented",
    "polygons",
    "ring_area",
    "shape_area",
    "Piece",
    "visible_pieces",
    "VisibleArrays",
    "visible_arrays",
    "box_filter",
    "coverage",
]
