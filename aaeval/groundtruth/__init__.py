"""Ground truth no one here wrote: Mitsuba 3 at high samples per pixel, box filter.

- :mod:`aaeval.groundtruth.variant`: which Mitsuba variant runs here (CUDA, LLVM with a
  libLLVM >= 16 found automatically, else scalar), :func:`import_mitsuba`;
- :mod:`aaeval.groundtruth.mitsuba`: the scene as Mitsuba triangles, camera and film,
  :func:`render_mitsuba`;
- :mod:`aaeval.groundtruth.cache`: :func:`groundtruth_image` -> ``(image, hit)``, cached
  on disk by scene geometry and options.

Nothing here imports Mitsuba until it is used.
"""

from aaeval.groundtruth.cache import cache_dir, groundtruth_image, groundtruth_key, scene_digest
from aaeval.groundtruth.mitsuba import render_mitsuba
from aaeval.groundtruth.variant import import_mitsuba, select_variant

__all__ = [
    "cache_dir",
    "groundtruth_image",
    "groundtruth_key",
    "scene_digest",
    "render_mitsuba",
    "import_mitsuba",
    "select_variant",
]
