"""SVG files to scenes: ``aaeval import svg FILE.svg -o SCENE.toml``.

The file is read by :func:`aaeval.readlimits.read_bytes` and checked as XML first (root
``<svg>``, a valid ``viewBox``, at most :data:`~aaeval.importers.limits.MAX_ELEMENTS`
elements once ``<use>`` is expanded, counted without expanding). The CSS cascade, colours
and lengths come from :mod:`aaeval.importers.svgstyle` (cssselect2 and tinycss2); path
data, shapes and transforms from :mod:`aaeval.importers.svgpath`. The tree is walked as
SVG 2 renders it: ``display: none`` subtrees, definitions, unknown elements and the
children of shapes are not drawn; ``<use>`` draws its target (the first element with that
id) with its own style as the parent; nested ``<svg>`` and ``<use>`` of ``<svg>`` or
``<symbol>`` establish a viewport (``viewBox``, ``preserveAspectRatio``) and clip to it
unless ``overflow`` is visible; ``clip-path`` keeps what lies inside the union of its
``<clipPath>``'s shapes (each under its clip-rule; userSpaceOnUse or objectBoundingBox
units on shapes); strokes are dashed (:mod:`aaeval.importers.dash`); markers are drawn
at the vertices of paths, lines, polylines and polygons, clipped to their viewport;
``paint-order`` orders fill, stroke and markers.

Each shape's true segments are kept in user space: fills are flattened
(:mod:`aaeval.importers.flatten`) to the tolerance divided by the transform's largest
stretch and then transformed, and their fill rule resolved in float64
(:mod:`aaeval.importers.fill`); strokes are outlined in user space with the user-space
width (:mod:`aaeval.importers.stroke`) and then transformed, so skews and non-uniform
scales stretch the stroke as SVG draws it. Each painted part is a layer in document order
(later nearer). Colours are sRGB in the file and linear in the scene.

What the scene format cannot hold is never dropped silently: text, images, gradient
and pattern paints, masks, filters, clip paths it cannot apply, CSS that cannot be
applied, and opacity (drawn opaque) are listed by element (``#id``, or ``tag[n]``: the n-th drawn
element of that tag, 0-based, definitions such as clip-path contents not counted) in the
result and in the scene's ``[svg].ignored``. So is every malformed element SVG does not
render (NaN or infinite numbers, negative sizes and radii), geometry beyond
:data:`MAX_COORDINATE`, and ``<use>`` of anything outside the file (nothing is fetched).
"""

from __future__ import annotations

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
from aaeval.importers.dash import dash_subpaths, path_length
from aaeval.importers.fill import resolve_fill
from aaeval.importers.shapes import (STROKE_CAPS, STROKE_JOINS, Region, Subpath, clip_regions, fill_regions,
                                     stroke_regions)
from aaeval.importers.svgpath import (IDENTITY, apply, compose, ellipse_outline, max_stretch, parse_path,
                                      parse_points, parse_transform, rect_outline, viewbox_transform)
from aaeval.importers.svgpath import rotate as rotation
from aaeval.importers.svgpath import scale as scaling
from aaeval.importers.svgpath import translate
from aaeval.importers.svgstyle import (GEOMETRY, INHERITED, INITIAL, NOT_APPLIED, LengthError, Lengths, Styles,
                                       font_size, parse_color, parse_paint)

__all__ = ["import_svg", "SvgError", "count_elements", "flatten_segments"]

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

# properties whose effect the scene format cannot hold
UNSUPPORTED = {"mask": "mask", "filter": "filter"}
SHAPES = ("rect", "circle", "ellipse", "line", "polyline", "polygon", "path")
MARKABLE = ("path", "line", "polyline", "polygon")
CONTAINERS = ("g", "a")
NOT_IMPORTED = {"text": "text element not imported (use 'aaeval import text')", "image": "image not imported",
                "foreignObject": "foreignObject not imported", "video": "video not imported",
                "audio": "audio not imported", "iframe": "iframe not imported", "canvas": "canvas not imported"}
