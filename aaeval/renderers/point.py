"""Method ``point``: one sample at each pixel centre (no anti-aliasing)."""

from __future__ import annotations

import numpy as np

from aaeval.renderers.registry import register_method
from aaeval.renderers.sampling import point_sampled, warmup_scene
from aaeval.scenes import Scene

__all__ = ["render_point"]


@register_method(
    "point",
    summary="one point sample at the pixel centre (aliased reference)",
    warmup=lambda: render_point(warmup_scene()),
)
def render_point(scene: Scene) -> np.ndarray:
    return point_sampled(scene, 1)
