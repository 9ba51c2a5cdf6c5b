"""SVG files to scenes: ``aaeval import svg FILE.svg -o SCENE.toml``.

The file is read by :func:`aaeval.readlimits.read_bytes` and checked as XML first (root
``<svg>``, a valid ``viewBox``, at most :data:`~aaeval.importers.limits.MAX_ELEMENTS`
elements once ``<use>`` is expanded, counted without expanding); then svgelements parses
it and applies every transform (``reify``). Each shape's true segments are kept
(:func:`shape_segments`): fills flatten them (:mod:`aaeval.importers.flatten`) and resolve
the fill rule in float64 (:mod:`aaeval.importers.fill`); strokes are built from the
segments themselves (:mod:`aaeval.importers.stroke`). Each element paints its fill, then
its stroke, each a layer in document order (later nearer). Colours are sRGB in the file
and linear in the scene.

A nested ``<svg>`` (a new viewport, which places and clips its content) is refused.
What the scene format cannot hold is never dropped silently: text, images, gradient
and pattern paints, clip paths, masks, filters and dashes are left out, and opacity is
drawn opaque; each is listed by element (``#id``, or ``tag[n]``: the n-th drawn element
of that tag, 0-based, definitions such as clip-path contents not counted) in the result
and in the scene's ``[svg].ignored``. So is every malformed element SVG does not render
(NaN or infinite numbers, negative sizes and radii), geometry beyond
:data:`MAX_COORDINATE`, and ``<use>`` of anything outside the file (nothing is fetched).
"""

from __future__ import annotations

import io
import math
import re
from pathlib import Path

import numpy as np

from aaeval.imageio import srgb_to_linear
from aaeval.importers.flatten import DEFAULT_TOLERANCE, arc_points, bezier_points
from aaeval.importers.fill import MAX_EDGES
from aaeval.importers.limits import (MAX_ELEMENTS, MAX_VERTICES, ImportLimitError, VertexBudget, budget_scope, charge,
                                     check_tolerance)
from aaeval.importers.scene import ImportResult, Layer, scene_document
from aaeval.importers.shapes import STROKE_CAPS, STROKE_JOINS, Seg, Subpath, fill_regions, stroke_regions

__all__ = ["import_svg", "SvgError", "shape_subpaths", "shape_segments", "count_elements"]

