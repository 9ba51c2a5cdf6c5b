"""Visible pieces from the Catmull kernel, integrated against a filter on the knot grid.

The scene is shifted by half a pixel and rendered at ``(W + 1) x (H + 1)`` by the same
scanline stages as ``catmull`` (:func:`aaeval.renderers._catmull_kernel.scanline`): the
pixels of that render are exactly the knot cells ``[m - 1/2, m + 1/2] x [n - 1/2, n + 1/2]``
of the original image, so every visible piece the kernel emits lies inside one cell. A
:class:`MomentSink` receives them (``emit_pixel``, ``emit_piece``, ``emit_strip_piece``,
``emit_area``, ``emit_rest``) and accumulates each one's integrals (:func:`~aaeval.filters.integrate.piece_integrals`)
times its colour per cell. Cells on the image border are cut to the image first
(samples lie only inside it). :func:`~aaeval.filters.integrate.combine_cells` then turns
cells into pixels.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numba.experimental import structref
from numba.extending import overload_method

from aaeval.filters.integrate import _clip_box, filter_kernel_args, piece_integrals
from aaeval.filters.registry import PixelFilter
from aaeval.renderers._catmull_kernel import _Workspace, define_workspace, scanline, sort_polygons

__all__ = ["MomentSink", "new_moment_sink", "knot_grid_sums"]


@structref.register
class MomentSinkType(_Workspace):
    pass


class MomentSink(structref.StructRefProxy):
    """Per-cell integrals ``acc[n, m, a, b, channel]`` of the visible colour against the basis.

    ``colors[src]`` is a kernel polygon's colour (``colors[-1]`` the background); the image
    spans ``[1/2, W + 1/2] x [1/2, H + 1/2]`` in the shifted coordinates the kernel sees;
    ``emitted`` holds what the current cell ``pix`` has received (for ``emit_rest``).
    """


define_workspace(MomentSink, MomentSinkType,
                 ["acc", "colors", "width", "height", "kind", "radius", "k", "alpha", "bias",
                  "out", "emitted", "pix", "bx", "by", "bf", "sx", "sy"])


@njit(cache=True)
def new_moment_sink(width, height, colors, kind, radius, k, alpha, bias):
    """A sink for an image of ``width x height`` pixels (cells ``(height + 1) x (width + 1)``)."""
    acc = np.zeros((height + 1, width + 1, k, k, 3))
    size = 256
    return MomentSink(acc, colors, width, height, kind, radius, k, alpha, bias, np.empty((k, k)),
                      np.zeros((k, k)), -1, np.empty(size), np.empty(size), np.empty(size, np.uint8),
                      np.empty(4), np.empty(4))


@njit(cache=True)
def _add(sink, pix, src, scale):
    """Add ``scale * sink.out`` (one piece's integrals) to cell ``pix`` in ``src``'s colour."""
    if pix != sink.pix:
        sink.pix = pix
        sink.emitted[:, :] = 0.0
    wc = sink.width + 1
    row = pix // wc
    col = pix - row * wc
    for a in range(sink.k):
        for b in range(sink.k):
            v = scale * sink.out[a, b]
            sink.emitted[a, b] += v
            for c in range(3):
                sink.acc[row, col, a, b, c] += v * sink.colors[src, c]


@njit(cache=True, inline="always")
def _cell_window(sink, pix):
    """Cell ``pix``'s row, column and its square cut to the image ``(x0, x1, y0, y1)`` (shifted coordinates)."""
    wc = sink.width + 1
    row = pix // wc
    col = pix - row * wc
    return (row, col, max(float(col), 0.5), min(col + 1.0, sink.width + 0.5),
            max(float(row), 0.5), min(row + 1.0, sink.height + 0.5))


@njit(cache=True)
def _integrate_piece(sink, pix, xs, ys, start, n):
    """``sink.out`` = the piece's integrals, cut to the image if its cell is on the border."""
    row, col, x0, x1, y0, y1 = _cell_window(sink, pix)
    ox = col + 0.5
    oy = row + 0.5
    if col > 0 and row > 0 and col < sink.width and row < sink.height:
        piece_integrals(xs, ys, start, n, ox, oy, sink.kind, sink.radius, sink.k, sink.alpha, sink.bias, sink.out)
        return
    if sink.bx.size < 2 * (16 * n + 16):
        size = 2 * (16 * n + 16)
        sink.bx = np.empty(size)
        sink.by = np.empty(size)
        sink.bf = np.empty(size, np.uint8)
    s, m = _clip_box(xs, ys, start, n, x0, x1, y0, y1, sink.bx, sink.by, sink.bf)
    if m < 3:
        sink.out[:, :] = 0.0
        return
    piece_integrals(sink.bx, sink.by, s, m, ox, oy, sink.kind, sink.radius, sink.k, sink.alpha, sink.bias, sink.out)


@njit(cache=True)
def _cell_integrals(sink, pix):
    """``sink.out`` = the integrals over the whole cell (cut to the image)."""
    row, col, x0, x1, y0, y1 = _cell_window(sink, pix)
    sink.sx[0] = x0
    sink.sy[0] = y0
    sink.sx[1] = x1
    sink.sy[1] = y0
    sink.sx[2] = x1
    sink.sy[2] = y1
    sink.sx[3] = x0
    sink.sy[3] = y1
    piece_integrals(sink.sx, sink.sy, 0, 4, col + 0.5, row + 0.5, sink.kind, sink.radius, sink.k, sink.alpha,
                    sink.bias, sink.out)


@overload_method(MomentSinkType, "emit_pixel", jit_options={"cache": True})
def _emit_pixel(sink, pix, src, x0, y0):
    def impl(sink, pix, src, x0, y0):
        _cell_integrals(sink, pix)
        _add(sink, pix, src, 1.0)
    return impl


@overload_method(MomentSinkType, "emit_piece", jit_options={"cache": True})
def _emit_piece(sink, pix, src, xs, ys, start, n):
    def impl(sink, pix, src, xs, ys, start, n):
        _integrate_piece(sink, pix, xs, ys, start, n)
        _add(sink, pix, src, 1.0)
    return impl


@overload_method(MomentSinkType, "emit_strip_piece", jit_options={"cache": True})
def _emit_strip_piece(sink, pix, src, area, xs, ys, start, n):
    # the strip coverage's area is the polygon's own: its integrals come from the polygon
    def impl(sink, pix, src, area, xs, ys, start, n):
        _integrate_piece(sink, pix, xs, ys, start, n)
        _add(sink, pix, src, 1.0)
    return impl


@overload_method(MomentSinkType, "emit_area", jit_options={"cache": True})
def _emit_area(sink, pix, src, area, x0, y0):
    # reached only for a front piece whose clip to its column left nothing (area ~ 0),
    # since the sink runs with centroids on: its area counts as the whole cell's share
    def impl(sink, pix, src, area, x0, y0):
        _cell_integrals(sink, pix)
        _add(sink, pix, src, area)
    return impl


@overload_method(MomentSinkType, "emit_rest", jit_options={"cache": True})
def _emit_rest(sink, pix, src, x0, y0):
    def impl(sink, pix, src, x0, y0):
        if pix != sink.pix:
            sink.pix = pix
            sink.emitted[:, :] = 0.0
        done = sink.emitted.copy()
        _cell_integrals(sink, pix)
        sink.out[:, :] -= done
        _add(sink, pix, src, 1.0)
    return impl


@njit(cache=True)
def _knot_grid_sums(start, length, x, y, planes, eps_z, colors, width, height, kind, radius, k, alpha, bias):
    polys = sort_polygons(start, length, x, y, planes)
    sink = new_moment_sink(width, height, colors, kind, radius, k, alpha, bias)
    scanline(polys, width + 1, 0, height + 1, eps_z, False, True, sink)
    return sink.acc


def knot_grid_sums(scene, filt: PixelFilter) -> np.ndarray:
    """Per-cell integrals ``(H + 1, W + 1, k, k, 3)`` of the visible colour (background included)."""
    from aaeval.renderers.catmull import kernel_inputs

    start, length, x, y, planes, source, eps_z = kernel_inputs(scene)
    kind, radius, k, alpha, bias = filter_kernel_args(filt)
    # the scene moved by (1/2, 1/2): z = a x + b y + c keeps its values at the moved points
    shifted = np.ascontiguousarray(planes.copy())
    shifted[:, 2] -= 0.5 * (planes[:, 0] + planes[:, 1])
    colors = np.vstack([scene.arrays.colors[source], np.asarray(scene.background, dtype=np.float64)])
    return _knot_grid_sums(start, length, x + 0.5, y + 0.5, shifted, eps_z, np.ascontiguousarray(colors),
                           scene.width, scene.height, kind, radius, k, alpha, bias)
