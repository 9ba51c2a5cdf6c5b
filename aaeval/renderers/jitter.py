"""Method ``jitter``: one uniform random sample per stratum of a ``k x k`` grid (Cook 1986).

The sample positions are a hash of ``(seed, row, column, sample)``: the same seed gives
the same image, and the pattern is fixed in screen space, so all frames of an animation
share it (the noise does not move with the scene; use another seed per frame for fresh
noise). Different seeds give independent patterns, whose mean converges to the exact
box-filtered image (or, with ``filter=``, to ``catmull`` with that filter).
"""

from __future__ import annotations

import numpy as np

from aaeval.renderers.catmull import FILTER_OPTION
from aaeval.renderers.registry import Option, register_method
from aaeval.renderers.sampling import SAMPLE_BYTES, point_sampled, warmup_scene
from aaeval.scenes import Scene

__all__ = ["render_jitter"]


@register_method(
    "jitter",
    summary="Cook 1986: one random sample per stratum of a k x k grid, reproducible from seed",
    options={
        "k": Option(int, 4, "strata per pixel side", minimum=1),
        "seed": Option(int, 0, "seed of the sample pattern (fixed in screen space)", minimum=0),
        **FILTER_OPTION,
    },
    warmup=lambda: render_jitter(warmup_scene(), k=2, seed=0),
    samples=lambda o: o["k"] ** 2,
    memory=lambda scene, o: SAMPLE_BYTES * scene.width * o["k"] ** 2,
)
def render_jitter(scene: Scene, k: int = 4, seed: int = 0, filter: str = "box") -> np.ndarray:
    return point_sampled(scene, k, seed=seed, filter=filter)
