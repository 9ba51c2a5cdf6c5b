"""The exactly filtered image of a scene: visible pieces integrated against the filter.

Each pixel ``(i, j)`` is

    sum over visible pieces P of  colour(P) * ∫∫_{P ∩ image} k(x - i - 1/2) k(y - j - 1/2) dA
    ---------------------------------------------------------------------------------------
                   ∫∫_{image} k(x - i - 1/2) k(y - j - 1/2) dA

which is what Mitsuba's film converges to (samples only inside the image, each pixel
divided by the filter weight it collected; see ``docs/filters.md``). The background fills
whatever no piece covers: its share is the denominator minus the pieces' coverage.

The visible pieces come from the Catmull kernel run on the knot grid
(:mod:`aaeval.catmull.filtered`); any other exact source of visible polygons can be
passed as :class:`Rings` (the Weiler-Atherton solver's, :func:`weiler_atherton_rings`, is
the cross-check in the tests).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from aaeval.catmull.filtered import filtered_pixels
from aaeval.filters.integrate import accumulate_rings, combine_cells, filter_kernel_args
from aaeval.filters.registry import PixelFilter, axis_weights
from aaeval.scenes import Scene

__all__ = ["Rings", "rings_from_pieces", "weiler_atherton_rings", "filtered_image", "divide_by_weight"]


class Rings(NamedTuple):
    """Signed rings of visible pieces: flat vertex arrays and a weight row per ring.

    Ring ``r`` is ``x/y[start[r] : start[r] + length[r]]``, positive shoelace area for an
    outer contour and negative for a hole; ``weights[r]`` is ``(red, green, blue, 1)``
    (the last channel measures coverage).
    """

    x: np.ndarray
    y: np.ndarray
    start: np.ndarray
    length: np.ndarray
    weights: np.ndarray


def rings_from_pieces(rings: list, colors: list) -> Rings:
    """Flat :class:`Rings` from point lists and their colours."""
    length = np.array([len(r) for r in rings], dtype=np.int64)
    start = np.zeros(len(rings), dtype=np.int64)
    start[1:] = np.cumsum(length)[:-1]
    xy = np.concatenate([np.asarray(r, dtype=np.float64).reshape(-1, 2) for r in rings]) if rings else np.zeros((0, 2))
    weights = np.hstack([np.asarray(colors, dtype=np.float64).reshape(-1, 3), np.ones((len(rings), 1))])
    return Rings(np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]), start, length, weights)


def weiler_atherton_rings(scene: Scene) -> Rings:
    """Visible pieces from the Weiler-Atherton hidden-surface solver (exact polygons)."""
    from aaeval.weiler_atherton import visible_pieces

    rings, colors = [], []
    for piece in visible_pieces(scene):
        color = scene.polygons[piece.source].color
        for ring in piece.shape.rings:
            rings.append(ring)
            colors.append(color)
    return rings_from_pieces(rings, colors)


def divide_by_weight(sums: np.ndarray, scene: Scene, filt: PixelFilter) -> np.ndarray:
    """Pixel values from filtered sums ``(H, W, 3)``: the film's division by the weight collected in the image."""
    denom = axis_weights(filt, scene.height)[:, None] * axis_weights(filt, scene.width)[None, :]
    return sums / denom[..., None]


def filtered_image(scene: Scene, filt: PixelFilter, rings: Rings | None = None, threads: int = 0) -> np.ndarray:
    """The exactly filtered image ``(H, W, 3)`` of the scene's visible pieces.

    Parameters
    ----------
    scene : Scene
    filt : PixelFilter
        A polynomial or Gaussian filter from :data:`aaeval.filters.FILTERS` (the box has
        its own exact path, ``catmull``).
    rings : Rings, optional
        Visible pieces from another exact source; by default the Catmull kernel's.
    threads : int
        Threads of the Catmull kernel (0: all cores); the image does not depend on it.
    """
    kind, radius, k, alpha, bias = filter_kernel_args(filt)
    if rings is None:
        return filtered_pixels(scene, filt, threads)
    acc = np.zeros((scene.height + 1, scene.width + 1, k, k, 4))
    accumulate_rings(rings.x, rings.y, rings.start, rings.length, rings.weights,
                     scene.width, scene.height, kind, radius, k, alpha, bias, acc)
    sums = combine_cells(acc, filt, scene.width, scene.height)
    # what no ring covers is background: the filter's whole weight minus the coverage
    denom = axis_weights(filt, scene.height)[:, None] * axis_weights(filt, scene.width)[None, :]
    background = (denom - sums[..., 3])[..., None] * np.asarray(scene.background, dtype=np.float64)
    return divide_by_weight(sums[..., :3] + background, scene, filt)