# elements that establish a viewport clip it unless overflow says otherwise (SVG 2's UA style sheet)
CLIPPING = ("svg", "symbol", "marker")
MAX_USE_DEPTH = 64
PAINT_PARTS = ("fill", "stroke", "markers")
PAINT_SERVERS = ("linearGradient", "radialGradient", "pattern", "meshgradient", "hatch")
GRADIENTS = ("linearGradient", "radialGradient")
ANIMATION = ("animate", "set", "animateTransform", "animateMotion", "animateColor", "discard")


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
    if not (math.isfinite(scale) and scale > 0):
        raise SvgError(f"scale must be a positive number, got {scale!r}")
    from aaeval.readlimits import read_bytes

    path = Path(path)
    data = read_bytes(path, what="SVG file")  # regular files of bounded size only
    ignored: list[str] = []
    root = _check_document(data, path)  # root element, viewBox, element count after <use>
    try:
        walk = _Walk(root, tolerance, ignored)
        width, height, box, aspect, root_style, lengths = walk.root_viewport()
    except SvgError as exc:
        raise SvgError(f"{path}: {exc}") from None
    if not (width > 0 and height > 0 and math.isfinite(width) and math.isfinite(height)):
        raise SvgError(f"{path}: the SVG has no positive width and height")
    if width * scale > MAX_COORDINATE or height * scale > MAX_COORDINATE:
        raise SvgError(f"{path}: the SVG is {width * scale:.3g}x{height * scale:.3g} px, beyond the limit of "
                       f"{MAX_COORDINATE:g} px")
    try:
        check_tolerance(tolerance, math.ceil(width * scale), math.ceil(height * scale))
    except ImportLimitError as exc:
        raise SvgError(f"{path}: {exc}") from None

    ctm = scaling(scale, scale)
    if box is not None:
        ctm = compose(ctm, viewbox_transform(box, aspect, width, height))
    layers: list[Layer] = []
    import sys

    depth = sys.getrecursionlimit()
    sys.setrecursionlimit(max(depth, 4 * MAX_ELEMENTS))  # a few frames per nesting level
    try:
        with budget_scope(VertexBudget()):
            if walk.root_drawn(root_style):
                walk.children(root, root_style, ctm, lengths, None, layers)
    except RecursionError:
        raise SvgError(f"{path}: elements are nested too deeply to import") from None
    except SvgError as exc:
        raise SvgError(f"{path}: {exc}") from None
    except ValueError as exc:  # limits, malformed values found on the way
        raise SvgError(f"{path}: {exc}") from None
    except Exception as exc:
        raise SvgError(f"{path}: could not import ({type(exc).__name__}: {exc})") from None
    finally:
        sys.setrecursionlimit(depth)

    source = {"file": file_ref if file_ref is not None else str(path), "scale": float(scale),
              "tolerance": float(tolerance), "ignored": ignored}
    document, cut = scene_document(
        math.ceil(width * scale - 1e-9), math.ceil(height * scale - 1e-9), background, layers,
        extension=("svg", source), frames=frames, translate=translate,
    )
    return ImportResult(document, ignored, cut)


def _svg_tag(el) -> str | None:
    """The local name of an SVG element (no namespace is taken as SVG), else None."""
    tag = el.tag
    if not isinstance(tag, str):
        return None  # comments, processing instructions
    if tag.startswith(SVG_NS):
        return tag[len(SVG_NS):]
    return None if tag.startswith("{") else tag


def _number(raw, default: float) -> float:
    try:
        return float(raw) if raw not in (None, "") else default
    except (TypeError, ValueError):
        return default


def _opacity(raw) -> float:
    """An opacity (number or percentage) clamped to [0, 1]; 1 when not valid."""
    text = str(raw).strip()
    try:
        value = float(text[:-1]) / 100 if text.endswith("%") else float(text)
    except ValueError:
        return 1.0
    return min(1.0, max(0.0, value)) if math.isfinite(value) else 1.0


def _conditions_pass(el) -> bool:
    """SVG 2's conditional processing: requiredExtensions (none supported), systemLanguage."""
    if el.get("requiredExtensions") is not None:
        return False
    languages = el.get("systemLanguage")
    if languages is not None:
        return any(lang.strip().lower().split("-")[0] == "en" for lang in languages.split(","))
    return True


def _angle(text: str) -> float | None:
    """A CSS angle in degrees, or None."""
    match = re.fullmatch(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)(deg|rad|grad|turn)?\s*", text)
    if not match:
        return None
    value = float(match.group(1))
    return value * {None: 1.0, "deg": 1.0, "rad": 180 / math.pi, "grad": 0.9, "turn": 360.0}[match.group(2)]


def paint_order(value: str) -> list[str]:
    """The parts in the order ``paint-order`` paints them (SVG 2, 13.6)."""
    words = value.split()
    if not words or words == ["normal"] or any(w not in PAINT_PARTS for w in words) or len(set(words)) != len(words):
        return list(PAINT_PARTS)
    return words + [p for p in PAINT_PARTS if p not in words]


