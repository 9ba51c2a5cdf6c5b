"""Method ``mitsuba``: the ground truth of :mod:`aaeval.groundtruth` as a method.

The scene's polygons become one triangle mesh seen by an orthographic camera that maps
each pixel onto its unit square; the ``aov`` integrator returns the flat colour of the
first hit (the Phong integrator of :mod:`aaeval.groundtruth.phong` shades ``[shaded]``
scenes); the box filter keeps every sample in its own pixel, so the image converges to
the exact area average (``catmull``) as spp grows. Images come from the one ground-truth
cache (:mod:`aaeval.groundtruth.cache`); ``cache=false`` renders every time, which is
what timing Mitsuba needs.
"""

from __future__ import annotations

import numpy as np

from aaeval.groundtruth.cache import groundtruth
from aaeval.groundtruth.flat import DEFAULT_SAMPLER, DEFAULT_SPP, SAMPLERS, render_mitsuba
from aaeval.renderers.catmull import FILTER_OPTION
from aaeval.renderers.registry import Option, register_method
from aaeval.scenes import Scene, parse_scene

__all__ = ["render_mitsuba_method"]


def _warmup() -> None:
    """Compile Mitsuba's kernels (and pick the variant) before anything is timed."""
    tiny = parse_scene(
        {
            "image": {"width": 4, "height": 3},
            "polygons": [{"color": [1, 0, 0], "vertices": [[0.2, 0.3, 1], [3.7, 0.6, 2], [1.5, 2.9, 0]]}],
        },
        source="<warm-up>",
    )
    for sampler in SAMPLERS:
        render_mitsuba(tiny, spp=16, sampler=sampler)


@register_method(
    "mitsuba",
    summary="Mitsuba 3 ground truth: flat colours (Phong for [shaded] scenes), box filter, high spp (cached on disk)",
    options={
        "spp": Option(int, DEFAULT_SPP, "samples per pixel (stratified/multijitter round up to a square)", minimum=1),
        "sampler": Option(str, DEFAULT_SAMPLER, "Mitsuba sampler", choices=SAMPLERS),
        "seed": Option(int, 0, "seed of the sampler", minimum=0),
        "variant": Option(str, "auto", "Mitsuba variant: auto (CUDA, else LLVM, else scalar) or an RGB variant name"),
        "cache": Option(bool, True, "reuse images cached in $AAEVAL_CACHE_DIR/groundtruth"),
        **FILTER_OPTION,  # a filter other than box is Mitsuba's matching rfilter, cached under its own key
    },
    samples=lambda o: o["spp"],
    warmup=_warmup,
    draws_polygons=False,  # the scene goes to Mitsuba, which resolves its own depth order
)
def render_mitsuba_method(
    scene: Scene, *, spp: int, sampler: str, seed: int, variant: str, cache: bool, filter: str = "box"
) -> np.ndarray:
    return groundtruth(scene, spp=spp, sampler=sampler, seed=seed, variant=variant, cache=cache, filter=filter).image
