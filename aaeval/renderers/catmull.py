"""Methods ``catmull`` and ``catmull-jagged``: Catmull 1978 exact area sampling.

``catmull`` gives every pixel the exact area average of the visible colours over the
pixel square (box filter), hidden surfaces solved inside the pixel by the recursive pixel
integrator. ``catmull-jagged`` is the paper's mode with the integrator switched off: the
nearest piece in the pixel's z-list colours the whole pixel.

This module only registers the methods and declares the options other methods share
(``FILTER_OPTION``, ``BOX_ONLY``); the algorithm lives in :mod:`aaeval.catmull`.
"""

from __future__ import annotations

import numpy as np

from aaeval.catmull import MAX_THREADS, render_flat
from aaeval.filters.exact import filtered_image
from aaeval.filters.registry import DEFAULT_FILTER, FILTERS
from aaeval.renderers.blending import BLEND, render_blended
from aaeval.renderers.registry import Option, register_method
from aaeval.scenes import Scene, parse_scene
from aaeval.scenes.shaded import has_shaded
from aaeval.specular.methods import PARAMETERS as SPECULAR_PARAMETERS
from aaeval.specular.methods import SPECULAR_METHODS
from aaeval.specular.exact import render_exact
from aaeval.specular.render import render_shaded

__all__ = ["render_catmull", "render_catmull_jagged", "FILTER_OPTION", "BOX_ONLY", "THREADS"]


def _warmup() -> None:
    tiny = parse_scene(
        {
            "image": {"width": 4, "height": 3},
            "polygons": [
                {"color": [1, 0, 0], "vertices": [[0.2, 0.3, 1], [3.7, 0.6, 2], [1.5, 2.9, 0]]},
                {"color": [0, 1, 0], "vertices": [[0.1, 2.5, 0], [3.9, 2.2, 3], [2.5, 0.1, 1]]},
                {"color": [0, 0, 1], "vertices": [[-1, -1, 5], [5, -1, 5], [5, 4, 5], [-1, 4, 5]]},
            ],
        },
        source="<warm-up>",
    )
    render_catmull(tiny)
    render_catmull_jagged(tiny)


# Options for scenes with [shaded] objects, declared once by the specular registry
# (flat scenes ignore them). Its method list is a live view: a clamp registered there
# later is accepted by catmull:specular=NAME. The same Options: every rule of each applies.
SPECULAR_OPTIONS = dict(SPECULAR_PARAMETERS)


FILTER_OPTION = {
    "filter": Option(
        str,
        DEFAULT_FILTER,
        "pixel filter, as Mitsuba 3 defines it and normalises its film (aaeval.filters, docs/filters.md)",
        choices=tuple(FILTERS),
    ),
}

# methods whose coverage is per pixel by construction (masks, analytic coverage) accept
# only the box, and say so when asked for another
BOX_ONLY = {"filter": Option(str, DEFAULT_FILTER, "pixel filter: box only (coverage is computed per pixel)",
                             choices=(DEFAULT_FILTER,))}


SHADING = Option(str, "piece", "shaded scenes: one Phong shade per visible piece at its centroid (piece) or the "
                 "shade integrated over each visible piece (exact, aaeval.specular.exact)", choices=("piece", "exact"))

THREADS = Option(int, 0, "bands of rows rendered in parallel on this many threads (0: all cores); "
                 "the image does not depend on it", minimum=0, maximum=MAX_THREADS)

# A supersampling specular method (crow) draws the whole scene magnified k times
# (aaeval.specular.render._supersampled): per pixel of that magnified scene, the bytes held
# (measured: 98-100 by peak RSS on shaded/thin-highlight.toml, region=all, k = 40 and 80;
# with a margin for scenes with more edges per pixel) and the seconds taken (0.53 us there).
FINE_PIXEL_BYTES = 160
FINE_PIXEL_SECONDS = 1e-6


def _fine_pixels(scene: Scene, options) -> float:
    """Pixels of the magnified scene a supersampling specular method draws (0 for none)."""
    supersamples = SPECULAR_METHODS[options["specular"]].supersample
    if not (supersamples and has_shaded(scene) and options["shading"] == "piece"):
        return 0.0
    return float(scene.width) * scene.height * float(options["k"]) ** 2


@register_method(
    "catmull",
    summary="Catmull 1978: exact box filter (or another filter=), hidden surfaces solved inside each pixel",
    options={**SPECULAR_OPTIONS, **FILTER_OPTION, "threads": THREADS, "shading": SHADING, "blend": BLEND},
    exact=True,
    warmup=_warmup,
    memory=lambda scene, o: FINE_PIXEL_BYTES * _fine_pixels(scene, o),
    seconds=lambda scene, o: FINE_PIXEL_SECONDS * _fine_pixels(scene, o),
    speed_baseline="skia",
)
def render_catmull(scene: Scene, filter: str = DEFAULT_FILTER, threads: int = 0, shading: str = "piece",
                   blend: str = "linear", **specular_options) -> np.ndarray:
    if blend != "linear":
        return render_blended(scene, blend, lambda s: render_catmull(s, filter, threads, shading, **specular_options))
    if filter != DEFAULT_FILTER:
        if has_shaded(scene):
            raise ValueError(f"catmull: filter={filter} supports flat-coloured scenes only, not [shaded] objects")
        return filtered_image(scene, FILTERS[filter], threads=threads)
    if has_shaded(scene) and shading == "exact":
        return render_exact(scene, threads=threads, **specular_options)
    if has_shaded(scene):
        return render_shaded(scene, **specular_options)
    return render_flat(scene, threads=threads)


@register_method(
    "catmull-jagged",
    summary="Catmull 1978 with the pixel integrator off: nearest piece fills the pixel",
    options={"threads": THREADS},
    warmup=_warmup,
)
def render_catmull_jagged(scene: Scene, threads: int = 0) -> np.ndarray:
    return render_flat(scene, jagged=True, threads=threads)
