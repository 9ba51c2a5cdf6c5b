"""Method ``skia``: what a 2D plotting library shows — Skia's anti-aliased path filling.

Polygons are painted back to front (painter's algorithm) onto the background with
anti-aliasing on, through skia-python into a float32 RGBA surface (``kRGBA_F32``, no
colour space, so Skia blends the linear values as given). The painter's order is by mean
vertex depth, farthest first (ties, within the scene format's tie band: the later polygon
is painted last, as on a shared plane). A painter's sort cannot resolve interpenetrating polygons, or cyclic
overlaps: one of them simply covers the other wherever they overlap.

Skia computes each shape's coverage of a pixel on its own and blends shape by shape
(source-over), so where two shapes abut inside a pixel the background leaks through the
shared edge ("conflation artifacts"): with coverage 1/2 each, the pixel gets
``1/2 colour + 1/4 colour + 1/4 background``. Catmull's per-pixel hidden-surface
integration has no such seam. Pixel values are float32, so they match a colour to about
1e-7, and Skia's coverage itself is quantised (about 1/256 per shape edge).
"""

from __future__ import annotations

import numpy as np
import skia

from aaeval.renderers.catmull import BOX_ONLY
from aaeval.renderers.registry import register_method
from aaeval.renderers.sampling import warmup_scene
from aaeval.scenes import Scene
from aaeval.scenes.depth import depth_tolerance, front_to_back

__all__ = ["render_skia", "painter_order"]


def painter_order(scene: Scene) -> list[int]:
    """Indices of the drawable polygons, farthest mean depth first; mean depths within the
    scene format's tie band of each other are tied, the later polygon painted last."""
    arr = scene.arrays
    drawable = np.flatnonzero(np.isfinite(arr.planes).all(axis=1))
    if drawable.size == 0:
        return []
    mean_z = np.add.reduceat(arr.vertices[:, 2], arr.start) / arr.length
    near_first = front_to_back(mean_z[drawable], depth_tolerance(arr.vertices[:, 2]))
    return drawable[near_first[::-1]].tolist()


@register_method(
    "skia",
    summary="Skia 2D rasterizer: anti-aliased polygons painted back to front (conflation at seams)",
    options=BOX_ONLY,
    warmup=lambda: render_skia(warmup_scene()),
)
def render_skia(scene: Scene, filter: str = "box") -> np.ndarray:
    pixels = np.empty((scene.height, scene.width, 4), dtype=np.float32)
    pixels[..., :3] = scene.background
    pixels[..., 3] = 1.0
    surface = skia.Surface(pixels, colorType=skia.kRGBA_F32_ColorType, alphaType=skia.kPremul_AlphaType)
    # a polygon with holes is one even-odd path, painted in its first piece's turn (its
    # pieces painted one by one would show Skia's seams along their shared edges)
    whole = {h.first: h for h in scene.holed}
    skip = {i for h in scene.holed for i in h.pieces if i != h.first}
    with surface as canvas:
        for i in painter_order(scene):
            if i in skip:
                continue
            polygon = scene.polygons[i]
            r, g, b = (float(v) for v in polygon.color)
            paint = skia.Paint(AntiAlias=True, Color4f=skia.Color4f(r, g, b, 1.0))
            rings = [ring[:, :2] for ring in whole[i].rings] if i in whole else [polygon.xy]
            path = skia.Path()
            path.setFillType(skia.PathFillType.kEvenOdd)
            for ring in rings:
                path.addPoly([skia.Point(float(x), float(y)) for x, y in ring], True)
            canvas.drawPath(path, paint)
    return pixels[..., :3].astype(np.float64)
