"""Method ``resvg``: the resvg SVG renderer (resvg-py) on scenes imported from SVG.

What SVG viewers ship: resvg (Rust, tiny-skia) fills each path with analytic
anti-aliasing and blends shape by shape, in sRGB-encoded 8-bit values, as browsers do.
The method renders the scene's source file (``[svg].file``, :mod:`aaeval.scenes.sources`)
on the scene's background, at the import's scale and the frame's translation (the SVG is
nested in an outer one that places it), and decodes the 8-bit sRGB result to linear RGB.
So its differences from the exact image are resvg's own: coverage per shape from 4 x 4
supersampled scanlines (tiny-skia, after Skia's SkScan_AntiPath: edges snap to 1/4 px),
conflation where shapes abut, blending in sRGB rather than linear light, 8-bit output,
and its own curve flattening. Scenes without an ``[svg]`` table, or whose import ignored something
(resvg would draw it), are refused.
"""

from __future__ import annotations

import io
import xml.etree.ElementTree as ET

import numpy as np

from aaeval.renderers.registry import MethodError, register_method, required_table
from aaeval.scenes import Scene

__all__ = ["render_resvg", "placed_svg"]

SVG_NS = "http://www.w3.org/2000/svg"


def placed_svg(source_text: str, width: int, height: int, scale: float, offset) -> str:
    """The SVG nested in a ``width`` x ``height`` canvas, scaled and moved by ``offset`` px."""
    ET.register_namespace("", SVG_NS)
    ET.register_namespace("xlink", "http://www.w3.org/1999/xlink")
    inner = ET.fromstring(source_text)
    outer = ET.Element(f"{{{SVG_NS}}}svg", {"width": str(width), "height": str(height),
                                             "viewBox": f"0 0 {width} {height}"})
    group = ET.SubElement(outer, f"{{{SVG_NS}}}g",
                          {"transform": f"translate({float(offset[0])!r},{float(offset[1])!r}) scale({float(scale)!r})"})
    group.append(inner)
    return ET.tostring(outer, encoding="unicode")


def _to_hex(linear) -> str:
    from aaeval.imageio import linear_to_srgb8

    r, g, b = linear_to_srgb8(np.asarray(linear, dtype=np.float64))
    return f"#{r:02x}{g:02x}{b:02x}"


def _warmup() -> None:
    import resvg_py

    resvg_py.svg_to_bytes(svg_string='<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"><rect width="2" height="3"/></svg>')


@register_method(
    "resvg",
    summary="resvg SVG renderer on scenes imported from SVG: per-shape analytic AA, sRGB 8-bit blending",
    warmup=_warmup,
    requires="svg",
)
def render_resvg(scene: Scene) -> np.ndarray:
    import resvg_py
    from PIL import Image

    from aaeval.imageio import srgb_to_linear
    from aaeval.scenes.sources import source_path

    svg = required_table(scene, "resvg")
    if svg.ignored:
        raise MethodError(f"{scene.source}: method 'resvg' would draw what the import ignored "
                          f"({len(svg.ignored)} item(s), first: {svg.ignored[0]}); it renders faithfully imported SVGs only")
    path = source_path(scene.source, svg.file)
    try:
        text = path.read_text()
    except OSError as exc:
        raise MethodError(f"{scene.source}: cannot read the scene's SVG {path} ({exc.strerror})") from None
    placed = placed_svg(text, scene.width, scene.height, svg.scale, svg.offset)
    png = resvg_py.svg_to_bytes(svg_string=placed, background=_to_hex(scene.background))
    pixels = np.asarray(Image.open(io.BytesIO(bytes(png))).convert("RGB"), dtype=np.float64) / 255.0
    if pixels.shape[:2] != (scene.height, scene.width):
        raise RuntimeError(f"resvg returned {pixels.shape[1]}x{pixels.shape[0]}, expected {scene.width}x{scene.height}")
    return srgb_to_linear(pixels)
