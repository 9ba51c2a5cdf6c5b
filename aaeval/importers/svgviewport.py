"""SVG viewports: the root's size, nested ``<svg>``, and ``<use>`` of ``<svg>`` or ``<symbol>``.

A viewport is placed at x, y, sized width x height, its ``viewBox`` mapped in with its
``preserveAspectRatio`` (:func:`aaeval.importers.svgpath.viewbox_transform`), lengths
inside resolved against the viewBox, and its contents clipped to it unless ``overflow``
is visible. A viewBox of no width or height disables rendering (:data:`DISABLED`). On the
root, a side missing from ``width``/``height`` follows the viewBox's proportions (100 px
without one).
"""

from __future__ import annotations

import math
import re

import numpy as np

from aaeval.importers.scene import Layer
from aaeval.importers.svgclip import clip_layers
from aaeval.importers.svgpath import apply, compose, translate, viewbox_transform
from aaeval.importers.svgstyle import LengthError, Lengths

__all__ = ["root_viewport", "draw_viewport", "viewbox", "own_length", "DISABLED"]

DISABLED = "disabled"  # a viewBox of no width or height: the element is not rendered (SVG 2, 8.6)


def root_viewport(root, style):
    box = viewbox(root.get("viewBox"))  # a disabling one was refused before
    box = None if box is DISABLED else box
    aspect = root.get("preserveAspectRatio", "")
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

def draw_viewport(walk, el, size_from, name, style, ctm, lengths, context, out) -> None:
    """A nested viewport (``<svg>``, or ``<symbol>``/``<svg>`` through ``<use>``):
    placed at x, y, sized width x height, its viewBox mapped in, clipped to it."""
    def length(prop, axis, default):
        raw = size_from.get(prop) if size_from is not el and size_from.get(prop) is not None else style.get(prop)
        try:
            return lengths.resolve(raw, axis) if raw is not None and raw.strip() != "auto" else default
        except LengthError:
            return default

    full = lengths.viewport
    x = own_length(style, "x", lengths)  # a <use> moves the viewport by its own x, y
    y = own_length(style, "y", lengths)
    w = length("width", "x", full[0])
    h = length("height", "y", full[1])
    if not (w > 0 and h > 0):
        return  # a viewport of no area renders nothing
    box = viewbox(el.get("viewBox"))
    if box is DISABLED:
        return
    inner = compose(ctm, translate(x, y))
    if box is not None:
        inner = compose(inner, viewbox_transform(box, el.get("preserveAspectRatio", ""), w, h))
    view = (box[2], box[3]) if box is not None else (w, h)
    layers: list[Layer] = []
    walk.children(el, style, inner, lengths.with_viewport(view), context, layers)
    if style["overflow"].strip().lower() not in ("visible", "auto"):
        corners = np.array([[x, y], [x + w, y], [x + w, y + h], [x, y + h]], dtype=np.float64)
        layers = clip_layers(layers, apply(ctm, corners))
    out.extend(layers)

def own_length(style, prop: str, lengths: Lengths) -> float:
    """An element's own x or y (0 when not given or not valid)."""
    try:
        return lengths.resolve(style[prop], prop) if style.get(prop) is not None else 0.0
    except LengthError:
        return 0.0


def viewbox(raw):
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

