"""Visible pieces from the Catmull kernel, integrated against a filter on the knot grid.

The scene is shifted by half a pixel and rendered at ``(W + 1) x (H + 1)`` by the same
scanline stages as ``catmull``: the pixels of that render are exactly the knot cells
``[m - 1/2, m + 1/2] x [n - 1/2, n + 1/2]`` of the original image, so every visible piece
the kernel emits lies inside one cell. The kernel's moment sink (``src/catmull/moment_sink.hpp``)
accumulates each one's integrals against the filter's basis times its colour per cell;
cells on the image border are cut to the image first (samples lie only inside it).
:func:`aaeval.filters.integrate.combine_cells` then turns cells into pixels;
:func:`filter_sums` does both in one native call (rows of cells contracted as they are done).
"""

from __future__ import annotations

import numpy as np

from aaeval.native import catmull as _catmull
from aaeval.catmull import kernel_inputs, native_arrays, thread_count
from aaeval.filters.integrate import cell_basis_matrix, filter_kernel_args
from aaeval.filters.registry import PixelFilter, axis_weights
from aaeval.scenes import Scene

__all__ = ["knot_grid_sums", "filter_sums", "filtered_pixels"]


def _inputs(scene: Scene, filt: PixelFilter):
    start, length, x, y, planes, source, eps_z = kernel_inputs(scene)
    kind, radius, k, alpha, bias = filter_kernel_args(filt)
    start, length, x, y, planes = native_arrays(start, length, x, y, planes)
    # the scene moved by (1/2, 1/2): z = a x + b y + c keeps its values at the moved points
    shifted = planes.copy()
    shifted[:, 2] -= 0.5 * (planes[:, 0] + planes[:, 1])
    colors = np.vstack([scene.arrays.colors[source], np.asarray(scene.background, dtype=np.float64)])
    return ((start, length, x + 0.5, y + 0.5, shifted, float(eps_z),
             np.ascontiguousarray(colors, dtype=np.float64).reshape(-1, 3), scene.width, scene.height),
            (int(kind), int(radius), int(k), float(alpha), float(bias)))


def knot_grid_sums(scene: Scene, filt: PixelFilter, threads: int = 0) -> np.ndarray:
    """Per-cell integrals ``(H + 1, W + 1, k, k, 3)`` of the visible colour (background included).

    A pixel holding two irregular pieces over what both hide takes the second's visible part
    as its piece less their overlap (integrals are linear in the pieces); the tent's
    integrals come in closed form (shoelace moments) and a cubic's four edge nodes as one
    vector; a piece alone in front of its pixel is integrated along its own edges cut to the
    pixel's column; the Gaussian's basis at its nodes comes from polynomials fitted once per
    render (``src/catmull/filter_basis.hpp``).
    """
    args, fargs = _inputs(scene, filt)
    return _catmull.knot_grid_sums(*args, *fargs, thread_count(threads))


def filter_sums(scene: Scene, filt: PixelFilter, threads: int = 0) -> np.ndarray:
    """Pixel sums ``(H, W, 3)`` of the visible colour against the filter (before the film's division).

    The same bits as ``combine_cells(knot_grid_sums(scene, filt), filt, W, H)``, without the
    cells: the kernel's sink contracts each row of cells along x as soon as the row is done.
    """
    return _native_filter_sums(scene, filt, threads)


def filtered_pixels(scene: Scene, filt: PixelFilter, threads: int = 0) -> np.ndarray:
    """The filtered image ``(H, W, 3)``: :func:`filter_sums` divided by the weight each pixel
    collects inside the image (Mitsuba's film), in the same native call; the same bits as
    ``aaeval.filters.exact.divide_by_weight(filter_sums(...), scene, filt)``."""
    weights = (np.ascontiguousarray(axis_weights(filt, scene.width), dtype=np.float64),
               np.ascontiguousarray(axis_weights(filt, scene.height), dtype=np.float64))
    return _native_filter_sums(scene, filt, threads, *weights)


def _native_filter_sums(scene, filt, threads, *weights):
    """The native filter_sums call (``weights``: the film's x and y weights, or none)."""
    args, fargs = _inputs(scene, filt)
    e = np.ascontiguousarray(cell_basis_matrix(filt), dtype=np.float64)
    return _catmull.filter_sums(*args, *fargs, e, thread_count(threads), *weights)
