"""Point sampling of a scene at ``k x k`` samples per pixel, box-averaged or through a filter.

The one entry point behind the methods ``point``, ``supersample`` and ``jitter``; the
numba kernel is :mod:`aaeval.renderers._sampling_kernel`.
"""

from __future__ import annotations

import numpy as np

from aaeval.filters import DEFAULT_FILTER, get_filter
from aaeval.filters.evaluate import profile_args
from aaeval.renderers._sampling_kernel import sample_image
from aaeval.renderers.catmull import kernel_inputs
from aaeval.scenes import Scene, parse_scene

__all__ = ["point_sampled", "kernel_scene", "warmup_scene", "SAMPLE_BYTES"]

# The kernel keeps depth, polygon and offset (x, y) per sample of one image row.
SAMPLE_BYTES = 8 + 8 + 16


def kernel_scene(scene: Scene) -> tuple:
    """The scene as kernel arguments: ``(width, height, starts, lengths, x, y, planes, eps_z, colors, background)``.

    Polygons are those of :func:`aaeval.renderers.catmull.kernel_inputs` (file order,
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
        Jitter seed: one uniform sample per stratum of the ``k x k`` grid. ``None`` puts
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
    return sample_image(*kernel_scene(scene), int(k), seed is not None, 0 if seed is None else int(seed),
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
