"""The SVG rendering tree walk: a layer for every painted part of every drawn element.

The tree is walked as SVG 2 renders it: ``display: none`` subtrees, definitions, unknown
elements and the children of shapes are not drawn; conditional processing
(``systemLanguage``, ``requiredExtensions``, ``<switch>``) is applied; ``<use>`` draws its
target (the first element with that id) with its own style as the parent, and of
``<svg>`` or ``<symbol>`` as a viewport (:mod:`aaeval.importers.svgviewport`);
``clip-path`` clips what the element draws (:mod:`aaeval.importers.svgclip`). A shape's
outline (:mod:`aaeval.importers.svggeometry`) is kept in user space: the fill is
flattened to the tolerance divided by the transform's largest stretch and then
transformed, its fill rule resolved in float64; the stroke
(:mod:`aaeval.importers.svgstroke`) and markers (:mod:`aaeval.importers.svgmarkers`)
follow in ``paint-order``. Each painted part is a layer in document order (later nearer).
Opacity, masks, filters, blend modes and what else the scene cannot hold are listed in the
report (:mod:`aaeval.importers.svgreport`).
"""

from __future__ import annotations

import math

import numpy as np

from aaeval.importers.limits import MAX_ELEMENTS, ImportLimitError
from aaeval.importers.scene import Layer
from aaeval.importers.shapes import Subpath, fill_regions
from aaeval.importers.svgclip import ClipPaths, clip_layers
from aaeval.importers.svgcomputed import ComputedStyles, parse_opacity
from aaeval.importers.svgdocument import (CONTAINERS, MARKABLE, MAX_USE_DEPTH, NOT_IMPORTED, SHAPES, XLINK_HREF,
                                          SvgError, Tree, conditions_pass, svg_tag)
from aaeval.importers.svggeometry import MAX_COORDINATE, bounding_box, flatten_segments, geometry, malformed
from aaeval.importers.svgmarkers import draw_markers
from aaeval.importers.svgpaint import Paints, paint_order
from aaeval.importers.svgpath import apply, compose, max_stretch, translate
from aaeval.importers.svgreport import Report
from aaeval.importers.svgstroke import stroke_layer
from aaeval.importers.svgstyle import INITIAL, LengthError, Lengths
from aaeval.importers.svgtransform import element_transform
from aaeval.importers.svgviewport import draw_viewport

__all__ = ["Walk"]

# properties whose effect the scene format cannot hold
UNSUPPORTED = {"mask": "mask", "filter": "filter"}
ANIMATION = ("animate", "set", "animateTransform", "animateMotion", "animateColor", "discard")


