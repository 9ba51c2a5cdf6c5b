"""Method ``blend2d``: the fastest CPU 2D rasterizer as a peer — Blend2D's analytic coverage.

Polygons are painted back to front (the painter's order of :func:`painter_order`, the
same as ``skia``'s) through ``blend2d-py`` into Blend2D's 8-bit premultiplied image (``PRGB32``,
B, G, R, A bytes in memory), starting transparent, and that image is laid over the
background in float64. Colours are the scene's
linear values rounded to 8 bits and blended as given (no sRGB), so a pixel matches the
exact image to about 1/255 plus Blend2D's coverage quantisation.

Blend2D computes each shape's exact cell coverage (the FreeType/AGG method) and blends
shape by shape (source-over), so, as with Skia, the background leaks through an edge two
shapes share inside a pixel (conflation seams). A polygon with holes is one path, its
holes wound against its outline: the binding has no fill-rule setter and Blend2D's
default non-zero rule then cuts them out (the scene format keeps rings apart, so no two
holes overlap).
"""

from __future__ import annotations

import blend2d
import numpy as np

from aaeval.renderers.catmull import BOX_ONLY
from aaeval.renderers.registry import register_method
from aaeval.renderers.sampling import warmup_scene
from aaeval.renderers.skia_painter import painter_order
from aaeval.scenes import Scene

__all__ = ["render_blend2d"]

BGR = [2, 1, 0]  # PRGB32 is 0xAARRGGBB, little-endian in memory: B, G, R, A


def _bytes(color) -> list[int]:
    """A linear colour as Blend2D's 8-bit components (clamped, rounded)."""
    return [int(v) for v in np.rint(np.clip(np.asarray(color, dtype=np.float64), 0.0, 1.0) * 255.0)]


def _signed_area(ring: np.ndarray) -> float:
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _path(rings: list[np.ndarray]) -> "blend2d.Path":
    """One path of the rings: the first (the outline) wound positive, the rest (holes)
    negative, so that the non-zero rule leaves the holes empty."""
    path = blend2d.Path()
    for k, ring in enumerate(rings):
        positive = _signed_area(ring) > 0
        if positive != (k == 0):
            ring = ring[::-1]
        xs, ys = ring[:, 0].tolist(), ring[:, 1].tolist()
        path.move_to(xs[0], ys[0])
        for x, y in zip(xs[1:], ys[1:]):
            path.line_to(x, y)
        path.close()
    return path


@register_method(
    "blend2d",
    summary="Blend2D 2D rasterizer: analytic coverage, polygons painted back to front, 8-bit (conflation at seams)",
    options=BOX_ONLY,
    warmup=lambda: render_blend2d(warmup_scene()),
)
def render_blend2d(scene: Scene, filter: str = "box") -> np.ndarray:
    image = blend2d.Image(scene.width, scene.height)
    context = blend2d.Context(image)
    context.set_comp_op(blend2d.CompOp.SRC_COPY)  # a new image's memory is not cleared
    context.set_fill_style_rgba(0, 0, 0, 0)
    context.fill_all()
    context.set_comp_op(blend2d.CompOp.SRC_OVER)
    # painted onto transparent black and laid over the background afterwards (source-over
    # is associative): the same blend, with the background exact where nothing covers it
    # a polygon with holes is one path, painted in its first piece's turn (its pieces
    # painted one by one would show seams along their shared edges)
    whole = {h.first: h for h in scene.holed}
    skip = {i for h in scene.holed for i in h.pieces if i != h.first}
    for i in painter_order(scene):
        if i in skip:
            continue
        polygon = scene.polygons[i]
        context.set_fill_style_rgba(*_bytes(polygon.color), 255)
        rings = [ring[:, :2] for ring in whole[i].rings] if i in whole else [polygon.xy]
        context.fill_path(_path(rings))
    context.end()
    premultiplied = image.asarray().astype(np.float64) / 255.0
    alpha = premultiplied[..., 3:]
    # clipped: a premultiplied byte rounded up over an alpha rounded down can pass 1 by 1/255
    over = premultiplied[..., BGR] + (1.0 - alpha) * np.asarray(scene.background, dtype=np.float64)
    return np.clip(over, 0.0, 1.0)
