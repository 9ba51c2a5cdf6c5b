"""Point sampling of a scene at ``k x k`` samples per pixel, box-averaged or through a filter.

The one entry point behind the methods ``point``, ``supersample`` and ``jitter``; the
kernel is C++ (``src/samplers/sampling.cpp``, module ``aaeval.native.samplers``).

``point``, ``supersample`` and ``jitter`` differ only in where the samples of a pixel
lie; the kernel takes that as ``(k, jitter, seed)`` and does the rest, a scanline
algorithm whose cost follows what the polygons cover:

- every polygon is listed on each pixel row its y extent meets, in file order;
- per row and per *strip* (the band of one row of strata, height 1/k), each listed
  polygon's edges that meet the strip are collected with the x range they span there;
  only the pixel columns of that range are visited, and only those edges take part in
  the inside test of a sample;
- inside test: crossing parity with the half-open rule ``(y0 <= y) != (y1 <= y)`` and
  ``x < x_cross``, the crossing computed from the edge's endpoints ordered by y. Two
  polygons sharing an edge compute the same crossing, so a sample on the shared edge
  belongs to exactly one of them; a polygon covers ``[ymin, ymax)`` vertically;
- depth: ``z = a x + b y + c``; polygons are visited in file order and a later one wins
  when its depth is within ``eps_z`` of the nearest so far or nearer (the scene format's
  tie rule, relative to the nearest depth: :mod:`aaeval.scenes.depth`; ``eps_z`` comes
  from :func:`aaeval.catmull.kernel_inputs`).

Sample ``(i, j)`` of pixel ``(row, col)`` lies at ``x = (col k + i + u) / k``,
``y = row + (j + v) / k``, with ``u = v = 1/2`` on the regular grid; jittered offsets
``u, v`` come from a counter-based hash (splitmix64) of ``(seed, row, column, sample,
axis)``: reproducible, independent of the order of work, and fixed in screen space, so
every frame of an animation sees the same sample pattern for a given seed. The box filter
averages each pixel's own samples; any other filter weights every sample by the filter
of each pixel it reaches and divides by the weight collected (Mitsuba's film).
"""

from __future__ import annotations

import numpy as np

from aaeval.filters import DEFAULT_FILTER, get_filter
from aaeval.filters.registry import profile_args
from aaeval.native.samplers import sample_image
from aaeval.catmull import kernel_inputs
from aaeval.scenes import Scene, parse_scene

__all__ = ["point_sampled", "kernel_scene", "warmup_scene", "SAMPLE_BYTES"]

# The kernel keeps depth, polygon and offset (x, y) per sample of one image row.
SAMPLE_BYTES = 8 + 8 + 16


def kernel_scene(scene: Scene) -> tuple:
    """The scene as kernel arguments: ``(width, height, starts, lengths, x, y, planes, eps_z, colors, background)``.

    Polygons are those of :func:`aaeval.catmull.kernel_inputs` (file order,
    edge-on ones left out); ``colors[k]`` is kernel polygon ``k``'s colour.
    """
    starts, lengths, x, y, planes, source, eps_z = kernel_inputs(scene)
    colors = np.ascontiguousarray(scene.arrays.colors[source])
    background = np.asarray(scene.background, dtype=np.float64)
    return scene.width, scene.height, starts, lengths, x, y, planes, eps_z, colors, background


def point_sampled(scene: Scene, k: int, *, seed: int | None = None, filter: str = DEFAULT_FILTER) -> np.ndarray:
    """``k x k`` point samples per pixel (a regular grid, or jittered when ``seed`` is given), filtered.

    Parameters
    ----------
    scene : Scene
    k : int
        Samples per pixel side (``k >= 1``).
    seed : int, optional
        Jitter seed (below ``2**64``; a negative one counts as its 64-bit two's
        complement): one uniform sample per stratum of the ``k x k`` grid. ``None`` puts
        each sample at its stratum's centre.
    filter : str
        A filter of :data:`aaeval.filters.FILTERS`. ``box`` is the plain mean of each
        pixel's samples; any other weights every sample by the filter of each pixel it
        reaches and divides by the weight collected, as Mitsuba's film does.

    Returns
    -------
    ndarray, shape (height, width, 3), float64
    """
    if k < 1:
        raise ValueError(f"k must be >= 1, got {k}")
    if seed is not None and not -(2**63) <= int(seed) < 2**64:
        raise ValueError(f"seed must be below 2**64, got {seed}")
    return sample_image(*kernel_scene(scene), int(k), seed is not None, 0 if seed is None else int(seed) % 2**64,
                        *profile_args(get_filter(filter)))


def warmup_scene() -> Scene:
    """A tiny scene with overlap, a concave polygon and one reaching outside the image."""
    return parse_scene(
        {
            "image": {"width": 5, "height": 4, "background": [0.1, 0.2, 0.3]},
            "polygons": [
                {"color": [1, 0, 0], "vertices": [[0.2, 0.3, 1], [4.7, 0.6, 2], [1.5, 3.9, 0]]},
                {"color": [0, 1, 0], "vertices": [[-1, -1, 0.5], [3, 0, 0.5], [1, 1, 0.5], [0, 5, 0.5]]},
                {"color": [0, 0, 1], "vertices": [[-2, -2, 5], [7, -2, 5], [7, 6, 5], [-2, 6, 5]]},
            ],
        },
        source="<warm-up>",
    )
