"""SVG shapes as geometry: each element's outline in its own user space, and its checks.

:func:`geometry` turns ``<rect>`` (rounded corners, ``rx``/``ry`` auto), ``<circle>``,
``<ellipse>``, ``<line>``, ``<polyline>``, ``<polygon>`` and ``<path>`` into subpaths of true
segments (:mod:`aaeval.importers.svgpath`), with lengths resolved against the viewport
and font; a path with an error draws up to it. :func:`malformed` says why an element SVG
does not render (a number that is not finite, a negative size or radius);
:func:`flatten_segments` flattens segments for fills and :func:`bounding_box` gives a
shape's box in user space. Geometry beyond :data:`MAX_COORDINATE` after its transform is
not imported.
"""

from __future__ import annotations

import re

import numpy as np

from aaeval.importers.flatten import arc_points, bezier_points
from aaeval.importers.limits import charge
from aaeval.importers.shapes import Subpath
from aaeval.importers.svgpath import ellipse_outline, parse_path, parse_points, rect_outline
from aaeval.importers.svgstyle import GEOMETRY, LengthError, Lengths
from aaeval.scenes.format import MAX_COORDINATE

__all__ = ["geometry", "malformed", "flatten_segments", "bounding_box", "MAX_COORDINATE"]

# attributes that hold numbers of an element's own geometry
GEOMETRY_ATTRS = ("x", "y", "width", "height", "rx", "ry", "cx", "cy", "r", "x1", "y1", "x2", "y2",
                  "points", "d", "transform", "stroke-width", "stroke-miterlimit")
NOT_FINITE = re.compile(r"(?<![a-z])(nan|inf(inity)?)(?![a-z])", re.IGNORECASE)


def geometry(el, tag, style, lengths: Lengths):
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

def bounding_box(el, tag, style, lengths, tol: float):
    """A shape's bounding box in its user space (x, y, w, h), from its flattened outline."""
    try:
        subpaths = flatten_segments(geometry(el, tag, style, lengths), tol * 1e-3)
    except LengthError:
        return None
    if not subpaths:
        return None
    points = np.concatenate([s.points for s in subpaths])
    lo, hi = points.min(axis=0), points.max(axis=0)
    return (float(lo[0]), float(lo[1]), float(hi[0] - lo[0]), float(hi[1] - lo[1]))

def malformed(attrs: dict, kind: str) -> str | None:
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
