"""Ground truth no one here wrote: Mitsuba 3 at high samples per pixel, box filter.

- :mod:`aaeval.mitsuba_variant`: which Mitsuba variant runs here (CUDA, LLVM with a
  libLLVM >= 16 found automatically, else scalar), :func:`import_mitsuba`;
- :mod:`aaeval.groundtruth.flat`: the scene as Mitsuba triangles, camera and film, and
  the flat-colour ground truth :func:`render_mitsuba`;
- :mod:`aaeval.groundtruth.phong`: the Phong ground truth of ``[shaded]`` scenes (the
  same formula as :mod:`aaeval.specular.shading` at every sample), with its specular term;
- :mod:`aaeval.groundtruth.cache`: the one disk cache, :func:`groundtruth` ->
  ``(image, specular, hit)`` for either kind, with one default (:data:`DEFAULT_SPP`
  samples of the :data:`DEFAULT_SAMPLER` sampler).

The method ``mitsuba`` (:mod:`aaeval.renderers.mitsuba`) renders through the cache.
Nothing here imports Mitsuba until it is used.
"""

from aaeval.groundtruth.cache import (
    GroundTruth,
    cache_dir,
    code_digest,
    groundtruth,
    groundtruth_image,
    groundtruth_key,
    groundtruth_phong,
    scene_digest,
)
from aaeval.groundtruth.flat import DEFAULT_SAMPLER, DEFAULT_SPP, SAMPLERS, render_mitsuba
from aaeval.groundtruth.phong import render_mitsuba_phong
from aaeval.mitsuba_variant import import_mitsuba, select_variant

__all__ = [
    "DEFAULT_SAMPLER",
    "DEFAULT_SPP",
    "SAMPLERS",
    "GroundTruth",
    "cache_dir",
    "code_digest",
    "groundtruth",
    "groundtruth_image",
    "groundtruth_key",
    "groundtruth_phong",
    "scene_digest",
    "render_mitsuba",
    "render_mitsuba_phong",
    "import_mitsuba",
    "select_variant",
]
