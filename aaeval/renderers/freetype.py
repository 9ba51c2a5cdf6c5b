"""Method ``freetype``: FreeType's own smooth rasterizer on text scenes (freetype-py).

What text renderers ship: FreeType computes each glyph's exact area coverage of every
pixel (its "smooth" rasterizer, an analytic coverage accumulator) from the font's own
outline, unhinted here so the shapes are the ones the importer flattened, and at 8 bits
(coverage quantised to 1/255). Glyphs are then blended one by one onto the background
(source-over in linear RGB), so where two glyphs touch inside a pixel the background leaks
through, as in every glyph-by-glyph text renderer.

It reads the scene's ``[text]`` table (:mod:`aaeval.scenes.sources`): the font, the
strings, sizes and pen origins, and lays the glyphs out with
:func:`aaeval.importers.text.layout`, the importer's own layout, so every glyph stands
where the imported polygons are. FreeType holds outlines and pen offsets in 26.6 fixed
point: positions are rounded to 1/64 px. Scenes without a ``[text]`` table are refused.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from aaeval.renderers.registry import MethodError, register_method, required_table
from aaeval.scenes import Scene

__all__ = ["render_freetype"]


@lru_cache(maxsize=8)
def _face(path: str):
    """The FreeType face of a font file, read through the bounded reader; a file that is
    not a font is refused in one line naming it."""
    import io

    import freetype

    from aaeval.readlimits import read_bytes

    from aaeval.importers.text import font_container_error

    data = read_bytes(path, what="font ([text].font)")
    refused = font_container_error(path, data)  # WOFF2 by name, as the importer refuses it
    if refused:
        raise MethodError(refused)
    try:
        return freetype.Face(io.BytesIO(data))
    except freetype.FT_Exception as exc:
        raise MethodError(f"{path}: FreeType cannot read this font ({exc}); [text].font must name a "
                          "TrueType/OpenType font file") from None


def _glyph_coverage(face, gid: int, size: float, x: float, y: float):
    """FreeType's coverage bitmap of one glyph whose pen stands at image (x, y), y down.

    Returns (coverage (h, w) float in [0, 1], row, col of its top-left pixel).
    """
    import freetype

    ix, iy = math.floor(x), math.floor(y)
    # FreeType's y axis points up: image (ix + fx + u, iy + fy - v) for outline (u, v)
    fx, fy = x - ix, y - iy
    face.set_char_size(int(round(size * 64)))
    face.set_transform(freetype.Matrix(0x10000, 0, 0, 0x10000), freetype.Vector(int(round(fx * 64)), int(round(-fy * 64))))
    face.load_glyph(gid, freetype.FT_LOAD_NO_HINTING | freetype.FT_LOAD_NO_BITMAP | freetype.FT_LOAD_RENDER)
    slot = face.glyph
    bitmap = slot.bitmap
    if bitmap.rows == 0 or bitmap.width == 0:
        return np.zeros((0, 0)), 0, 0
    rows = np.array(bitmap.buffer, dtype=np.uint8).reshape(bitmap.rows, bitmap.pitch)[:, : bitmap.width]
    return rows / 255.0, iy - slot.bitmap_top, ix + slot.bitmap_left


def _warmup() -> None:
    from aaeval.importers.text import DEFAULT_FONT
    from aaeval.scenes.sources import font_path

    _glyph_coverage(_face(str(font_path(".", DEFAULT_FONT))), 36, 12.0, 3.3, 10.6)


@register_method(
    "freetype",
    summary="FreeType's smooth rasterizer on text scenes: exact coverage per glyph, 8-bit, blended glyph by glyph",
    warmup=_warmup,
    requires="text",
)
def render_freetype(scene: Scene) -> np.ndarray:
    from aaeval.importers.text import layout
    from aaeval.scenes.sources import font_path

    text = required_table(scene, "freetype")
    font = str(font_path(scene.source, text.font))
    face = _face(font)
    image = np.empty((scene.height, scene.width, 3))
    image[:] = scene.background
    color = np.asarray(text.color, dtype=np.float64)
    import freetype

    for string, size, origin in zip(text.strings, text.sizes, text.origins):
        for glyph in layout(font, string, size, origin):
            try:
                cover, top, left = _glyph_coverage(face, glyph.gid, size, glyph.x, glyph.y)
            except freetype.FT_Exception as exc:  # a damaged glyph in a font that opened
                raise MethodError(f"{font}: FreeType cannot render glyph {glyph.glyph!r} for {glyph.char!r} "
                                  f"({exc})") from None
            _blend(image, cover, top, left, color)
    return image


def _blend(image: np.ndarray, cover: np.ndarray, top: int, left: int, color: np.ndarray) -> None:
    """Source-over of ``color`` at coverage ``cover`` placed at (top, left), clipped to the image."""
    h, w = cover.shape
    r0, c0 = max(top, 0), max(left, 0)
    r1, c1 = min(top + h, image.shape[0]), min(left + w, image.shape[1])
    if r0 >= r1 or c0 >= c1:
        return
    a = cover[r0 - top : r1 - top, c0 - left : c1 - left, None]
    region = image[r0:r1, c0:c1]
    region *= 1.0 - a
    region += a * color
