"""The scene format's one depth rule, in the two forms the methods need.

At a point (x, y), every polygon whose depth there is within ``eps`` of the smallest
depth there is tied with the nearest, and of the tied polygons the one listed latest is
visible (``docs/scene_format.md``, "Near ties"). ``eps`` is :func:`depth_tolerance`.

The rule is relative to the *smallest* depth, not chained from neighbour to neighbour:
with depths 0, 0.8 eps and 1.6 eps (file order), the first two are tied and the second
is visible; the third is not tied with the nearest, although it is within eps of the
second. Methods that resolve depth one sample at a time follow it while visiting
polygons in file order (``nearer_or_tied`` in ``src/samplers/depth.hpp``: a later polygon
at depth ``z`` is visible when ``z <= nearest + eps``, and the nearest depth kept is
``min(nearest, z)``, so the band does not drift towards the back); methods that order
whole fragments or polygons by one representative depth (the A-buffer's ``zmin``, the
painter's mean depth) order them front to back and then put each run within ``eps`` of
the run's nearest depth latest first (``tied_latest_first``, the same header, bound as
``aaeval.native.samplers.tied_latest_first``; :func:`front_to_back`).
"""

from __future__ import annotations

import numpy as np

from aaeval.native.samplers import tied_latest_first

__all__ = ["depth_tolerance", "front_to_back"]

#: relative size of the tie band: far above float64 rounding of a plane evaluation
#: (~1e-16 of the depth magnitude), far below any depth difference a scene means
RELATIVE_TIE = 1e-11


def depth_tolerance(z: np.ndarray) -> float:
    """``eps = 1e-11 x (1 + the largest |z| of the scene)`` for the scene's vertex depths ``z``."""
    zmax = float(np.abs(z).max()) if np.size(z) else 0.0
    return RELATIVE_TIE * (1.0 + zmax)


def front_to_back(depth: np.ndarray, eps: float) -> np.ndarray:
    """Indices ``0..n-1`` front to back by the rule, each taken at its one ``depth``.

    Sorted on ``(depth, -index)``, then each run of positions within ``eps`` of the run's
    first depth lists the latest index first (runs are taken from the front: a run ends
    at the first depth more than ``eps`` behind the run's first)."""
    depth = np.ascontiguousarray(depth, dtype=np.float64)
    index = np.arange(depth.size, dtype=np.int64)
    order = np.lexsort((-index, depth)).astype(np.int64)
    return tied_latest_first(order, depth, index, float(eps))