class _Walk:
    """The rendering tree walk: layers of every drawn element, in painting order."""

    def __init__(self, root, tol: float, ignored: list[str]):
        self.root = root
        self.tol = tol
        self.ignored = ignored
        self.styles = Styles(root, SVG_NS)
        ignored.extend(self.styles.problems)
        self.by_id: dict[str, object] = {}
        self.parent: dict[int, object] = {}
        for el in root.iter():
            ident = el.get("id")
            if ident is not None:
                self.by_id.setdefault(ident, el)  # the first element with an id is the one referenced
            for child in el:
                self.parent[id(child)] = el
        self.counts: dict[str, int] = {}
        self.tree_styles: dict[int, dict] = {}
        self.use_depth = 0
        self.drawn = 0  # elements drawn, markers' contents once per vertex
        self.active_markers: set[int] = set()  # a marker drawn inside itself is an error: not drawn
        self.reported: set[str] = set()
        for k, el in enumerate(el for el in root.iter() if _svg_tag(el) in ANIMATION):
            self.note(f"{'#' + el.get('id') if el.get('id') else f'<{_svg_tag(el)}>[{k}]'}: animation not applied "
                      "(drawn as the document stands before it runs)")

    def note(self, text: str) -> None:
        if text not in self.reported:
            self.reported.add(text)
            self.ignored.append(text)

    # styles ---------------------------------------------------------------
    def style(self, el, parent: dict | None, name: str | None = None) -> dict:
        """The computed style of ``el`` with ``parent`` as the inherited style."""
        declared = self.styles.of(el)
        out: dict = {}
        for prop, initial in INITIAL.items():
            value = declared.get(prop)
            inherit = parent is not None and prop in INHERITED
            low = value.strip().lower() if value is not None else None
            if low is None or low == "unset":
                value = parent[prop] if inherit else initial
            elif low == "inherit":
                value = parent[prop] if parent is not None else initial
            elif low == "initial":
                value = initial
            out[prop] = value
        for prop in GEOMETRY:
            value = declared.get(prop)
            if value is not None and value.strip().lower() == "inherit":
                value = parent.get(prop) if parent else None
            if value is not None:
                out[prop] = value
        # colour: currentColor (and anything invalid) takes the parent's
        parent_color = parent["color"] if parent else INITIAL["color"]
        try:
            color = parse_color(out["color"])
        except ValueError:
            color = None
        out["color"] = out["color"] if isinstance(color, tuple) else parent_color
        for prop in ("fill", "stroke"):
            try:
                valid = parse_paint(out[prop]) is not None
            except ValueError:
                valid = True  # a colour space aaeval cannot convert: reported where painted
            if not valid:
                out[prop] = parent[prop] if parent else INITIAL[prop]
        parent_font = parent["font"] if parent else font_size(INITIAL["font-size"], 16.0, 16.0)
        root_font = parent["root-font"] if parent else None
        size = font_size(out["font-size"], parent_font, root_font or parent_font)
        out["font"] = size if size is not None else parent_font
        out["root-font"] = root_font if root_font is not None else out["font"]
        if "overflow" not in declared:
            out["overflow"] = "hidden" if _svg_tag(el) in CLIPPING and el is not self.root else "visible"
        if name is not None:
            for prop in sorted(set(declared) & NOT_APPLIED):
                self.note(f"{name}: CSS property {prop}: {declared[prop][:40]} not applied")
        return out

    def tree_style(self, el) -> dict:
        """The computed style of ``el`` where it stands in the document (markers' contents
        inherit from the marker's ancestors, not from the shape that uses it)."""
        key = id(el)
        if key not in self.tree_styles:
            parent = self.parent.get(key)
            self.tree_styles[key] = self.style(el, self.tree_style(parent) if parent is not None else None)
        return self.tree_styles[key]

    def root_viewport(self):
        style = self.tree_style(self.root)
        box = _viewbox(self.root.get("viewBox"))  # a disabling one was refused before
        box = None if box is DISABLED else box
        aspect = self.root.get("preserveAspectRatio", "")
        fallback = (box[2], box[3]) if box is not None else (100.0, 100.0)
        lengths = Lengths(fallback, style["font"], fallback, style["root-font"])
        size, given = [], []
        for prop, axis, base in (("width", "x", fallback[0]), ("height", "y", fallback[1])):
            raw = (style.get(prop) or "").strip()
            value, given_here = base, False
            if raw and raw.lower() != "auto":
                try:
                    if raw.endswith("%"):
                        value, given_here = float(raw[:-1]) / 100 * base, True
                    else:
                        value, given_here = lengths.resolve(raw, axis), True
                except (LengthError, ValueError):
                    pass
            size.append(value)
            given.append(given_here)
        if box is not None and given[0] != given[1]:  # one side given: the other keeps the viewBox's shape
            if given[0]:
                size[1] = size[0] * box[3] / box[2]
            else:
                size[0] = size[1] * box[2] / box[3]
        view = (box[2], box[3]) if box is not None else tuple(size)
        return size[0], size[1], box, aspect, style, Lengths(view, style["font"], view, style["root-font"])

    def root_drawn(self, style) -> bool:
        """Whether the root draws anything; what it asks that is not applied is listed."""
        opacity = _opacity(style["opacity"])
        if style["display"].strip().lower() == "none" or opacity <= 0:
            return False
        if opacity < 1:
            self.note(f"<svg>: opacity {style['opacity']} ignored (drawn opaque)")
        for prop, what in {**UNSUPPORTED, "clip-path": "clip path"}.items():
            if style[prop].strip().lower() not in ("", "none"):
                self.note(f"<svg>: {what} on the root not applied")
        if self.root.get("transform"):
            self.note("<svg>: transform on the root element not applied")
        return True

    def name(self, el, tag: str) -> str:
        n = self.counts.get(tag, 0)
        self.counts[tag] = n + 1
        return f"#{el.get('id')}" if el.get("id") else f"{tag}[{n}]"

    # the walk -------------------------------------------------------------
    def children(self, el, style, ctm, lengths, context, out) -> None:
        for child in el:
            self.draw(child, style, ctm, lengths, context, out)

    def draw(self, el, parent: dict, ctm, lengths: Lengths, context, out: list[Layer]) -> None:
        tag = _svg_tag(el)
        if tag is None or not _conditions_pass(el):
            return
        if tag not in SHAPES and tag not in CONTAINERS and tag not in ("svg", "use", "switch") \
                and tag not in NOT_IMPORTED:
            return  # definitions, metadata and unknown elements are not rendered, nor their children
        self.drawn += 1
        if self.drawn > MAX_ELEMENTS:
            raise ImportLimitError(f"more than {MAX_ELEMENTS} elements to draw once <use> references and markers "
                                   "are expanded (the limit)")
        name = self.name(el, tag)
        style = self.style(el, parent, name)
        if style["display"].strip().lower() == "none":
            return
        if tag in NOT_IMPORTED:
            self.note(f"{name}: {NOT_IMPORTED[tag]}")
            return
        lengths = lengths.with_font(style["font"])
        opacity = _opacity(style["opacity"])
        if opacity <= 0:
            return  # draws nothing
        if opacity < 1:
            self.note(f"{name}: opacity {style['opacity']} ignored (drawn opaque)")
        if tag in SHAPES and style["shape-rendering"].strip().lower() in ("crispedges", "optimizespeed"):
            self.note(f"{name}: shape-rendering {style['shape-rendering']} ignored (drawn anti-aliased)")
        for prop in ("mix-blend-mode", "isolation"):
            if style[prop].strip().lower() not in (INITIAL[prop], "isolate"):
                self.note(f"{name}: {prop} {style[prop]} ignored (drawn normal)")
        transform = el.get("transform")
        if transform is not None:
            own = parse_transform(transform)
            if own is None:
                self.note(f"{name}: transform {transform[:40]!r} is not valid; drawn untransformed")
            else:
                ctm = compose(ctm, own)
        unsupported = [(prop, what) for prop, what in UNSUPPORTED.items()
                       if style[prop].strip().lower() not in ("", "none")]
        clipped = style["clip-path"].strip().lower() not in ("", "none")
        mine: list[Layer] = [] if clipped else out
        if tag in SHAPES:
            for prop, what in unsupported:
                self.note(f"{name}: {what} not supported; element not imported")
            if not unsupported:
                try:
                    self.shape(el, tag, name, style, ctm, lengths, context, mine)
                except (ArithmeticError, TypeError, IndexError, np.linalg.LinAlgError) as exc:
                    # one element's numbers, not the file: SVG renders the rest
                    self.note(f"{name}: could not be built ({type(exc).__name__}: {exc}); element not imported")
                except SvgError:
                    raise
                except ValueError as exc:  # a stated limit, passed while building this element
                    raise SvgError(f"{name}: {exc}") from None
        else:
            for prop, what in unsupported:
                self.note(f"{name}: {what} on a group not applied (its shapes are drawn unmasked, unfiltered)")
            if tag in CONTAINERS:
                self.children(el, style, ctm, lengths, context, mine)
            elif tag == "switch":
                for child in el:
                    if _svg_tag(child) is not None and _conditions_pass(child):
                        self.draw(child, style, ctm, lengths, context, mine)
                        break
            elif tag == "svg":
                self.viewport(el, el, name, style, ctm, lengths, context, mine)
            elif tag == "use":
                self.use(el, name, style, ctm, lengths, context, mine)
        if clipped and mine:
            box = self.bounding_box(el, tag, style, lengths) if tag in SHAPES else None
            clip = self.clip_path(style["clip-path"], name, ctm, box, lengths)
            out.extend(mine if clip is None else _clip_layers(mine, clip))

    def bounding_box(self, el, tag, style, lengths):
        """A shape's bounding box in its user space (x, y, w, h), from its flattened outline."""
        try:
            subpaths = flatten_segments(self.geometry(el, tag, style, lengths), self.tol * 1e-3)
        except LengthError:
            return None
        if not subpaths:
            return None
        points = np.concatenate([s.points for s in subpaths])
        lo, hi = points.min(axis=0), points.max(axis=0)
        return (float(lo[0]), float(lo[1]), float(hi[0] - lo[0]), float(hi[1] - lo[1]))

    def clip_path(self, value: str, name: str, ctm, box, lengths: Lengths):
        """The region (device space) a ``clip-path`` keeps, or None where it is not applied
        (then listed): a union of the clipPath's shapes, each under its clip-rule."""
        paint = parse_paint(value) if value.strip().lower().startswith("url(") else None
        target = self.by_id.get(paint[1]) if paint and paint[0] == "url" and paint[1] else None
        if target is None or _svg_tag(target) != "clipPath":
            self.note(f"{name}: clip-path {value.strip()[:60]} is not a clipPath in the file; drawn unclipped")
            return None
        tstyle = self.tree_style(target)
        if tstyle["clip-path"].strip().lower() not in ("", "none"):
            self.note(f"{name}: clip-path #{target.get('id')} has a clip path of its own; drawn unclipped")
            return None
        space = compose(ctm, parse_transform(target.get("transform", "")) or IDENTITY)
        if target.get("clipPathUnits", "").strip() == "objectBoundingBox":
            if box is None or box[2] <= 0 or box[3] <= 0:
                if box is None:
                    self.note(f"{name}: clip-path in objectBoundingBox units on a group not applied; drawn unclipped")
                    return None
                return []  # a box of no area: nothing is kept
            space = compose(space, (box[2], 0.0, 0.0, box[3], box[0], box[1]))
        rings = []
        for child in target:
            shape, tag = child, _svg_tag(child)
            if tag is None or not _conditions_pass(child):
                continue
            placed = space
            style = self.tree_style(child)
            if style["display"].strip().lower() == "none" or style["visibility"].strip().lower() != "visible":
                continue
            if child.get("transform"):
                placed = compose(placed, parse_transform(child.get("transform")) or IDENTITY)
            if tag == "use":
                href = str(child.get("href") or child.get(XLINK_HREF) or "").strip()
                shape = self.by_id.get(href[1:]) if href.startswith("#") else None
                tag = _svg_tag(shape) if shape is not None else None
                if tag not in SHAPES:
                    continue
                style = self.style(shape, style)
                x, y = _number(child.get("x"), 0.0), _number(child.get("y"), 0.0)
                own = parse_transform(shape.get("transform", "")) or IDENTITY
                placed = compose(compose(placed, translate(x, y)), own)
            if tag not in SHAPES:
                if tag in NOT_IMPORTED:
                    self.note(f"{name}: clip-path #{target.get('id')} holds a <{tag}>; drawn unclipped")
                    return None
                continue
            try:
                segments = self.geometry(shape, tag, style, lengths.with_font(style["font"]))
            except LengthError:
                continue
            stretch = max_stretch(placed)
            if not segments or not (math.isfinite(stretch) and stretch > 0):
                continue
            rule = "evenodd" if style["clip-rule"].strip() == "evenodd" else "nonzero"
            flat = flatten_segments(segments, self.tol / stretch)
            subpaths = [Subpath(apply(placed, s.points), s.closed) for s in flat]
            rings.extend(ring for region in fill_regions(subpaths, rule) for ring in (region.outer, *region.holes))
        return [Region(outer, holes) for outer, holes in resolve_fill(rings, "nonzero")] if rings else []

    def viewport(self, el, size_from, name, style, ctm, lengths, context, out) -> None:
        """A nested viewport (``<svg>``, or ``<symbol>``/``<svg>`` through ``<use>``):
        placed at x, y, sized width x height, its viewBox mapped in, clipped to it."""
        def length(prop, axis, default):
            raw = size_from.get(prop) if size_from is not el and size_from.get(prop) is not None else style.get(prop)
            try:
                return lengths.resolve(raw, axis) if raw is not None and raw.strip() != "auto" else default
            except LengthError:
                return default

        full = lengths.viewport
        x = _own_length(style, "x", lengths)  # a <use> moves the viewport by its own x, y
        y = _own_length(style, "y", lengths)
        w = length("width", "x", full[0])
        h = length("height", "y", full[1])
        if not (w > 0 and h > 0):
            return  # a viewport of no area renders nothing
        box = _viewbox(el.get("viewBox"))
        if box is DISABLED:
            return
        inner = compose(ctm, translate(x, y))
        if box is not None:
            inner = compose(inner, viewbox_transform(box, el.get("preserveAspectRatio", ""), w, h))
        view = (box[2], box[3]) if box is not None else (w, h)
        layers: list[Layer] = []
        self.children(el, style, inner, lengths.with_viewport(view), context, layers)
        if style["overflow"].strip().lower() not in ("visible", "auto"):
            corners = np.array([[x, y], [x + w, y], [x + w, y + h], [x, y + h]], dtype=np.float64)
            layers = _clip_layers(layers, apply(ctm, corners))
        out.extend(layers)

    def use(self, el, name, style, ctm, lengths, context, out) -> None:
        href = str(el.get("href") or el.get(XLINK_HREF) or "").strip()
        if not href.startswith("#"):
            if href:
                self.note(f"{name}: <use> of {href[:80]!r} not imported (only references inside the file are "
                          "followed; nothing is fetched)")
            return
        target = self.by_id.get(href[1:])
        if target is None or self.use_depth >= MAX_USE_DEPTH:
            return  # a reference to nothing renders nothing
        try:
            x = lengths.resolve(style.get("x", "0"), "x")
            y = lengths.resolve(style.get("y", "0"), "y")
        except LengthError:
            x = y = 0.0
        ctm = compose(ctm, translate(x, y))
        paints = {part: self.paint(style[part], style, part, name, context) for part in ("fill", "stroke")}
        self.use_depth += 1
        try:
            kind = _svg_tag(target)
            if kind in ("symbol", "svg"):
                tname = self.name(target, kind)
                tstyle = self.style(target, style, tname)
                if tstyle["display"].strip().lower() != "none":
                    own = parse_transform(target.get("transform", "")) if kind == "symbol" else None
                    self.viewport(target, el, tname, tstyle, compose(ctm, own) if own else ctm, lengths, paints, out)
            else:
                self.draw(target, style, ctm, lengths, paints, out)
        finally:
            self.use_depth -= 1

    # paints ---------------------------------------------------------------
    def paint(self, raw: str, style: dict, what: str, name: str, context) -> np.ndarray | None:
        """The linear RGB a fill or stroke paints, or None when it paints nothing."""
        try:
            paint = parse_paint(raw)
        except ValueError as exc:
            self.note(f"{name}: {what}: {exc}; not painted")
            return None
        if paint is None or paint[0] == "none":
            return None
        if paint[0] == "context":
            return None if context is None else context.get(paint[1])
        if paint[0] == "url":
            target = self.by_id.get(paint[1]) if paint[1] else None
            if target is None or _svg_tag(target) not in PAINT_SERVERS:
                fallback = paint[2]
                if fallback is None or fallback[0] != "color":
                    return None  # a reference to nothing, no fallback colour: none
                paint = fallback
            else:
                paint = self.solid_gradient(target)
                if paint is None:
                    self.note(f"{name}: {what} {raw.strip()} (gradient or pattern) not imported")
                    return None
                if paint[0] == "none":
                    return None
        color = paint[1]
        if color == "currentcolor":
            color = parse_color(style["color"])
        alpha = color[3] * _opacity(style[f"{what}-opacity"])
        if alpha <= 0:
            return None  # transparent: nothing to draw
        if alpha < 1:
            self.note(f"{name}: {what} colour alpha {alpha:.3g} ignored (drawn opaque)")
        return srgb_to_linear(np.array(color[:3], dtype=np.float64))

    def solid_gradient(self, target):
        """What a gradient paints when it is one colour everywhere: ``("none",)`` without
        stops, ``("color", rgba)`` when its stops are all alike (one stop: SVG 2, 14.3.4);
        None for a true gradient or a pattern. Stops come from ``href`` when it has none."""
        stops, el, seen = [], target, set()
        while el is not None and id(el) not in seen and _svg_tag(el) in GRADIENTS:
            seen.add(id(el))
            stops = [child for child in el if _svg_tag(child) == "stop"]
            if stops:
                break
            href = str(el.get("href") or el.get(XLINK_HREF) or "").strip()
            el = self.by_id.get(href[1:]) if href.startswith("#") else None
        if _svg_tag(target) not in GRADIENTS:
            return None
        if not stops:
            return ("none",)
        colours = set()
        for stop in stops:
            style = self.tree_style(stop)
            color = parse_color(style["stop-color"])
            if color == "currentcolor":
                color = parse_color(style["color"])
            color = color if isinstance(color, tuple) else (0.0, 0.0, 0.0, 1.0)
            colours.add((*color[:3], color[3] * _opacity(style["stop-opacity"])))
        return ("color", colours.pop()) if len(colours) == 1 else None

    # shapes ---------------------------------------------------------------
    def geometry(self, el, tag, style, lengths: Lengths):
        """The shape's outline in user space: subpaths of segments, or [] (not rendered)."""
        def get(prop, axis, default=0.0):
            raw = style.get(prop) if prop in GEOMETRY else el.get(prop)
            if raw is None:
                return default
            try:
                return lengths.resolve(raw, axis)
            except LengthError as exc:
                if "not resolved" in str(exc):
                    raise
                return default  # an invalid value is its initial value

        if tag == "path":
            subpaths, _ = parse_path(el.get("d", ""))  # an error: drawn up to it
            return subpaths
        if tag == "rect":
            w, h = get("width", "x"), get("height", "y")
            if not (w > 0 and h > 0):
                return []
            rx, ry = get("rx", "x", None), get("ry", "y", None)
            rx = None if rx is not None and rx < 0 else rx  # negative: auto
            ry = None if ry is not None and ry < 0 else ry
            rx = ry if rx is None else rx
            ry = rx if ry is None else ry
            rx, ry = min(rx or 0.0, w / 2), min(ry or 0.0, h / 2)
            return rect_outline(get("x", "x"), get("y", "y"), w, h, rx, ry)
        if tag in ("circle", "ellipse"):
            if tag == "circle":
                rx = ry = get("r", "d")
            else:
                rx, ry = get("rx", "x", None), get("ry", "y", None)
                rx = ry if rx is None else rx  # auto: the other radius
                ry = rx if ry is None else ry
            if rx is None or not (rx > 0 and ry > 0):
                return []
            return ellipse_outline(get("cx", "x"), get("cy", "y"), rx, ry)
        if tag == "line":
            ends = [get(k, k[0]) for k in ("x1", "y1", "x2", "y2")]
            return parse_path("M {!r} {!r} L {!r} {!r}".format(*ends))[0]
        points, _ = parse_points(el.get("points", ""))
        if len(points) < 2 and tag == "polyline" or len(points) < 2:
            return []
        d = "M " + " L ".join(f"{x!r} {y!r}" for x, y in points.tolist()) + (" Z" if tag == "polygon" else "")
        return parse_path(d)[0]

    def shape(self, el, tag, name, style, ctm, lengths, context, out) -> None:
        problem = _malformed(el.attrib, tag)
        if problem:
            self.note(f"{name}: {problem}; element not imported")
            return
        try:
            segments = self.geometry(el, tag, style, lengths)
        except LengthError as exc:
            self.note(f"{name}: {exc}; element not imported")
            return
        if not segments:
            return
        stretch = max_stretch(ctm)
        if not (math.isfinite(stretch) and stretch > 0):
            return  # a transform that collapses the shape draws nothing
        ctrl = np.concatenate([s.ctrl for segs, _ in segments for s in segs])
        placed = apply(ctm, ctrl)
        if not np.isfinite(placed).all():
            self.note(f"{name}: a coordinate is not a finite number after its transform; element not imported")
            return
        reach = float(np.abs(placed).max())
        if reach > MAX_COORDINATE:
            self.note(f"{name}: coordinates reach {reach:.3g} px, beyond +-{MAX_COORDINATE:g}; element not imported")
            return
        visible = style["visibility"].strip().lower() == "visible"
        fill = self.paint(style["fill"], style, "fill", name, context) if visible else None
        stroke = self.paint(style["stroke"], style, "stroke", name, context) if visible else None
        tol = self.tol / stretch
        parts: list[Layer] = []
        for part in paint_order(style["paint-order"]):
            if part == "fill" and fill is not None:
                rule = "evenodd" if style["fill-rule"].strip() == "evenodd" else "nonzero"
                subpaths = [Subpath(apply(ctm, s.points), s.closed) for s in flatten_segments(segments, tol)]
                parts.append(Layer(fill, fill_regions(subpaths, rule), name + " fill"))
            elif part == "stroke" and stroke is not None:
                self.stroke(segments, el, name, style, ctm, lengths, stroke, tol, stretch, reach, parts)
            elif part == "markers" and tag in MARKABLE:
                self.markers(segments, name, style, ctm, lengths, {"fill": fill, "stroke": stroke}, parts)
        out.extend(layer for layer in parts if layer.regions)

    def stroke_width(self, style, lengths) -> float:
        try:
            width = lengths.resolve(style["stroke-width"], "d")
        except LengthError:
            return 1.0
        return width if width >= 0 else 1.0

    def stroke(self, segments, el, name, style, ctm, lengths, color, tol, stretch, reach, out) -> None:
        raw = style["stroke-width"]
        if not math.isfinite(_number(raw, 1.0)):
            self.note(f"{name}: stroke-width {raw} is not a finite number; stroke not imported")
            return
        width = self.stroke_width(style, lengths)
        if width <= 0:
            return
        if reach + width * stretch > MAX_COORDINATE:
            self.note(f"{name}: stroke width {width * stretch:.3g} px reaches beyond +-{MAX_COORDINATE:g}; "
                      "stroke not imported")
            return
        segments = self.dashes(segments, el, name, style, lengths)
        if style["vector-effect"].strip().lower() == "non-scaling-stroke":
            self.note(f"{name}: vector-effect non-scaling-stroke ignored (stroke scaled)")
        cap = style["stroke-linecap"].strip()
        join = style["stroke-linejoin"].strip()
        if join in ("miter-clip", "arcs"):
            self.note(f"{name}: stroke-linejoin {join} drawn as miter (bevel beyond the miter limit)")
            join = "miter"
        limit = _number(style["stroke-miterlimit"], 4.0)
        if not (math.isfinite(limit) and limit >= 1.0):
            self.note(f"{name}: stroke-miterlimit {style['stroke-miterlimit']} is not a number >= 1 "
                      "(an error in SVG); 4 used")
            limit = 4.0
        regions = stroke_regions(
            segments, width, cap=cap if cap in STROKE_CAPS else "butt", join=join if join in STROKE_JOINS else "miter",
            miter_limit=limit, tol=tol, transform=lambda ring: apply(ctm, ring),
        )
        out.append(Layer(color, regions, name + " stroke"))

    def dashes(self, segments, el, name, style, lengths):
        """The subpaths the stroke draws: the dashes of stroke-dasharray, or all of them
        (none, a negative or invalid value, or a pattern summing to zero: solid)."""
        raw = style["stroke-dasharray"].strip()
        if raw.lower() in ("", "none"):
            return segments
        try:
            pattern = [lengths.resolve(v, "d") for v in re.split(r"[\s,]+", raw) if v]
            offset = lengths.resolve(style["stroke-dashoffset"], "d")
        except LengthError as exc:
            if "not resolved" in str(exc):
                self.note(f"{name}: stroke-dasharray: {exc}; stroked solid")
            return segments
        if not pattern or min(pattern) < 0 or sum(pattern) <= 0 or not all(map(math.isfinite, pattern + [offset])):
            return segments
        declared = _number(el.get("pathLength"), 0.0)
        if declared > 0 and math.isfinite(declared):  # lengths along the path are in its own units
            factor = path_length(segments) / declared
            pattern, offset = [v * factor for v in pattern], offset * factor
            if sum(pattern) <= 0:
                return segments
        return dash_subpaths(segments, pattern, offset, budget=charge)

    # markers --------------------------------------------------------------
    def markers(self, segments, name, style, ctm, lengths, paints, out) -> None:
        refs = {}
        for where in ("start", "mid", "end"):
            paint = parse_paint(style[f"marker-{where}"]) if style[f"marker-{where}"].strip() != "none" else None
            target = self.by_id.get(paint[1]) if paint and paint[0] == "url" and paint[1] else None
            if target is not None and _svg_tag(target) == "marker":
                refs[where] = target
        if not refs:
            return
        stroke_width = self.stroke_width(style, lengths)
        vertices = _marker_vertices(segments)
        for k, (point, incoming, outgoing) in enumerate(vertices):
            where = "start" if k == 0 else "end" if k == len(vertices) - 1 else "mid"
            if where in refs:
                self.marker(refs[where], where, point, incoming, outgoing, stroke_width, ctm, lengths, paints, out)

    def marker(self, el, where, point, incoming, outgoing, stroke_width, ctm, lengths, paints, out) -> None:
        if self.use_depth >= MAX_USE_DEPTH or id(el) in self.active_markers:
            return
        style = self.tree_style(el)
        mlengths = lengths.with_font(style["font"])
        try:
            mw = mlengths.resolve(el.get("markerWidth", "3"), "x")
            mh = mlengths.resolve(el.get("markerHeight", "3"), "y")
        except LengthError:
            mw = mh = 3.0
        if not (mw > 0 and mh > 0):
            return
        box = _viewbox(el.get("viewBox"))
        if box is DISABLED:
            return
        fit = viewbox_transform(box, el.get("preserveAspectRatio", ""), mw, mh) if box is not None else IDENTITY
        try:
            ref = apply(fit, np.array([[mlengths.resolve(el.get("refX", "0"), "x"),
                                        mlengths.resolve(el.get("refY", "0"), "y")]]))[0]
        except LengthError:
            ref = apply(fit, np.zeros((1, 2)))[0]
        orient = el.get("orient", "0").strip()
        if orient in ("auto", "auto-start-reverse"):
            angle = _bisector(incoming, outgoing)
            if orient == "auto-start-reverse" and where == "start":
                angle += 180.0
        else:
            angle = _angle(orient) or 0.0
        units = 1.0 if el.get("markerUnits", "").strip() == "userSpaceOnUse" else stroke_width
        if units <= 0:
            return
        place = compose(ctm, compose(translate(*point), compose(rotation(angle), compose(scaling(units, units),
                                                                                       translate(-ref[0], -ref[1])))))
        view = (box[2], box[3]) if box is not None else (mw, mh)
        layers: list[Layer] = []
        self.use_depth += 1
        self.active_markers.add(id(el))
        try:
            self.children(el, style, compose(place, fit), mlengths.with_viewport(view), paints, layers)
        finally:
            self.use_depth -= 1
            self.active_markers.discard(id(el))
        if style["overflow"].strip().lower() not in ("visible", "auto"):
            corners = np.array([[0, 0], [mw, 0], [mw, mh], [0, mh]], dtype=np.float64)
            layers = _clip_layers(layers, apply(place, corners))
        out.extend(layers)


