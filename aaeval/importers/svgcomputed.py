"""Computed styles of SVG elements: the cascade's declared values made into used ones.

The declared values come from :mod:`aaeval.importers.svgstyle` (cssselect2, tinycss2);
here ``inherit``, ``initial`` and ``unset`` are applied, inherited properties taken from
the parent, an invalid ``color`` or paint replaced by the parent's, font sizes resolved
(``em`` against the parent, ``rem`` against the root) and ``overflow`` given the UA
style sheet's ``hidden`` on elements that establish a viewport. Properties the import
cannot apply are listed in the report. :func:`parse_number` and :func:`parse_opacity` read the plain
values the walk takes from attributes and styles.
"""

from __future__ import annotations

import math

from aaeval.importers.svgdocument import SVG_NS, svg_tag
from aaeval.importers.svgstyle import (GEOMETRY, INHERITED, INITIAL, NOT_APPLIED, Styles, font_size, parse_color,
                                       parse_paint)

__all__ = ["ComputedStyles", "parse_number", "parse_opacity", "CLIPPING"]

# elements that establish a viewport clip it unless overflow says otherwise (SVG 2's UA style sheet)
CLIPPING = ("svg", "symbol", "marker")


def parse_number(raw, default: float) -> float:
    try:
        return float(raw) if raw not in (None, "") else default
    except (TypeError, ValueError):
        return default


def parse_opacity(raw) -> float:
    """An opacity (number or percentage) clamped to [0, 1]; 1 when not valid."""
    text = str(raw).strip()
    try:
        value = float(text[:-1]) / 100 if text.endswith("%") else float(text)
    except ValueError:
        return 1.0
    return min(1.0, max(0.0, value)) if math.isfinite(value) else 1.0



class ComputedStyles:
    """The computed style of each element, given its parent's (or where it stands in the
    document: :meth:`tree_style`). Problems of the style sheets go to the report first."""

    def __init__(self, tree, report):
        self.root = tree.root
        self.parent = tree.parent
        self.report = report
        self.cascade = Styles(tree.root, SVG_NS)
        report.ignored.extend(self.cascade.problems)
        self.tree_styles: dict[int, dict] = {}

    def style(self, el, parent: dict | None, name: str | None = None) -> dict:
        """The computed style of ``el`` with ``parent`` as the inherited style."""
        declared = self.cascade.of(el)
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
        color = parse_color(out["color"])
        out["color"] = out["color"] if isinstance(color, tuple) else parent_color
        for prop in ("fill", "stroke"):
            if parse_paint(out[prop]) is None:
                out[prop] = parent[prop] if parent else INITIAL[prop]
        parent_font = parent["font"] if parent else font_size(INITIAL["font-size"], 16.0, 16.0)
        root_font = parent["root-font"] if parent else None
        size = font_size(out["font-size"], parent_font, root_font or parent_font)
        out["font"] = size if size is not None else parent_font
        out["root-font"] = root_font if root_font is not None else out["font"]
        if "overflow" not in declared:
            out["overflow"] = "hidden" if svg_tag(el) in CLIPPING and el is not self.root else "visible"
        if name is not None:
            for prop in sorted(set(declared) & NOT_APPLIED):
                self.report.note(f"{name}: CSS property {prop}: {declared[prop][:40]} not applied")
        return out

    def tree_style(self, el) -> dict:
        """The computed style of ``el`` where it stands in the document (markers' contents
        inherit from the marker's ancestors, not from the shape that uses it)."""
        key = id(el)
        if key not in self.tree_styles:
            parent = self.parent.get(key)
            self.tree_styles[key] = self.style(el, self.tree_style(parent) if parent is not None else None)
        return self.tree_styles[key]