SVG_NS = "{http://www.w3.org/2000/svg}"
XLINK_HREF = "{http://www.w3.org/1999/xlink}href"
# Geometry beyond this (pixels, after transforms) is not imported: the scene format holds
# coordinates up to 1e9, and float64 products of larger ones lose the exactness fill
# rules need.
MAX_COORDINATE = 1e9
# attributes that hold numbers of an element's own geometry
GEOMETRY_ATTRS = ("x", "y", "width", "height", "rx", "ry", "cx", "cy", "r", "x1", "y1", "x2", "y2",
                  "points", "d", "transform", "stroke-width", "stroke-miterlimit")
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
NOT_FINITE = re.compile(r"(?<![a-z])(nan|inf(inity)?)(?![a-z])", re.IGNORECASE)

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
    from aaeval.readlimits import read_bytes

    path = Path(path)
    data = read_bytes(path, what="SVG file")  # regular files of bounded size only
    ignored: list[str] = []
    _check_document(data, path, ignored)  # root element, viewBox, element count after <use>
    try:
        svg = se.SVG.parse(io.BytesIO(data), reify=True, transform=f"scale({scale!r})")
        width, height = svg.width, svg.height
    except Exception as exc:  # svgelements raises many kinds on broken input
        raise SvgError(f"{path}: not a readable SVG ({type(exc).__name__}: {exc})") from None
    if not (isinstance(width, (int, float)) and isinstance(height, (int, float)) and width > 0 and height > 0
            and math.isfinite(width) and math.isfinite(height)):
        raise SvgError(f"{path}: the SVG has no positive width and height")
    if width * scale > MAX_COORDINATE or height * scale > MAX_COORDINATE:
        raise SvgError(f"{path}: the SVG is {width * scale:.3g}x{height * scale:.3g} px, beyond the limit of "
                       f"{MAX_COORDINATE:g} px")
    try:
        check_tolerance(tolerance, math.ceil(width * scale), math.ceil(height * scale))
    except ImportLimitError as exc:
        raise SvgError(f"{path}: {exc}") from None

    layers: list[Layer] = []
    counts: dict[str, int] = {}
    try:
        with budget_scope(VertexBudget()):
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
    except ValueError as exc:  # limits, malformed values found on the way
        raise SvgError(f"{path}: {exc}") from None
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
    if isinstance(element, se.Use) or values.get("tag") == "use":
        attrs = values.get("attributes") or {}
        href = str(attrs.get("href", attrs.get(XLINK_HREF, attrs.get("xlink:href", "")))).strip()
        if not href.startswith("#"):
            ignored.append(f"{name}: <use> of {href[:80]!r} not imported (only references inside the file are "
                           "followed; nothing is fetched)")
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

    problem = _malformed(values.get("attributes") or {}, type(element).__name__)
    if problem:
        ignored.append(f"{name}: {problem}; element not imported")
        return []
    segments = shape_segments(abs(se.Path(element)))  # abs: the transform applied to the points
    if any(not np.isfinite(s.ctrl).all() for segs, _ in segments for s in segs):
        ignored.append(f"{name}: a coordinate is not a finite number after its transform; element not imported")
        return []
    reach = max((float(np.abs(s.ctrl).max()) for segs, _ in segments for s in segs), default=0.0)
    if reach > MAX_COORDINATE:
        ignored.append(f"{name}: coordinates reach {reach:.3g} px, beyond +-{MAX_COORDINATE:g}; element not imported")
        return []
    subpaths = flatten_segments(segments, tol)
    layers = []
    fill = _paint(values.get("fill"), element.fill, name, "fill", ignored)
    if fill is not None and subpaths:
        rule = "evenodd" if str(values.get("fill-rule", "nonzero")).strip() == "evenodd" else "nonzero"
        layers.append(Layer(fill, fill_regions(subpaths, rule), name + " fill"))
    stroke = _paint(values.get("stroke"), element.stroke, name, "stroke", ignored)
    raw_width = values.get("stroke-width")
    width = element.implicit_stroke_width
    width = float(width) if width is not None else 0.0
    if stroke is not None and segments and raw_width not in (None, "") and not math.isfinite(_number(raw_width, 1.0)):
        ignored.append(f"{name}: stroke-width {raw_width} is not a finite number; stroke not imported")
    elif stroke is not None and segments and not math.isfinite(width):
        ignored.append(f"{name}: stroke width {width} is not a finite number after the transform; stroke not imported")
    elif stroke is not None and segments and reach + width > MAX_COORDINATE:
        ignored.append(f"{name}: stroke width {width:.3g} px reaches beyond +-{MAX_COORDINATE:g}; stroke not imported")
    elif stroke is not None and segments and width > 0:
        if values.get("stroke-dasharray") not in (None, "", "none"):
            ignored.append(f"{name}: stroke-dasharray ignored (stroked solid)")
        cap = str(values.get("stroke-linecap", "butt")).strip()
        join = str(values.get("stroke-linejoin", "miter")).strip()
        if join in ("miter-clip", "arcs"):
            ignored.append(f"{name}: stroke-linejoin {join} drawn as miter (bevel beyond the miter limit)")
            join = "miter"
        limit = _number(values.get("stroke-miterlimit"), 4.0)
        if not (math.isfinite(limit) and limit >= 1.0):
            ignored.append(f"{name}: stroke-miterlimit {values.get('stroke-miterlimit')} is not a number >= 1 "
                           "(an error in SVG); 4 used")
            limit = 4.0
        regions = stroke_regions(
            segments, width, cap=cap if cap in STROKE_CAPS else "butt", join=join if join in STROKE_JOINS else "miter",
            miter_limit=limit, tol=tol,
        )
        layers.append(Layer(stroke, regions, name + " stroke"))
    return [layer for layer in layers if layer.regions]


