"""Error along edges: where anti-aliasing methods differ most.

:func:`edge_mask` finds the pixels an edge crosses from the exact coverage of the Catmull
(1978) scanline algorithm; :func:`edge_rmse` is the RMSE over those pixels only;
:func:`noise_weight` how much a sampled coverage error moves each edge pixel.
"""

from __future__ import annotations

import numpy as np

from aaeval.catmull import visible_fragments
from aaeval.metrics._checks import check_image_pair
from aaeval.metrics.image import masked_rmse

__all__ = ["edge_mask", "edge_rmse", "noise_weight"]

# A pixel one polygon covers whole gets an area a few ulps off 1 from the clipping, and an
# edge lying on the pixel's border may leave a zero-area fragment beside it.
_FULL_AREA_TOL = 1e-12


def edge_mask(scene) -> np.ndarray:
    """Pixels of ``scene`` that a visible edge crosses, shape (H, W), bool.

    A pixel is an edge pixel unless one polygon (or the background) covers all of it:
    exactly, its visible fragments (:func:`aaeval.catmull.visible_fragments`)
    are not a single fragment of area 1. Hidden edges do not count; lines where
    interpenetrating polygons cross do. An edge lying exactly on a pixel's border does
    not cross that pixel.

    Parameters
    ----------
    scene : aaeval.scenes.Scene
        The scene at the frame wanted (``scene.at_frame(k)``).
    """
    fragments = visible_fragments(scene)
    n = scene.width * scene.height
    largest = np.zeros(n)
    np.maximum.at(largest, fragments.pixel, fragments.area)
    return (largest < 1.0 - _FULL_AREA_TOL).reshape(scene.height, scene.width)


def edge_rmse(image_true, image_test, *, mask) -> float:
    """Root-mean-square error over the pixels of ``mask`` (every channel).

    Parameters
    ----------
    image_true, image_test : ndarray, shape (H, W, 3)
        The reference and the test image (linear RGB), the same shape.
    mask : ndarray of bool, shape (H, W)
        The pixels to measure, typically :func:`edge_mask` of the scene.

    Returns
    -------
    rmse : float
        RMSE over the masked pixels; NaN when the mask selects no pixel.
    """
    image_true, image_test = check_image_pair(image_true, image_test)
    mask = np.asarray(mask)
    if mask.shape != image_true.shape[:2]:
        raise ValueError(f"mask has shape {mask.shape}, expected the images' {image_true.shape[:2]}")
    if mask.dtype != bool:
        raise ValueError(f"mask must be boolean, got dtype {mask.dtype}")
    return masked_rmse(image_true, image_test, mask)


def noise_weight(scene) -> np.ndarray:
    """Relative noise of each pixel and channel on the pixels an edge crosses, (H, W, 3).

    For a scene of flat colours, the range (max - min) of the colours of the fragments
    visible in the pixel, per channel (the background counts as a fragment): a sampled
    coverage's error moves the pixel by that range times the coverage's error. Scenes with
    shaded objects: 1 everywhere (their colour varies inside a fragment).
    """
    from aaeval.scenes.shaded import has_shaded

    if has_shaded(scene):
        return np.ones((scene.height, scene.width, 3))
    fragments = visible_fragments(scene, centroids=False)
    colours = np.vstack([np.array([p.color for p in scene.polygons]).reshape(-1, 3), scene.background[None]])
    colour = colours[np.where(fragments.polygon < 0, len(scene.polygons), fragments.polygon)]
    n = scene.width * scene.height
    high, low = np.full((n, 3), -np.inf), np.full((n, 3), np.inf)
    np.maximum.at(high, fragments.pixel, colour)
    np.minimum.at(low, fragments.pixel, colour)
    return (high - low).reshape(scene.height, scene.width, 3)
