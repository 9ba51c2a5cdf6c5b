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
(resvg would draw it), are refused, and so is a source the importer refuses (before the render
and its clock, :func:`check_source`): the scene cannot be that SVG's import then, and what the
importer's limits stop can cost resvg minutes (a path of 100,000 edges crossing each other:
every crossing a reordering of tiny-skia's active edges, 17 s a render at 24 x 24 px).

The source is read through the bounded reader (:mod:`aaeval.readlimits`) and parsed before
resvg sees it: a file that is not SVG (not XML, empty, an entity bomb) is refused in one line
naming it, and so is one that names another file (an ``<image>``, or an ``href`` that is not
``#id`` in the same document, which resvg would read from disk and embed). A root ``<svg>``
with a viewBox and no width or height gets the size SVG gives it standing alone (the
viewBox's, or the other dimension over the viewBox's aspect ratio), as the importer does;
nested, it would take 100% of the canvas and be scaled twice.
"""

from __future__ import annotations

import functools
import hashlib
import io
import math
import xml.etree.ElementTree as ET

import numpy as np

from aaeval.readlimits import read_bytes
from aaeval.renderers.registry import MethodError, register_method, required_table
from aaeval.scenes import Scene

__all__ = ["render_resvg", "placed_svg", "check_source"]

SVG_NS = "http://www.w3.org/2000/svg"


XLINK_NS = "http://www.w3.org/1999/xlink"


class SourceError(MethodError):
    """The scene's SVG source is not an SVG resvg may draw."""


def _parse_source(source_text: str, name: str) -> ET.Element:
    """The root ``<svg>`` of ``source_text``, refused in one line naming ``name`` if it is
    not XML, not SVG, or names another file."""
    try:
        root = ET.fromstring(source_text)
    except ET.ParseError as exc:  # not XML, empty, or an entity bomb (expat's amplification limit)
        raise SourceError(f"{name}: not a readable SVG (XML error: {exc})") from None
    if root.tag != f"{{{SVG_NS}}}svg":
        raise SourceError(f"{name}: not an SVG (root element {root.tag!r}, expected <svg> in the SVG namespace)")
    for element in root.iter():
        tag = element.tag.rsplit("}", 1)[-1] if isinstance(element.tag, str) else ""
        if tag == "image":
            raise SourceError(f"{name}: <image> names a file resvg would read and embed; method 'resvg' "
                              "draws self-contained SVGs only (the importer leaves images out)")
        for key in ("href", f"{{{XLINK_NS}}}href"):
            ref = element.get(key)
            if ref is not None and not ref.strip().startswith("#"):
                raise SourceError(f"{name}: <{tag}> href={ref!r} names another file; method 'resvg' draws "
                                  "self-contained SVGs only (references must be #id in the same file)")
    return root


def _length(text: str | None) -> float | None:
    """A plain or ``px`` length, else None."""
    if text is None:
        return None
    text = text.strip().removesuffix("px")
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) and value > 0 else None


def _standalone_size(root: ET.Element) -> None:
    """Give a root ``<svg>`` with a viewBox the width and height it has standing alone.

    Nested in the canvas, a missing width or height would be 100% of the canvas (already
    ``scale`` times the document) and the viewBox would scale the content a second time.
    """
    width, height = root.get("width"), root.get("height")
    if width is not None and height is not None:
        return
    box = root.get("viewBox")
    try:
        _, _, vw, vh = (float(v) for v in (box or "").replace(",", " ").split())
    except ValueError:
        return
    if not (math.isfinite(vw) and math.isfinite(vh) and vw > 0 and vh > 0):
        return
    w, h = _length(width), _length(height)
    if width is None and height is None:
        w, h = vw, vh
    elif width is None and h is not None:
        w = h * vw / vh
    elif height is None and w is not None:
        h = w * vh / vw
    if w is not None and h is not None:
        root.set("width", repr(float(w)))
        root.set("height", repr(float(h)))