def _malformed(attrs: dict, kind: str) -> str | None:
    """Why an element's own geometry is malformed (SVG: not rendered), or None."""
    for key in GEOMETRY_ATTRS:
        raw = attrs.get(key)
        if raw is not None and NOT_FINITE.search(str(raw)):
            return f"{key}={str(raw)[:40]!r} is not a finite number"
    style = str(attrs.get("style", ""))
    if NOT_FINITE.search(style):
        return f"style {style[:40]!r} holds a value that is not a finite number"
    negative = {"Rect": ("width", "height", "rx", "ry"), "Circle": ("r",), "Ellipse": ("rx", "ry")}.get(kind, ())
    for key in negative:
        raw = attrs.get(key)
        if raw is None:
            continue
        try:
            value = float(re.match(r"\s*[-+]?[0-9.eE+-]+", str(raw)).group(0))
        except (AttributeError, ValueError):
            continue
        if value < 0:
            return f"{key}={raw!r} is negative (an error in SVG: the element is not rendered)"
    return None


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


def shape_segments(path) -> list[tuple[list[Seg], bool]]:
    """A reified svgelements Path as its true segments, subpath by subpath: a list of
    (segments, closed), absolute pixel coordinates."""
    import svgelements as se

    subpaths: list[tuple[list[Seg], bool]] = []
    segs: list[Seg] = []
    start = None
    at = None

    def finish(closed: bool):
        nonlocal segs
        if segs:
            subpaths.append((segs, closed))
        elif closed and start is not None:  # "M x y Z": a subpath of zero length
            subpaths.append(([Seg("line", np.array([start, start], dtype=np.float64))], True))
        segs = []

    for seg in path:
        if isinstance(seg, se.Move):
            finish(False)
            start = at = (seg.end.x, seg.end.y)
            continue
        if at is None and seg.start is not None:
            start = at = (seg.start.x, seg.start.y)
        if isinstance(seg, se.Close):
            if at is not None and start is not None and at != start:
                segs.append(Seg("line", np.array([at, start], dtype=np.float64)))
            elif not segs and start is not None:
                segs.append(Seg("line", np.array([start, start], dtype=np.float64)))
            finish(True)
            at = start
            continue
        end = (seg.end.x, seg.end.y)
        if isinstance(seg, se.Line):
            segs.append(Seg("line", np.array([at, end], dtype=np.float64)))
        elif isinstance(seg, se.QuadraticBezier):
            segs.append(Seg("bezier", np.array([at, (seg.control.x, seg.control.y), end], dtype=np.float64)))
        elif isinstance(seg, se.CubicBezier):
            segs.append(Seg("bezier", np.array(
                [at, (seg.control1.x, seg.control1.y), (seg.control2.x, seg.control2.y), end], dtype=np.float64)))
        elif isinstance(seg, se.Arc):
            if seg.start == seg.end and not seg.sweep:
                continue
            arc = (float(seg.center.x), float(seg.center.y), float(seg.rx), float(seg.ry), float(seg.get_rotation()),
                   float(seg.get_start_t()), float(seg.sweep))
            segs.append(Seg("arc", np.array([at, end], dtype=np.float64), arc))
        else:
            raise SvgError(f"unknown path segment {type(seg).__name__}")
        at = end
    finish(False)
    return subpaths


def flatten_segments(subpaths, tol: float) -> list[Subpath]:
    """Segments (from :func:`shape_segments`) flattened to ``tol``: closed polylines for fills."""
    out = []
    for segs, closed in subpaths:
        points = [segs[0].start]
        charge(len(segs))
        for seg in segs:
            if seg.kind == "line":
                points.append(seg.end)
            elif seg.kind == "bezier":
                points.extend(bezier_points(seg.ctrl, tol))
            else:
                cx, cy, rx, ry, rot, start, sweep = seg.arc
                arc = arc_points((cx, cy), rx, ry, rot, start, sweep, tol)
                arc[-1] = seg.end
                points.extend(arc)
        if len(points) >= 2:
            out.append(Subpath(np.array(points, dtype=np.float64), closed))
    return out


