"""Method ``msaa``: multisample anti-aliasing with Direct3D's standard sample patterns.

Coverage and depth are resolved per sample (the scene format's near-tie rule, as every
sampling method here); colour is computed once per pixel and polygon: a flat polygon's
colour, or for ``[shaded]`` scenes the Phong shade of the polygon at the pixel centre
(the polygon's normal field evaluated there, as a GPU evaluates a pixel shader once per
pixel at the centre without centroid interpolation), so a highlight narrower than a pixel
aliases as it does under real MSAA. The resolve is the box filter: the mean of the
samples.

Sample positions are the D3D11 standard multisample patterns
(``D3D11_STANDARD_MULTISAMPLE_PATTERN``), in 1/16 pixel from the pixel centre, x right
and y down. Sources: the figures of the Direct3D 11 documentation,
"D3D11_STANDARD_MULTISAMPLE_QUALITY_LEVELS enumeration"
(MicrosoftDocs/sdk-api, sdk-api-src/content/d3d11/ne-d3d11-d3d11_standard_multisample_quality_levels.md),
read as numbers from Mesa's OpenSWR rasterizer, "hardcoded offsets based on Direct3d
standard multisample positions" (src/gallium/drivers/swr/rasterizer/core/multisample.h,
``MultisampleTraits<...>::samplePosXi/Yi``, 1/256 pixel from the pixel's corner, so
``(v - 0x80) / 16`` is the 1/16 offset below); the 8x table agrees with the HLSL
``v2MSAAOffsets`` of tobguent/image-triangulation (demo/Effects/ShaderCommon.hlsl).
"""

from __future__ import annotations

import numpy as np

from aaeval.renderers.offsets import OffsetSampler
from aaeval.renderers.registry import Option, register_method
from aaeval.renderers.sampling import SAMPLE_BYTES, warmup_scene
from aaeval.scenes import Scene

__all__ = ["render_msaa", "STANDARD_PATTERNS"]

#: D3D11 standard sample positions, in 1/16 pixel from the pixel centre (x right, y down)
STANDARD_PATTERNS: dict[int, tuple[tuple[int, int], ...]] = {
    1: ((0, 0),),
    2: ((4, 4), (-4, -4)),
    4: ((-2, -6), (6, -2), (-6, 2), (2, 6)),
    8: ((1, -3), (-1, 3), (5, 1), (-3, -5), (-5, 5), (-7, -1), (3, 7), (7, -7)),
    16: ((1, 1), (-1, -3), (-3, 2), (4, -1), (-5, -2), (2, 5), (5, 3), (3, -5),
         (-2, 6), (0, -7), (-4, -6), (-6, 4), (-8, 0), (7, -4), (6, 7), (-7, -8)),
}


def sample_offsets(samples: int) -> np.ndarray:
    """The pattern of ``samples`` as offsets in pixels from the pixel centre, shape (samples, 2)."""
    return np.asarray(STANDARD_PATTERNS[samples], dtype=np.float64) / 16.0


@register_method(
    "msaa",
    summary="MSAA: D3D11 standard 2/4/8/16-sample patterns, coverage per sample, one shade per pixel, box resolve",
    options={"samples": Option(int, 4, "samples per pixel (the D3D11 standard pattern of that count)",
                               choices=(1, 2, 4, 8, 16))},
    warmup=lambda: render_msaa(warmup_scene(), samples=2),
    samples=lambda o: o["samples"],
    memory=lambda scene, o: SAMPLE_BYTES * scene.width + 16 * 8 * scene.width * scene.height,
)
def render_msaa(scene: Scene, samples: int = 4) -> np.ndarray:
    sampler = OffsetSampler(scene)
    image = np.zeros(scene.shape)
    for dx, dy in sample_offsets(samples):
        image += sampler.sample(dx, dy, shade_at_centre=True)
    return image / samples