def placed_svg(source_text: str, width: int, height: int, scale: float, offset, name: str = "SVG") -> str:
    """The SVG nested in a ``width`` x ``height`` canvas, scaled and moved by ``offset`` px."""
    ET.register_namespace("", SVG_NS)
    ET.register_namespace("xlink", XLINK_NS)
    inner = _parse_source(source_text, name)
    _standalone_size(inner)
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


def check_source(scene: Scene, options) -> None:
    """Refuse a scene whose SVG source the importer refuses, in the importer's words
    (:attr:`aaeval.renderers.registry.Method.check`): resvg draws faithfully imported SVGs
    only. The source is imported once per process for each content, scale and tolerance."""
    from aaeval.scenes.sources import source_path

    svg = required_table(scene, "resvg")
    path = source_path(scene.source, svg.file)
    data = read_bytes(path, what="SVG ([svg].file)")
    refusal = _import_refusal(str(path), hashlib.blake2b(data).hexdigest(), float(svg.scale), float(svg.tolerance))
    if refusal is not None:
        raise SourceError(f"{scene.source}: method 'resvg' draws faithfully imported SVGs only, and the import "
                          f"refuses the source: {refusal}")


@functools.lru_cache(maxsize=64)
def _import_refusal(path: str, digest: str, scale: float, tolerance: float) -> str | None:
    """The importer's one-line refusal of the SVG at ``path`` (``digest``: its content, so an
    edited file is imported again), or None when it imports."""
    from aaeval.importers.svg import import_svg

    try:
        import_svg(path, tolerance=tolerance, scale=scale)
    except ValueError as exc:  # SvgError and the import's limits
        return _one_line(exc)
    return None


@register_method(
    "resvg",
    summary="resvg SVG renderer on scenes imported from SVG: per-shape analytic AA, sRGB 8-bit blending",
    warmup=_warmup,
    requires="svg",
    check=check_source,
)
def render_resvg(scene: Scene) -> np.ndarray:
    import resvg_py
    from PIL import Image

    from aaeval.imageio import srgb_to_linear
    from aaeval.importers.svgdocument import LANGUAGE
    from aaeval.scenes.sources import source_path

    svg = required_table(scene, "resvg")
    if svg.ignored:
        raise MethodError(f"{scene.source}: method 'resvg' would draw what the import ignored "
                          f"({len(svg.ignored)} item(s), first: {svg.ignored[0]}); it renders faithfully imported SVGs only")
    path = source_path(scene.source, svg.file)
    data = read_bytes(path, what="SVG ([svg].file)")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SourceError(f"{path}: not a readable SVG (not UTF-8 text: byte {data[exc.start]:#04x} at offset "
                          f"{exc.start})") from None
    placed = placed_svg(text, scene.width, scene.height, svg.scale, svg.offset, name=str(path))
    try:
        # dpi: CSS's 96 px per inch; resvg-py passes its default 0 through, and every absolute
        # unit (in, cm, mm, Q, pt, pc) would have no length; languages: the import's, so a
        # <switch> on systemLanguage picks the same child in both
        png = resvg_py.svg_to_bytes(svg_string=placed, background=_to_hex(scene.background), skip_system_fonts=True,
                                    dpi=96.0, languages=[LANGUAGE])
    except ValueError as exc:  # resvg's own refusals, e.g. "nodes limit reached" on a <use> bomb
        raise SourceError(f"{path}: resvg refuses this SVG ({_one_line(exc)})") from None
    pixels = np.asarray(Image.open(io.BytesIO(bytes(png))).convert("RGB"), dtype=np.float64) / 255.0
    if pixels.shape[:2] != (scene.height, scene.width):
        raise RuntimeError(f"resvg returned {pixels.shape[1]}x{pixels.shape[0]}, expected {scene.width}x{scene.height}")
    return srgb_to_linear(pixels)


def _one_line(exc: Exception) -> str:
    return " ".join(str(exc).split())[:300]