class Walk:
    """The rendering tree walk: layers of every drawn element, in painting order."""

    def __init__(self, root, tol: float, ignored: list[str]):
        self.root = root
        self.tol = tol
        self.report = Report(ignored)
        self.tree = Tree(root)
        self.computed = ComputedStyles(self.tree, self.report)
        self.paints = Paints(self.tree, self.computed, self.report)
        self.clips = ClipPaths(self.tree, self.computed, self.report, tol)
        self.use_depth = 0
        self.drawn = 0  # elements drawn, markers' contents once per vertex
        self.active_markers: set[int] = set()  # a marker drawn inside itself is an error: not drawn
        for k, el in enumerate(el for el in root.iter() if svg_tag(el) in ANIMATION):
            label = f"#{el.get('id')}" if el.get("id") else f"<{svg_tag(el)}>[{k}]"
            self.report.note(f"{label}: animation not applied (drawn as the document stands before it runs)")

    def root_drawn(self, style) -> bool:
        """Whether the root draws anything; what it asks that is not applied is listed."""
        opacity = parse_opacity(style["opacity"])
        if style["display"].strip().lower() == "none" or opacity <= 0:
            return False
        if opacity < 1:
            self.report.note(f"<svg>: opacity {style['opacity']} ignored (drawn opaque)")
        for prop, what in {**UNSUPPORTED, "clip-path": "clip path"}.items():
            if style[prop].strip().lower() not in ("", "none"):
                self.report.note(f"<svg>: {what} on the root not applied")
        if self.root.get("transform"):
            self.report.note("<svg>: transform on the root element not applied")
        return True

    def children(self, el, style, ctm, lengths, context, out) -> None:
        for child in el:
            self.draw(child, style, ctm, lengths, context, out)

    def draw(self, el, parent: dict, ctm, lengths: Lengths, context, out: list[Layer]) -> None:
        tag = svg_tag(el)
        if tag is None or not conditions_pass(el):
            return
        if tag not in SHAPES and tag not in CONTAINERS and tag not in ("svg", "use", "switch") \
                and tag not in NOT_IMPORTED:
            return  # definitions, metadata and unknown elements are not rendered, nor their children
        self.drawn += 1
        if self.drawn > MAX_ELEMENTS:
            raise ImportLimitError(f"more than {MAX_ELEMENTS} elements to draw once <use> references and markers "
                                   "are expanded (the limit)")
        name = self.report.name(el, tag)
        style = self.computed.style(el, parent, name)
        if style["display"].strip().lower() == "none":
            return
        if tag in NOT_IMPORTED:
            self.report.note(f"{name}: {NOT_IMPORTED[tag]}")
            return
        lengths = lengths.with_font(style["font"])
        opacity = parse_opacity(style["opacity"])
        if opacity <= 0:
            return  # draws nothing
        if opacity < 1:
            self.report.note(f"{name}: opacity {style['opacity']} ignored (drawn opaque)")
        if tag in SHAPES and style["shape-rendering"].strip().lower() in ("crispedges", "optimizespeed"):
            self.report.note(f"{name}: shape-rendering {style['shape-rendering']} ignored (drawn anti-aliased)")
        for prop in ("mix-blend-mode", "isolation"):
            if style[prop].strip().lower() not in (INITIAL[prop], "isolate"):
                self.report.note(f"{name}: {prop} {style[prop]} ignored (drawn normal)")
        own = element_transform(el.get("transform"), style["transform-origin"], lengths)
        if own is False:
            self.report.note(f"{name}: transform {el.get('transform')[:40]!r} is not valid; drawn untransformed")
        elif own is not None:
            ctm = compose(ctm, own)
        unsupported = [(prop, what) for prop, what in UNSUPPORTED.items()
                       if style[prop].strip().lower() not in ("", "none")]
        clipped = style["clip-path"].strip().lower() not in ("", "none")
        mine: list[Layer] = [] if clipped else out
        if tag in SHAPES:
            for prop, what in unsupported:
                self.report.note(f"{name}: {what} not supported; element not imported")
            if not unsupported:
                try:
                    self.shape(el, tag, name, style, ctm, lengths, context, mine)
                except (ArithmeticError, TypeError, IndexError, np.linalg.LinAlgError) as exc:
                    # one element's numbers, not the file: SVG renders the rest
                    self.report.note(f"{name}: could not be built ({type(exc).__name__}: {exc}); element not imported")
                except SvgError:
                    raise
                except ValueError as exc:  # a stated limit, passed while building this element
                    raise SvgError(f"{name}: {exc}") from None
        else:
            for prop, what in unsupported:
                self.report.note(f"{name}: {what} on a group not applied (its shapes are drawn unmasked, unfiltered)")
            if tag in CONTAINERS:
                self.children(el, style, ctm, lengths, context, mine)
            elif tag == "switch":
                for child in el:
                    if svg_tag(child) is not None and conditions_pass(child):
                        self.draw(child, style, ctm, lengths, context, mine)
                        break
            elif tag == "svg":
                draw_viewport(self, el, el, name, style, ctm, lengths, context, mine)
            elif tag == "use":
                self.use(el, name, style, ctm, lengths, context, mine)
        if clipped and mine:
            box = bounding_box(el, tag, style, lengths, self.tol) if tag in SHAPES else None
            clip = self.clips.region(style["clip-path"], name, ctm, box, lengths)
            out.extend(mine if clip is None else clip_layers(mine, clip))

    def use(self, el, name, style, ctm, lengths, context, out) -> None:
        href = str(el.get("href") or el.get(XLINK_HREF) or "").strip()
        if not href.startswith("#"):
            if href:
                self.report.note(f"{name}: <use> of {href[:80]!r} not imported (only references inside the file are "
                                 "followed; nothing is fetched)")
            return
        target = self.tree.by_id.get(href[1:])
        if target is None or self.use_depth >= MAX_USE_DEPTH:
            return  # a reference to nothing renders nothing
        try:
            x = lengths.resolve(style.get("x", "0"), "x")
            y = lengths.resolve(style.get("y", "0"), "y")
        except LengthError:
            x = y = 0.0
        ctm = compose(ctm, translate(x, y))
        paints = {part: self.paints.paint(style[part], style, part, name, context) for part in ("fill", "stroke")}
        self.use_depth += 1
        try:
            kind = svg_tag(target)
            if kind in ("symbol", "svg"):
                tname = self.report.name(target, kind)
                tstyle = self.computed.style(target, style, tname)
                if tstyle["display"].strip().lower() != "none":
                    own = (element_transform(target.get("transform"), tstyle["transform-origin"], lengths)
                           if kind == "symbol" else None)
                    placed = compose(ctm, own) if own else ctm
                    draw_viewport(self, target, el, tname, tstyle, placed, lengths, paints, out)
            else:
                self.draw(target, style, ctm, lengths, paints, out)
        finally:
            self.use_depth -= 1


    def shape(self, el, tag, name, style, ctm, lengths, context, out) -> None:
        problem = malformed(el.attrib, tag)
        if problem:
            self.report.note(f"{name}: {problem}; element not imported")
            return
        try:
            segments = geometry(el, tag, style, lengths)
        except LengthError as exc:
            self.report.note(f"{name}: {exc}; element not imported")
            return
        if not segments:
            return
        stretch = max_stretch(ctm)
        if not (math.isfinite(stretch) and stretch > 0):
            return  # a transform that collapses the shape draws nothing
        ctrl = np.concatenate([s.ctrl for segs, _ in segments for s in segs])
        placed = apply(ctm, ctrl)
        if not np.isfinite(placed).all():
            self.report.note(f"{name}: a coordinate is not a finite number after its transform; element not imported")
            return
        reach = float(np.abs(placed).max())
        if reach > MAX_COORDINATE:
            self.report.note(f"{name}: coordinates reach {reach:.3g} px, beyond +-{MAX_COORDINATE:g}; "
                             "element not imported")
            return
        visible = style["visibility"].strip().lower() == "visible"
        fill = self.paints.paint(style["fill"], style, "fill", name, context) if visible else None
        stroke = self.paints.paint(style["stroke"], style, "stroke", name, context) if visible else None
        tol = self.tol / stretch
        parts: list[Layer] = []
        for part in paint_order(style["paint-order"]):
            if part == "fill" and fill is not None:
                rule = "evenodd" if style["fill-rule"].strip() == "evenodd" else "nonzero"
                subpaths = [Subpath(apply(ctm, s.points), s.closed) for s in flatten_segments(segments, tol)]
                parts.append(Layer(fill, fill_regions(subpaths, rule), name + " fill"))
            elif part == "stroke" and stroke is not None:
                stroke_layer(self.report.note, segments, el, name, style, ctm, lengths, stroke, tol, stretch, reach,
                             parts)
            elif part == "markers" and tag in MARKABLE:
                draw_markers(self, segments, name, style, ctm, lengths, {"fill": fill, "stroke": stroke}, parts)
        out.extend(layer for layer in parts if layer.regions)
