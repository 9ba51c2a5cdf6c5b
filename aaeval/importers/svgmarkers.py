"""SVG markers: drawn at the vertices of paths, lines, polylines and polygons.

At each vertex (SVG 2, 13.7.3) the ``marker-start``, ``-mid`` or ``-end`` marker's
contents are drawn placed at the vertex, turned by ``orient`` (a fixed angle, or the
bisector of the incoming and outgoing directions: ``auto``, ``auto-start-reverse``),
scaled by the stroke width (``markerUnits``), with its viewBox mapped onto
``markerWidth`` x ``markerHeight`` and clipped there unless ``overflow`` is visible. The
contents inherit from the marker's ancestors; ``context-fill``/``context-stroke`` take
the shape's paints. A marker drawn inside itself draws nothing.
"""

from __future__ import annotations

import math
import re

import numpy as np

from aaeval.importers.scene import Layer
from aaeval.importers.svgclip import clip_layers
from aaeval.importers.svgdocument import MAX_USE_DEPTH, svg_tag
from aaeval.importers.svgpath import IDENTITY, apply, compose, viewbox_transform
from aaeval.importers.svgpath import rotate as rotation
from aaeval.importers.svgpath import scale as scaling
from aaeval.importers.svgpath import translate
from aaeval.importers.svgstroke import stroke_width
from aaeval.importers.svgstyle import LengthError, parse_paint
from aaeval.importers.svgviewport import DISABLED, viewbox

__all__ = ["draw_markers"]


def draw_markers(walk, segments, name, style, ctm, lengths, paints, out) -> None:
    """The layers of a shape's markers (``walk``: the :class:`~aaeval.importers.svgwalk.Walk`
    that draws their contents) appended to ``out``."""
    refs = {}
    for where in ("start", "mid", "end"):
        paint = parse_paint(style[f"marker-{where}"]) if style[f"marker-{where}"].strip() != "none" else None
        target = walk.tree.by_id.get(paint[1]) if paint and paint[0] == "url" and paint[1] else None
        if target is not None and svg_tag(target) == "marker":
            refs[where] = target
    if not refs:
        return
    width = stroke_width(style, lengths)
    vertices = _marker_vertices(segments)
    for k, (point, incoming, outgoing) in enumerate(vertices):
        where = "start" if k == 0 else "end" if k == len(vertices) - 1 else "mid"
        if where in refs:
            _draw_marker(walk, refs[where], where, point, incoming, outgoing, width, ctm, lengths, paints, out)


def _draw_marker(walk, el, where, point, incoming, outgoing, stroke_width, ctm, lengths, paints, out) -> None:
    """One marker ``el`` drawn at one vertex."""
    if walk.use_depth >= MAX_USE_DEPTH or id(el) in walk.active_markers:
        return
    style = walk.computed.tree_style(el)
    mlengths = lengths.with_font(style["font"])
    try:
        mw = mlengths.resolve(el.get("markerWidth", "3"), "x")
        mh = mlengths.resolve(el.get("markerHeight", "3"), "y")
    except LengthError:
        mw = mh = 3.0
    if not (mw > 0 and mh > 0):
        return
    box = viewbox(el.get("viewBox"))
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
    walk.use_depth += 1
    walk.active_markers.add(id(el))
    try:
        walk.children(el, style, compose(place, fit), mlengths.with_viewport(view), paints, layers)
    finally:
        walk.use_depth -= 1
        walk.active_markers.discard(id(el))
    if style["overflow"].strip().lower() not in ("visible", "auto"):
        corners = np.array([[0, 0], [mw, 0], [mw, mh], [0, mh]], dtype=np.float64)
        layers = clip_layers(layers, apply(place, corners))
    out.extend(layers)


def _angle(text: str) -> float | None:
    """A CSS angle in degrees, or None."""
    match = re.fullmatch(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)(deg|rad|grad|turn)?\s*", text)
    if not match:
        return None
    value = float(match.group(1))
    return value * {None: 1.0, "deg": 1.0, "rad": 180 / math.pi, "grad": 0.9, "turn": 360.0}[match.group(2)]



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
