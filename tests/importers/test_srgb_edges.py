"""With sRGB blending chosen, an imported SVG renders as a browser-like renderer converges to:
catmull's exact coverage averaged in sRGB matches resvg rendered 16 times larger and averaged
in sRGB (its own anti-aliasing error then under a level) within 8-bit rounding at every pixel,
edges included, once curves are flattened finely. resvg at the image's own size is off by tens
of levels at edges: its supersampled coverage, not the blending space, is the difference."""

from __future__ import annotations

import io

import numpy as np
import pytest
import resvg_py
from PIL import Image

from aaeval.fileio import linear_to_srgb8
from aaeval.importers.svg import import_svg
from aaeval.renderers import render
from aaeval.scenes import parse_scene

SIZE = 48
UPSCALE = 16
SHAPES = f"""<svg xmlns="http://www.w3.org/2000/svg" width="{{w}}" height="{{w}}" viewBox="0 0 {SIZE} {SIZE}">
  <rect width="{SIZE}" height="{SIZE}" fill="white"/>
  <polygon points="5.3,3.1 43.2,10.7 31.6,43.9 2.9,33.2" fill="#1f4fa0"/>
  <circle cx="30" cy="19" r="10.3" fill="#e05a10"/>
  <ellipse cx="14.5" cy="36.2" rx="9.1" ry="4.3" transform="rotate(23 14.5 36.2)" fill="#2a9d3c"/>
  <path d="M 3 20 C 10 5, 20 40, 27 24 A 6 4 30 0 1 38 30 Z" fill="#7b2a8f"/>
</svg>"""


def _resvg_srgb(upscale: int) -> np.ndarray:
    """resvg's render at ``upscale`` times the size, each block averaged in sRGB (8-bit codes)."""

    png = bytes(resvg_py.svg_to_bytes(svg_string=SHAPES.format(w=SIZE * upscale)))
    big = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.float64)
    return big.reshape(SIZE, upscale, SIZE, upscale, 3).mean(axis=(1, 3))


@pytest.fixture(scope="module")
def ours(tmp_path_factory) -> np.ndarray:
    path = tmp_path_factory.mktemp("srgb") / "shapes.svg"
    path.write_text(SHAPES.format(w=SIZE))
    result = import_svg(path, tolerance=0.0005)  # curves within 1/2000 px: no flattening shows
    assert result.ignored == []
    scene = parse_scene(result.document, source=str(path.with_suffix(".toml")))
    return linear_to_srgb8(render(scene, "catmull:blend=srgb")).astype(np.float64)


@pytest.mark.slow
def test_srgb_blending_matches_a_converged_resvg_within_8_bit_rounding(ours):
    converged, finer = _resvg_srgb(UPSCALE), _resvg_srgb(2 * UPSCALE)
    # the converged render's own error: what is left between it and one twice as fine
    own = np.abs(converged - finer).max()
    assert own < 1.0
    # ours is rounded to 8 bits (half a level); the reference is off by at most its own error
    assert np.abs(ours - converged).max() <= 0.5 + 2 * own


@pytest.mark.slow
def test_resvg_at_its_own_size_differs_at_edges_by_its_anti_aliasing(ours):
    own_size = _resvg_srgb(1)
    edges = np.abs(ours - own_size).max(axis=-1)
    assert edges.max() > 8  # its coverage, not the blending space: the converged render agrees
