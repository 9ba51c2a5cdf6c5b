"""Method ``supersample``: a regular ``k x k`` grid per pixel, box-averaged (Crow 1981) or filtered.

Sample ``(i, j)`` of pixel ``(row, col)`` is at ``(col + (i + 1/2)/k, row + (j + 1/2)/k)``;
``k = 1`` is ``point``. Edge error falls about as ``1/k``. With ``filter=`` the samples
are weighted by that filter (:func:`aaeval.renderers.sampling.point_sampled`), so
``supersample:k=16,filter=mitchell`` is the sampled counterpart of ``catmull:filter=mitchell``.
"""

from __future__ import annotations

import numpy as np

from aaeval.renderers.catmull import FILTER_OPTION
from aaeval.renderers.registry import Option, register_method
from aaeval.renderers.sampling import SAMPLE_BYTES, point_sampled, warmup_scene
from aaeval.scenes import Scene

__all__ = ["render_supersample"]


@register_method(
    "supersample",
    summary="Crow 1981: regular k x k grid of point samples per pixel, box-averaged or filtered",
    options={"k": Option(int, 4, "samples per pixel side", minimum=1), **FILTER_OPTION},
    warmup=lambda: render_supersample(warmup_scene(), k=2),
    samples=lambda o: o["k"] ** 2,
    memory=lambda scene, o: SAMPLE_BYTES * scene.width * o["k"] ** 2,
)
def render_supersample(scene: Scene, k: int = 4, filter: str = "box") -> np.ndarray:
    return point_sampled(scene, k, filter=filter)
