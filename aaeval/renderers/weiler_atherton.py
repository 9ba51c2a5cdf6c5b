"""Method ``weiler-atherton``: Weiler & Atherton 1977 visible polygons, box-filtered.

The hidden surfaces are solved in object space (:mod:`aaeval.weiler_atherton`) and the
non-overlapping visible polygons are then area-sampled exactly over each pixel: the same
image as ``catmull`` by a completely different road.
"""

from __future__ import annotations

from aaeval.renderers.registry import Option, register_method
from aaeval.scenes import Scene
from aaeval.weiler_atherton import box_filter, coverage, visible_pieces

__all__ = ["render_weiler_atherton"]


def _warmup() -> None:
    # compiles the coverage kernel; the clipper is plain Python
    coverage([[(0.2, 0.3), (3.7, 0.6), (1.5, 2.9)]], [1.0], 4, 3)


@register_method(
    "weiler-atherton",
    summary="Weiler-Atherton 1977: visible polygons solved in object space, exact box filter",
    options={
        "window": Option(int, 0, "screen subdivision: most polygons per window (0: none)", minimum=0),
    },
    exact=True,
    warmup=_warmup,
)
def render_weiler_atherton(scene: Scene, window: int = 0) -> "np.ndarray":  # noqa: F821
    return box_filter(scene, visible_pieces(scene, window=window))
