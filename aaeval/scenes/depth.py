"""The scene format's one depth rule, in the two forms the methods need.

At a point (x, y), every polygon whose depth there is within ``eps`` of the smallest
depth there is tied with the nearest, and of the tied polygons the one listed latest is
visible (``docs/scene_format.md``, "Near ties"). ``eps`` is :func:`depth_tolerance`.

The rule is relative to the *smallest* depth, not chained from neighbour to neighbour:
with depths 0, 0.8 eps and 1.6 eps (file order), the first two are tied and the second
is visible; the third is not tied with the nearest, although it is within eps of the
second. Methods that resolve depth one sample at a time follow it with
:func:`nearer_or_tied` while visiting polygons in file order; methods that order whole
fragments or polygons by one representative depth (the A-buffer's ``zmin``, the
painter's mean depth) order them with :func:`tied_latest_first`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["depth_tolerance", "nearer_or_tied", "tied_latest_first", "front_to_back"]

#: relative size of the tie band: far above float64 rounding of a plane evaluation
#: (~1e-16 of the depth magnitude), far below any depth difference a scene means
RELATIVE_TIE = 1e-11


def depth_tolerance(z: np.ndarray) -> float:
    """``eps = 1e-11 x (1 + the largest |z| of the scene)`` for the scene's vertex depths ``z``."""
    zmax = float(np.abs(z).max()) if np.size(z) else 0.0
    return RELATIVE_TIE * (1.0 + zmax)


@njit(cache=True, inline="always")
def nearer_or_tied(z, nearest, eps):
    """Whether a polygon at depth ``z``, listed after every polygon seen so far at this
    point, is visible: the nearest depth seen so far is ``nearest``. The caller then keeps
    ``min(nearest, z)`` as the nearest depth (not ``z``: the rule is relative to the
    minimum, so the band must not drift towards the back)."""
    return z <= nearest + eps


@njit(cache=True)
def tied_latest_first(order, depth, index, eps):
    """Reorders ``order`` (positions sorted front to back on ``depth``) in place so that
    each run of positions within ``eps`` of the run's nearest depth lists the latest
    ``index`` first: front to back by the rule. Runs are taken from the front: a run ends
    at the first depth more than ``eps`` behind the run's first."""
    n = order.size
    a = 0
    while a < n:
        b = a + 1
        while b < n and depth[order[b]] <= depth[order[a]] + eps:
            b += 1
        # insertion sort of the run on descending index (runs are short)
        for i in range(a + 1, b):
            item = order[i]
            j = i - 1
            while j >= a and index[order[j]] < index[item]:
                order[j + 1] = order[j]
                j -= 1
            order[j + 1] = item
        a = b


def front_to_back(depth: np.ndarray, eps: float) -> np.ndarray:
    """Indices ``0..n-1`` front to back by the rule, each taken at its one ``depth``."""
    depth = np.ascontiguousarray(depth, dtype=np.float64)
    index = np.arange(depth.size, dtype=np.int64)
    order = np.lexsort((-index, depth)).astype(np.int64)
    tied_latest_first(order, depth, index, float(eps))
    return order
