"""The colour space in which an exact renderer averages coverage: ``blend=linear|srgb``.

Linear light is the physically right average and the default. Browsers and 2-D
libraries (Skia, resvg, Blend2D) average sRGB-encoded values instead; ``blend=srgb``
renders the same exact coverage that way, so the difference between the two is itself
something a sweep can measure, and an imported SVG can be compared exactly with a
browser-like render. With exact coverage the pixel is a weighted sum of its visible
colours (the weights are areas, or a filter's integrals), so averaging in sRGB is
rendering the scene with sRGB-encoded colours and decoding the result.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from aaeval.fileio import linear_to_srgb, srgb_to_linear
from aaeval.renderers.registry import Option
from aaeval.scenes import Scene
from aaeval.scenes.shaded import has_shaded

__all__ = ["BLEND", "render_blended"]

BLEND = Option(str, "linear", "colour space coverage is averaged in: linear light, or srgb as browsers and 2-D "
               "libraries blend (aaeval.renderers.blending)", choices=("linear", "srgb"))


def render_blended(scene: Scene, blend: str, render) -> np.ndarray:
    """``render(scene)``, its coverage averaged in the ``blend`` colour space."""
    if blend == "linear":
        return render(scene)
    if blend != "srgb":
        raise ValueError(f"blend must be linear or srgb, got {blend!r}")
    if has_shaded(scene):
        raise ValueError("blend=srgb supports flat-coloured scenes only, not [shaded] objects")
    encoded = replace(scene, background=linear_to_srgb(scene.background),
                      polygons=tuple(replace(p, color=linear_to_srgb(p.color)) for p in scene.polygons),
                      holed=tuple(replace(h, color=linear_to_srgb(h.color)) for h in scene.holed))
    return srgb_to_linear(np.clip(render(encoded), 0.0, 1.0))
