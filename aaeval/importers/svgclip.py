"""Clipping in SVG: ``clip-path`` regions and the clip of a viewport.

:class:`ClipPaths` turns a ``clip-path: url(#id)`` into the region it keeps (device
space): the union of the ``<clipPath>``'s shapes, each under its ``clip-rule`` and cut
by its own ``clip-path`` (in the child's user space), in ``userSpaceOnUse`` or
``objectBoundingBox`` units (on shapes), ``<use>`` of a shape followed, cut by the
``<clipPath>``'s own ``clip-path``. What it cannot apply (a reference to something else,
a cycle of references, bounding-box units on a group, text inside) is listed and drawn
unclipped. :func:`clip_layers` clips layers to a region or to a viewport's rectangle.
"""

from __future__ import annotations

import math

import numpy as np

from aaeval.importers.fill import resolve_fill
from aaeval.importers.scene import Layer
from aaeval.importers.shapes import Region, Subpath, clip_regions, fill_regions
from aaeval.importers.svgcomputed import parse_number
from aaeval.importers.svgdocument import NOT_IMPORTED, SHAPES, XLINK_HREF, conditions_pass, svg_tag
from aaeval.importers.svggeometry import bounding_box, flatten_segments, geometry
from aaeval.importers.svgpath import IDENTITY, apply, compose, max_stretch, translate
from aaeval.importers.svgstyle import LengthError, Lengths, parse_paint
from aaeval.importers.svgtransform import element_transform

__all__ = ["ClipPaths", "clip_layers"]


def clip_layers(layers: list[Layer], clip) -> list[Layer]:
    """Each layer's regions within ``clip``: a convex polygon (a viewport) or regions."""
    if isinstance(clip, np.ndarray):
        clip = [Region(clip, [])]
    return [Layer(layer.color, clip_regions(layer.regions, clip), layer.name) for layer in layers]


class ClipPaths:
    """The regions ``clip-path`` values keep, resolved in the document."""

    def __init__(self, tree, computed, report, tol: float):
        self.tree = tree
        self.computed = computed
        self.report = report
        self.tol = tol
        self.resolving: set[int] = set()  # clipPaths being resolved: one met again is a cycle

    def region(self, value: str, name: str, ctm, box, lengths: Lengths):
        """The region (device space) a ``clip-path`` keeps, or None where it is not applied
        (then listed): a union of the clipPath's shapes, each under its clip-rule."""
        paint = parse_paint(value) if value.strip().lower().startswith("url(") else None
        target = self.tree.by_id.get(paint[1]) if paint and paint[0] == "url" and paint[1] else None
        if target is None or svg_tag(target) != "clipPath":
            self.report.note(f"{name}: clip-path {value.strip()[:60]} is not a clipPath in the file; drawn unclipped")
            return None
        if id(target) in self.resolving:
            self.report.note(f"{name}: clip-path #{target.get('id')} refers back to itself (a cycle, an error in SVG); "
                             "drawn unclipped by it")
            return None
        self.resolving.add(id(target))
        try:
            return self._union(target, name, ctm, box, lengths)
        finally:
            self.resolving.discard(id(target))

    def _union(self, target, name: str, ctm, box, lengths: Lengths):
        """The union of a clipPath's shapes (device space), each under its clip-rule and
        clipped by its own clip-path, within the clipPath's own clip-path (in the user space
        of the element it clips); None where the clipPath is not applied."""
        tstyle = self.computed.tree_style(target)
        kept = self._children(target, tstyle, name, ctm, box, lengths)
        if kept and tstyle["clip-path"].strip().lower() not in ("", "none"):
            clip = self.region(tstyle["clip-path"], name, ctm, box, lengths)
            if clip is not None:
                kept = clip_regions(kept, clip)
        return kept

    def _children(self, target, tstyle, name: str, ctm, box, lengths: Lengths):
        """The union of a clipPath's children (device space); None where it is not applied."""
        own = element_transform(target.get("transform"), tstyle["transform-origin"], lengths)
        space = compose(ctm, own or IDENTITY)
        if target.get("clipPathUnits", "").strip() == "objectBoundingBox":
            if box is None or box[2] <= 0 or box[3] <= 0:
                if box is None:
                    self.report.note(f"{name}: clip-path in objectBoundingBox units on a group not applied; "
                                     "drawn unclipped")
                    return None
                return []  # a box of no area: nothing is kept
            space = compose(space, (box[2], 0.0, 0.0, box[3], box[0], box[1]))
        rings = []
        for child in target:
            shape, tag = child, svg_tag(child)
            if tag is None or not conditions_pass(child):
                continue
            placed = space
            style = self.computed.tree_style(child)
            if style["display"].strip().lower() == "none" or style["visibility"].strip().lower() != "visible":
                continue
            if child.get("transform"):
                own = element_transform(child.get("transform"), style["transform-origin"],
                                        lengths.with_font(style["font"]))
                placed = compose(placed, own or IDENTITY)
            if tag == "use":
                href = str(child.get("href") or child.get(XLINK_HREF) or "").strip()
                shape = self.tree.by_id.get(href[1:]) if href.startswith("#") else None
                tag = svg_tag(shape) if shape is not None else None
                if tag not in SHAPES:
                    continue
                style = self.computed.style(shape, style)
                x, y = parse_number(child.get("x"), 0.0), parse_number(child.get("y"), 0.0)
                own = element_transform(shape.get("transform"), style["transform-origin"],
                                        lengths.with_font(style["font"])) or IDENTITY
                placed = compose(compose(placed, translate(x, y)), own)
            if tag not in SHAPES:
                if tag in NOT_IMPORTED:
                    self.report.note(f"{name}: clip-path #{target.get('id')} holds a <{tag}>; drawn unclipped")
                    return None
                continue
            try:
                segments = geometry(shape, tag, style, lengths.with_font(style["font"]))
            except LengthError:
                continue
            stretch = max_stretch(placed)
            if not segments or not (math.isfinite(stretch) and stretch > 0):
                continue
            rule = "evenodd" if style["clip-rule"].strip() == "evenodd" else "nonzero"
            flat = flatten_segments(segments, self.tol / stretch)
            subpaths = [Subpath(apply(placed, s.points), s.closed) for s in flat]
            regions = fill_regions(subpaths, rule)
            if style["clip-path"].strip().lower() not in ("", "none"):  # a child's own clip, in its user space
                shape_lengths = lengths.with_font(style["font"])
                own_box = bounding_box(shape, tag, style, shape_lengths, self.tol)
                clip = self.region(style["clip-path"], name, placed, own_box, shape_lengths)
                if clip is not None:
                    regions = clip_regions(regions, clip)
            rings.extend(ring for region in regions for ring in (region.outer, *region.holes))
        return [Region(outer, holes) for outer, holes in resolve_fill(rings, "nonzero")] if rings else []
