"""What an SVG fill or stroke paints, and in which order the parts of a shape are painted.

A paint resolves to one linear RGB colour or to nothing: ``none``, a transparent colour
(alpha or ``fill-opacity`` 0), ``currentColor`` with the element's own ``color``,
``context-fill``/``context-stroke`` from the ``<use>`` or marker's shape, ``url(#missing)``
to its fallback colour, a gradient that is one colour everywhere to that colour. A true
gradient or a pattern and a translucent colour (drawn opaque) are listed in the report.
:func:`paint_order` orders fill, stroke and markers (SVG 2, 13.6).
"""

from __future__ import annotations

import numpy as np

from aaeval.imageio import srgb_to_linear
from aaeval.importers.svgcomputed import parse_opacity
from aaeval.importers.svgdocument import XLINK_HREF, svg_tag
from aaeval.importers.svgstyle import parse_color, parse_paint

__all__ = ["Paints", "paint_order", "PAINT_PARTS"]

PAINT_PARTS = ("fill", "stroke", "markers")
PAINT_SERVERS = ("linearGradient", "radialGradient", "pattern", "meshgradient", "hatch")
GRADIENTS = ("linearGradient", "radialGradient")


def paint_order(value: str) -> list[str]:
    """The parts in the order ``paint-order`` paints them (SVG 2, 13.6)."""
    words = value.split()
    if not words or words == ["normal"] or any(w not in PAINT_PARTS for w in words) or len(set(words)) != len(words):
        return list(PAINT_PARTS)
    return words + [p for p in PAINT_PARTS if p not in words]



class Paints:
    """Paints resolved against the document's paint servers; what is not imported is reported."""

    def __init__(self, tree, computed, report):
        self.tree = tree
        self.computed = computed
        self.report = report

    def paint(self, raw: str, style: dict, what: str, name: str, context) -> np.ndarray | None:
        """The linear RGB a fill or stroke paints, or None when it paints nothing."""
        paint = parse_paint(raw)
        if paint is None or paint[0] == "none":
            return None
        if paint[0] == "context":
            return None if context is None else context.get(paint[1])
        if paint[0] == "url":
            target = self.tree.by_id.get(paint[1]) if paint[1] else None
            if target is None or svg_tag(target) not in PAINT_SERVERS:
                fallback = paint[2]
                if fallback is None or fallback[0] != "color":
                    return None  # a reference to nothing, no fallback colour: none
                paint = fallback
            else:
                paint = self.solid_gradient(target)
                if paint is None:
                    self.report.note(f"{name}: {what} {raw.strip()} (gradient or pattern) not imported")
                    return None
                if paint[0] == "none":
                    return None
        color = paint[1]
        if color == "currentcolor":
            color = parse_color(style["color"])
        alpha = color[3] * parse_opacity(style[f"{what}-opacity"])
        if alpha <= 0:
            return None  # transparent: nothing to draw
        if alpha < 1:
            self.report.note(f"{name}: {what} colour alpha {alpha:.3g} ignored (drawn opaque)")
        return srgb_to_linear(np.array(color[:3], dtype=np.float64))

    def solid_gradient(self, target):
        """What a gradient paints when it is one colour everywhere: ``("none",)`` without
        stops, ``("color", rgba)`` when its stops are all alike (one stop: SVG 2, 14.3.4);
        None for a true gradient or a pattern. Stops come from ``href`` when it has none."""
        stops, el, seen = [], target, set()
        while el is not None and id(el) not in seen and svg_tag(el) in GRADIENTS:
            seen.add(id(el))
            stops = [child for child in el if svg_tag(child) == "stop"]
            if stops:
                break
            href = str(el.get("href") or el.get(XLINK_HREF) or "").strip()
            el = self.tree.by_id.get(href[1:]) if href.startswith("#") else None
        if svg_tag(target) not in GRADIENTS:
            return None
        if not stops:
            return ("none",)
        colours = set()
        for stop in stops:
            style = self.computed.tree_style(stop)
            color = parse_color(style["stop-color"])
            if color == "currentcolor":
                color = parse_color(style["color"])
            color = color if isinstance(color, tuple) else (0.0, 0.0, 0.0, 1.0)
            colours.add((*color[:3], color[3] * parse_opacity(style["stop-opacity"])))
        return ("color", colours.pop()) if len(colours) == 1 else None

