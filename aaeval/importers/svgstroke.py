"""An SVG element's stroke as a layer: width, dashes, caps, joins and miter limit.

The stroke is outlined in user space with the user-space width
(:mod:`aaeval.importers.stroke`) and then transformed, so skews and non-uniform scales
stretch it as SVG draws it; ``stroke-dasharray`` is applied first
(:mod:`aaeval.importers.dash`, lengths in ``pathLength`` units where given). What SVG
draws otherwise (``miter-clip`` and ``arcs`` joins, ``non-scaling-stroke``) is listed in
the report through the ``note`` given.
"""

from __future__ import annotations

import math
import re

from aaeval.importers.dash import dash_subpaths, path_length
from aaeval.importers.limits import charge
from aaeval.importers.scene import Layer
from aaeval.importers.shapes import STROKE_CAPS, STROKE_JOINS, stroke_regions
from aaeval.importers.svgcomputed import parse_number
from aaeval.importers.svggeometry import MAX_COORDINATE
from aaeval.importers.svgpath import apply
from aaeval.importers.svgstyle import LengthError

__all__ = ["stroke_layer", "stroke_width", "dashes"]


def stroke_width(style, lengths) -> float:
    try:
        width = lengths.resolve(style["stroke-width"], "d")
    except LengthError:
        return 1.0
    return width if width >= 0 else 1.0

def stroke_layer(note, segments, el, name, style, ctm, lengths, color, tol, stretch, reach, out) -> None:
    raw = style["stroke-width"]
    if not math.isfinite(parse_number(raw, 1.0)):
        note(f"{name}: stroke-width {raw} is not a finite number; stroke not imported")
        return
    width = stroke_width(style, lengths)
    if width <= 0:
        return
    if reach + width * stretch > MAX_COORDINATE:
        note(f"{name}: stroke width {width * stretch:.3g} px reaches beyond +-{MAX_COORDINATE:g}; "
             "stroke not imported")
        return
    segments = dashes(note, segments, el, name, style, lengths)
    if style["vector-effect"].strip().lower() == "non-scaling-stroke":
        note(f"{name}: vector-effect non-scaling-stroke ignored (stroke scaled)")
    cap = style["stroke-linecap"].strip()
    join = style["stroke-linejoin"].strip()
    if join in ("miter-clip", "arcs"):
        note(f"{name}: stroke-linejoin {join} drawn as miter (bevel beyond the miter limit)")
        join = "miter"
    limit = parse_number(style["stroke-miterlimit"], 4.0)
    if not (math.isfinite(limit) and limit >= 1.0):
        note(f"{name}: stroke-miterlimit {style['stroke-miterlimit']} is not a number >= 1 "
             "(an error in SVG); 4 used")
        limit = 4.0
    regions = stroke_regions(
        segments, width, cap=cap if cap in STROKE_CAPS else "butt", join=join if join in STROKE_JOINS else "miter",
        miter_limit=limit, tol=tol, transform=lambda ring: apply(ctm, ring),
    )
    out.append(Layer(color, regions, name + " stroke"))

def dashes(note, segments, el, name, style, lengths):
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
            note(f"{name}: stroke-dasharray: {exc}; stroked solid")
        return segments
    if not pattern or min(pattern) < 0 or sum(pattern) <= 0 or not all(map(math.isfinite, pattern + [offset])):
        return segments
    declared = parse_number(el.get("pathLength"), 0.0)
    if declared > 0 and math.isfinite(declared):  # lengths along the path are in its own units
        factor = path_length(segments) / declared
        pattern, offset = [v * factor for v in pattern], offset * factor
        if sum(pattern) <= 0:
            return segments
    return dash_subpaths(segments, pattern, offset, budget=charge)