DISABLED = "disabled"  # a viewBox of no width or height: the element is not rendered (SVG 2, 8.6)


def _own_length(style, prop: str, lengths: Lengths) -> float:
    """An element's own x or y (0 when not given or not valid)."""
    try:
        return lengths.resolve(style[prop], prop) if style.get(prop) is not None else 0.0
    except LengthError:
        return 0.0


def _viewbox(raw):
    if raw is None:
        return None
    try:
        numbers = [float(v) for v in re.split(r"[\s,]+", raw.strip())]
    except ValueError:
        return None
    if len(numbers) != 4 or not all(map(math.isfinite, numbers)):
        return None  # not a viewBox: ignored
    if numbers[2] <= 0 or numbers[3] <= 0:
        return DISABLED
    return tuple(numbers)


def _direction(seg, t: float):
    if seg.degenerate():
        return None
    d = seg.tangents(np.array([t]))[0]
    return d if np.isfinite(d).all() and (d != 0).any() else None


def _marker_vertices(segments):
    """(point, incoming direction, outgoing direction) at every vertex of a path, in
    order (SVG 2, 13.7.3); a direction is None where there is none. Segments of no length
    give no direction: the nearest one with a length does (on a closed subpath, around
    its start), as the SVG WG resolved."""
    out = []
    for segs, closed in segments:
        ends = [_direction(seg, 1.0) for seg in segs]
        starts = [_direction(seg, 0.0) for seg in segs]
        n = len(segs)

        def incoming(k):  # the direction arriving at the end of segment k
            for j in range(k, k - n if closed else -1, -1):
                if ends[j % n] is not None:
                    return ends[j % n]
            return None

        def outgoing(k):  # the direction leaving at the start of segment k
            for j in range(k, k + n if closed else n):
                if starts[j % n] is not None:
                    return starts[j % n]
            return None

        out.append([segs[0].start, incoming(n - 1) if closed else None, outgoing(0)])
        for k, seg in enumerate(segs):
            following = outgoing(k + 1) if k + 1 < n or closed else None
            out.append([seg.end, incoming(k), following])
    return out