def shape_subpaths(path, tol: float) -> list[Subpath]:
    """A reified svgelements Path as flattened subpaths (absolute pixel coordinates)."""
    return flatten_segments(shape_segments(path), tol)


def _local_name(tag) -> str:
    tag = str(tag)
    return tag.rsplit("}", 1)[-1] if tag.startswith("{") else tag


def count_elements(root, limit: int = MAX_ELEMENTS) -> int:
    """Elements of the tree once every ``<use>`` is expanded, counted without expanding
    (each element's count once, memoised); stops early past ``limit``. A reference cycle
    raises :class:`SvgError`."""
    by_id = {}
    for el in root.iter():
        ident = el.get("id")
        if ident is not None:
            by_id.setdefault(ident, el)
    memo: dict[int, int] = {}
    state: dict[int, int] = {}  # 1 on the stack, 2 done

    def count(el) -> int:
        key = id(el)
        if state.get(key) == 2:
            return memo[key]
        if state.get(key) == 1:
            raise SvgError(f"<use> references form a cycle through {el.get('id') or _local_name(el.tag)!r}")
        state[key] = 1
        total = 1
        for child in el:
            total += count(child)
            if total > limit:
                break
        if _local_name(el.tag) == "use":
            href = el.get("href") or el.get(XLINK_HREF) or ""
            target = by_id.get(href[1:]) if href.startswith("#") else None
            if target is not None:
                total += count(target)
        state[key] = 2
        memo[key] = min(total, limit + 1)
        return memo[key]

    import sys

    old = sys.getrecursionlimit()
    sys.setrecursionlimit(max(old, 20000))
    try:
        return count(root)
    except RecursionError:
        raise SvgError("elements are nested too deeply to import") from None
    finally:
        sys.setrecursionlimit(old)


def _check_document(data: bytes, path: Path, ignored: list[str]) -> None:
    """Refuse, before svgelements expands anything, a file that is not an SVG document, a
    malformed viewBox, and more than MAX_ELEMENTS elements after ``<use>`` expansion."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.fromstring(data)
    except ET.ParseError as exc:
        raise SvgError(f"{path}: not a readable SVG (XML: {exc})") from None
    except Exception as exc:  # entity limits of the XML parser and the like
        raise SvgError(f"{path}: not a readable SVG ({type(exc).__name__}: {exc})") from None
    if _local_name(root.tag) != "svg":
        raise SvgError(f"{path}: not an SVG document (its root element is <{_local_name(root.tag)}>, not <svg>)")
    box = root.get("viewBox")
    if box is not None:
        parts = re.split(r"[\s,]+", box.strip())
        try:
            numbers = [float(v) for v in parts]
        except ValueError:
            numbers = []
        if len(numbers) != 4 or not all(map(math.isfinite, numbers)):
            raise SvgError(f"{path}: viewBox {box[:60]!r} is not four finite numbers")
        if numbers[2] <= 0 or numbers[3] <= 0:
            raise SvgError(f"{path}: viewBox {box[:60]!r} has a width or height that is not positive (an error in "
                           "SVG; zero disables rendering)")
    try:
        n = count_elements(root)
    except SvgError as exc:
        raise SvgError(f"{path}: {exc}") from None
    if n > MAX_ELEMENTS:
        raise SvgError(f"{path}: more than {MAX_ELEMENTS} elements once <use> references are expanded (the limit)")
    # vertices, estimated from the numbers in path data and point lists (two per vertex),
    # before svgelements builds an object per segment
    total = 0
    for el in root.iter():
        for key in ("d", "points"):
            raw = el.get(key)
            if not raw:
                continue
            vertices = len(NUMBER.findall(raw)) // 2
            total += vertices
            if vertices > MAX_EDGES:
                name = f"#{el.get('id')}" if el.get("id") else f"a <{_local_name(el.tag)}>"
                raise SvgError(f"{path}: {name} has about {vertices} vertices, over the limit of {MAX_EDGES} "
                               "for one outline")
    if total > MAX_VERTICES:
        raise SvgError(f"{path}: about {total} vertices in path data, over the limit of {MAX_VERTICES}")
