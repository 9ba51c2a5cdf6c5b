"""Polygon clipping against a line, with Catmull's clip flags: the Python face.

The clipper is native, written once in ``src/common/geometry.hpp`` (``clip_split``,
``clip_side``) and shared by the Catmull kernel and the filters. A polygon is a run of
vertices with a flag per vertex: 1 when the edge from it to the next lies on a clipping
line (never to be clipped along again). Lines are ``a x + b y + c = 0`` with ``(a, b)`` a
unit normal; side A is ``d < 0``, side B ``d > 0`` (Catmull 1978, "The Clipping
Algorithm"), and points within ``EPS_LINE`` of the line belong to both sides, so no
near-duplicate vertices are made. The ground truth's window clip calls the same native
function (``aaeval._catmull.clip_to_window``).
"""

from __future__ import annotations

import numpy as np

from aaeval import _catmull

__all__ = ["EPS_LINE", "clip_to_window"]

# Distance (pixels) under which a point counts as lying on a clipping line (the native
# geometry's constant): far above float64 rounding, far below any area the tests resolve.
EPS_LINE = 1e-11


def clip_to_window(xs: np.ndarray, ys: np.ndarray, window: tuple[float, float, float, float]) -> np.ndarray:
    """The part of the polygon ``xs, ys`` inside the window ``(x0, y0, x1, y1)``: side A of
    its four sides in turn; ``(k, 2)``, ``k == 0`` when nothing is inside."""
    x0, y0, x1, y1 = window
    return _catmull.clip_to_window(np.ascontiguousarray(xs, dtype=np.float64),
                                   np.ascontiguousarray(ys, dtype=np.float64),
                                   float(x0), float(y0), float(x1), float(y1))