def _bisector(incoming, outgoing) -> float:
    """The angle (degrees) of the bisector of the incoming and outgoing directions."""
    angles = [math.atan2(d[1], d[0]) for d in (incoming, outgoing) if d is not None]
    if not angles:
        return 0.0
    if len(angles) == 1:
        return math.degrees(angles[0])
    turn = (angles[1] - angles[0] + math.pi) % (2 * math.pi) - math.pi
    return math.degrees(angles[0] + turn / 2)


def _clip_layers(layers: list[Layer], clip) -> list[Layer]:
    """Each layer's regions within ``clip``: a convex polygon (a viewport) or regions."""
    if isinstance(clip, np.ndarray):
        clip = [Region(clip, [])]
    return [Layer(layer.color, clip_regions(layer.regions, clip), layer.name) for layer in layers]


def _malformed(attrs: dict, kind: str) -> str | None:
    """Why an element's own geometry is malformed (SVG: not rendered), or None."""
    for key in GEOMETRY_ATTRS:
        raw = attrs.get(key)
        if raw is not None and NOT_FINITE.search(str(raw)):
            return f"{key}={str(raw)[:40]!r} is not a finite number"
    style = str(attrs.get("style", ""))
    if NOT_FINITE.search(style):
        return f"style {style[:40]!r} holds a value that is not a finite number"
    negative = {"rect": ("width", "height"), "circle": ("r",), "ellipse": ("rx", "ry")}.get(kind, ())
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


def _check_document(data: bytes, path: Path):
    """The document's root element. Refuse, before anything is expanded, a file that is not an SVG document, a
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
    # before any segment is built
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
    return root
