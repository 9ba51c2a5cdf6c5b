"""Weiler & Atherton (1977): hidden surfaces solved in object space with a general
polygon clipper; the output is the visible polygons themselves.

- :mod:`.clipper`: concave polygons with holes clipped against each other.
- :mod:`.hidden_surface`: polygon area sorting, recursive subdivision, cyclic overlap,
  interpenetration, screen subdivision.
- :mod:`.raster`: exact box filter of the visible polygons.
- :mod:`.lines`: visible edges (hidden-line drawings).

The kernels are C++ (``src/weiler_atherton/``: ``clipper.cpp``, ``solver.cpp`` with the
convex pieces' short road in ``convex.hpp``, ``near_ties.cpp``, ``raster.cpp``), bound as
:mod:`aaeval.native.weiler_atherton`; the functions above prepare their inputs.
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
