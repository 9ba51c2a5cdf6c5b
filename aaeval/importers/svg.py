"""SVG files to scenes: ``aaeval import svg FILE.svg -o SCENE.toml``.

svgelements parses the file and applies every transform (``reify``); each shape's
segments are flattened here (:mod:`aaeval.importers.flatten`); Skia's path operations
resolve the fill rule and stroke the outline (:mod:`aaeval.importers.shapes`). Each
element paints its fill, then its stroke, each a layer in document order (later
nearer). Colours are sRGB in the file and linear in the scene.

A nested ``<svg>`` (a new viewport, which places and clips its content) is refused.
What the scene format cannot hold is never dropped silently: text, images, gradient
and pattern paints, clip paths, masks, filters and dashes are left out, and opacity is
drawn opaque; each is listed by element (``#id``, or ``tag[n]``: the n-th drawn element
of that tag, 0-based, definitions such as clip-path contents not counted) in the result
and in the scene's ``[svg].ignored``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from aaeval.imageio import srgb_to_linear
from aaeval.importers.flatten import DEFAULT_TOLERANCE, arc_points, bezier_points
from aaeval.importers.scene import ImportResult, Layer, scene_document
from aaeval.importers.shapes import STROKE_CAPS, STROKE_JOINS, Subpath, fill_regions, stroke_regions

__all__ = ["import_svg", "SvgError", "shape_subpaths"]

# attributes whose effect the scene format cannot hold: the element is left out
UNSUPPORTED = {"clip-path": "clip path", "mask": "mask", "filter": "filter"}


class SvgError(ValueError):
    """An SVG file that cannot be read or imported."""


def import_svg(
    path: str | Path, *, tolerance: float = DEFAULT_TOLERANCE, scale: float = 1.0,
    background=(1.0, 1.0, 1.0), frames: int = 1, translate=(0.0, 0.0), file_ref: str | None = None,
) -> ImportResult:
    """Import an SVG file as a scene dictionary.

    Parameters
    ----------
    path : path of the SVG file.
    tolerance : float
        Flattening tolerance in scene pixels.
    scale : float
        Scene pixels per SVG pixel (the document's own size, viewBox applied).
    background : linear RGB of the scene's background (an SVG has none).
    frames, translate : the scene's animation.
    file_ref : str, optional
        How the scene's ``[svg].file`` names the SVG (default: ``path`` as given).
    """
    import svgelements as se

    if not (math.isfinite(scale) and scale > 0):
        raise SvgError(f"scale must be a positive number, got {scale!r}")
    path = Path(path)
    if not path.is_file():
        raise SvgError(f"{path}: no such SVG file")
    try:
        svg = se.SVG.parse(str(path), reify=True, transform=f"scale({scale!r})")
        width, height = svg.width, svg.height
    except Exception as exc:  # svgelements raises many kinds on broken input
        raise SvgError(f"{path}: not a readable SVG ({type(exc).__name__}: {exc})") from None
    if not (isinstance(width, (int, float)) and isinstance(height, (int, float)) and width > 0 and height > 0):
        raise SvgError(f"{path}: the SVG has no positive width and height")

    layers: list[Layer] = []
    ignored: list[str] = []
    counts: dict[str, int] = {}
    try:
        for element in svg.elements():
            tag = element.values.get("tag", type(element).__name__.lower()) if hasattr(element, "values") else "?"
            counts[tag] = counts.get(tag, 0) + 1
            name = f"#{element.id}" if getattr(element, "id", None) else f"{tag}[{counts[tag] - 1}]"
            if isinstance(element, se.SVG) and element is not svg:
                raise SvgError(f"{path}: nested <svg> {name} is not supported (its viewport would place and "
                               "clip its content); make it a <g> with a transform")
            layers.extend(_element_layers(se, element, name, tolerance, ignored))
    except SvgError:
        raise
    except Exception as exc:
        raise SvgError(f"{path}: could not import ({type(exc).__name__}: {exc})") from None

    source = {"file": file_ref if file_ref is not None else str(path), "scale": float(scale),
              "tolerance": float(tolerance), "ignored": ignored}
    document, cut = scene_document(
        math.ceil(width * scale - 1e-9), math.ceil(height * scale - 1e-9), background, layers,
        extension=("svg", source), frames=frames, translate=translate,
    )
    return ImportResult(document, ignored, cut)


def _element_layers(se, element, name: str, tol: float, ignored: list[str]) -> list[Layer]:
    """The fill and stroke layers of one element; anything left out goes to ``ignored``."""
    values = getattr(element, "values", {})
    if isinstance(element, (se.Text,)) or values.get("tag") in ("text", "tspan"):
        ignored.append(f"{name}: text element not imported (use 'aaeval import text')")
        return []
    if isinstance(element, se.Image):
        ignored.append(f"{name}: image not imported")
        return []
    if isinstance(element, (se.SVG, se.Group)) or not isinstance(element, se.Shape):
        for attr, what in UNSUPPORTED.items():
            if values.get(attr) not in (None, "", "none"):
                ignored.append(f"{name}: {what} on a group not applied (its shapes are drawn unclipped, unmasked, unfiltered)")
        return []
    for attr, what in UNSUPPORTED.items():
        if values.get(attr) not in (None, "", "none"):
            ignored.append(f"{name}: {what} not supported; element not imported")
            return []
    for attr in ("opacity", "fill-opacity", "stroke-opacity"):
        if _number(values.get(attr), 1.0) < 1.0:
            ignored.append(f"{name}: {attr} {values.get(attr)} ignored (drawn opaque)")

    subpaths = shape_subpaths(abs(se.Path(element)), tol)  # abs: the transform applied to the points
    layers = []
    fill = _paint(values.get("fill"), element.fill, name, "fill", ignored)
    if fill is not None and subpaths:
        rule = "evenodd" if str(values.get("fill-rule", "nonzero")).strip() == "evenodd" else "nonzero"
        layers.append(Layer(fill, fill_regions(subpaths, rule), name + " fill"))
    stroke = _paint(values.get("stroke"), element.stroke, name, "stroke", ignored)
    width = float(element.implicit_stroke_width or 0.0)
    if stroke is not None and subpaths and width > 0:
        if values.get("stroke-dasharray") not in (None, "", "none"):
            ignored.append(f"{name}: stroke-dasharray ignored (stroked solid)")
        cap = str(values.get("stroke-linecap", "butt")).strip()
        join = str(values.get("stroke-linejoin", "miter")).strip()
        if join == "miter-clip" or join == "arcs":
            join = "miter"
        regions = stroke_regions(
            subpaths, width, cap=cap if cap in STROKE_CAPS else "butt", join=join if join in STROKE_JOINS else "miter",
            miter_limit=_number(values.get("stroke-miterlimit"), 4.0), tol=tol,
        )
        layers.append(Layer(stroke, regions, name + " stroke"))
    return [layer for layer in layers if layer.regions]


def _paint(raw, color, name: str, what: str, ignored: list[str]) -> np.ndarray | None:
    """Linear RGB of a fill or stroke, or None when it paints nothing (or cannot be held)."""
    if raw is not None and str(raw).strip().startswith("url("):
        ignored.append(f"{name}: {what} {str(raw).strip()} (gradient or pattern) not imported")
        return None
    if color is None or color.value is None:
        return None
    if color.alpha < 255:
        ignored.append(f"{name}: {what} colour alpha {color.alpha}/255 ignored (drawn opaque)")
    return srgb_to_linear(np.array([color.red, color.green, color.blue]) / 255.0)


def _number(raw, default: float) -> float:
    try:
        return float(raw) if raw not in (None, "") else default
    except (TypeError, ValueError):
        return default


def shape_subpaths(path, tol: float) -> list[Subpath]:
    """A reified svgelements Path as flattened subpaths (absolute pixel coordinates)."""
    import svgelements as se

    subpaths: list[Subpath] = []
    points: list = []
    closed = False

    def finish():
        if len(points) >= 2:
            subpaths.append(Subpath(np.array(points, dtype=np.float64), closed))

    for seg in path:
        if isinstance(seg, se.Move):
            finish()
            points, closed = [(seg.end.x, seg.end.y)], False
            continue
        if not points and seg.start is not None:
            points = [(seg.start.x, seg.start.y)]
        if isinstance(seg, se.Close):
            closed = True
            finish()
            points, closed = [], False
        elif isinstance(seg, se.Line):
            points.append((seg.end.x, seg.end.y))
        elif isinstance(seg, se.QuadraticBezier):
            points.extend(bezier_points([(p.x, p.y) for p in (seg.start, seg.control, seg.end)], tol))
        elif isinstance(seg, se.CubicBezier):
            points.extend(bezier_points([(p.x, p.y) for p in (seg.start, seg.control1, seg.control2, seg.end)], tol))
        elif isinstance(seg, se.Arc):
            if seg.start == seg.end and not seg.sweep:
                continue
            arc = arc_points((seg.center.x, seg.center.y), seg.rx, seg.ry, seg.get_rotation(), seg.get_start_t(), seg.sweep, tol)
            arc[-1] = (seg.end.x, seg.end.y)
            points.extend(arc)
        else:
            raise SvgError(f"unknown path segment {type(seg).__name__}")
    finish()
    return subpaths
