"""Method ``abuffer``: Carpenter 1984, "The A-buffer, an antialiased hidden surface method".

Coverage by 4 x 8 bit masks (32 subsamples at the subcell centres), fragments with z
ranges resolved front to back; coverage is quantised to 1/32 of the pixel except where
two fragments' z ranges overlap and the paper's blending estimate is applied. Details
in :mod:`aaeval.renderers._abuffer_kernel`.
"""

from __future__ import annotations

import numpy as np

from aaeval.renderers._abuffer_kernel import abuffer_image
from aaeval.renderers.catmull import BOX_ONLY
from aaeval.renderers.registry import register_method, scene_load
from aaeval.renderers.sampling import kernel_scene, warmup_scene
from aaeval.scenes import Scene

__all__ = ["render_abuffer"]


@register_method(
    "abuffer",
    summary="Carpenter 1984 A-buffer: 4x8 coverage masks with z ranges, resolved front to back",
    options=BOX_ONLY,
    warmup=lambda: render_abuffer(warmup_scene()),
    # fragments of one row are buffered (5 arrays, doubling) and each pixel's are sorted by
    # insertion: time grows with the square of the depth per pixel (4000 identical
    # triangles in 16x16: about 2 ns per unit of depth_squares beyond the near-tie pass)
    memory=lambda scene, o: 2 * 40 * scene_load(scene).fragments / max(scene.height, 1),
    seconds=lambda scene, o: 2e-9 * scene_load(scene).depth_squares,
)
def render_abuffer(scene: Scene, filter: str = "box") -> np.ndarray:
    return abuffer_image(*kernel_scene(scene))
