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
    # Everything per polygon that numpy can do for all of them at once is done first
    # (coordinates as Python floats, colour bytes, which rings to reverse), so the loop
    # below only makes Blend2D's calls: building each path from numpy rows one by one was
    # about 13x Blend2D's own time on random triangles. (blend2d-py has no call taking a
    # whole polygon or array, only move_to / line_to / close.) The paths are the same as
    # _path makes: each ring wound positive (a single ring's winding does not matter to
    # the non-zero rule, but the same commands keep the same bytes).
    arr = scene.arrays
    xy = arr.vertices[:, :2]
    nxt = np.arange(len(xy)) + 1
    ends = arr.start + arr.length
    nxt[ends - 1] = arr.start
    twice_area = np.add.reduceat(xy[:, 0] * xy[nxt, 1] - xy[nxt, 0] * xy[:, 1], arr.start) if len(xy) else []
    xs, ys = xy[:, 0].tolist(), xy[:, 1].tolist()
    rgb = np.rint(np.clip(arr.colors, 0.0, 1.0) * 255.0).astype(np.int64).tolist()
    starts, lengths = arr.start.tolist(), arr.length.tolist()
    negative = (np.asarray(twice_area) <= 0).tolist()  # _signed_area > 0 is kept as it is
    fill_path, set_fill = context.fill_path, context.set_fill_style_rgba
    last = None
    for i in painter_order(scene):
        if i in skip:
            continue
        if rgb[i] != last:
            last = rgb[i]
            set_fill(*last, 255)
        if i in whole:
            fill_path(_path([ring[:, :2] for ring in whole[i].rings]))
            continue
        path = blend2d.Path()
        line_to = path.line_to
        a, n = starts[i], lengths[i]
        if negative[i]:
            path.move_to(xs[a + n - 1], ys[a + n - 1])
            for j in range(a + n - 2, a - 1, -1):
                line_to(xs[j], ys[j])
        else:
            path.move_to(xs[a], ys[a])
            for j in range(a + 1, a + n):
                line_to(xs[j], ys[j])
        path.close()
        fill_path(path)
    context.end()
    premultiplied = image.asarray().astype(np.float64) / 255.0
    alpha = premultiplied[..., 3:]
    # clipped: a premultiplied byte rounded up over an alpha rounded down can pass 1 by 1/255
    over = premultiplied[..., BGR] + (1.0 - alpha) * np.asarray(scene.background, dtype=np.float64)
    return np.clip(over, 0.0, 1.0)
