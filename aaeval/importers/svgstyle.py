"""SVG styling: the CSS cascade (cssselect2 + tinycss2), inheritance, colours and lengths.

The cascade follows CSS Cascading 4 as SVG 2 uses it: presentation attributes count as
author rules of specificity zero before every stylesheet; then ``<style>`` rules (only
``type`` absent, empty or ``text/css``) in order of specificity and source order; then the
``style`` attribute; then ``!important`` stylesheet declarations, then ``!important`` ones
in ``style``. cssselect2 matches the selectors (attribute, combined, pseudo-class
selectors, specificity); tinycss2 parses the declarations and the colours (CSS Color 4:
space-separated ``rgb()``, ``hsl()`` with any hue, ``hwb()``, alpha, ``transparent``,
``currentColor``). Whatever the cascade cannot apply (an at-rule, a selector cssselect2
cannot compile) is reported by name, never dropped silently.

Lengths (CSS Values 4): px, in, cm, mm, Q, pt, pc; em and ex against the element's font
size (16 px unless set; ex is half an em, as resvg and Chrome without font metrics take
it), rem against the root's; vw, vh, vmin, vmax against the outermost viewport;
percentages against the nearest viewport's width, height, or diagonal over sqrt 2. A
length that is not exactly ``number unit`` (``"44mmx"``) is invalid.
"""

from __future__ import annotations

import math
import re

__all__ = ["Styles", "INHERITED", "PRESENTATION", "Lengths", "parse_color", "parse_paint", "LengthError"]

# properties aaeval reads, with their initial values; those inherited by default
INITIAL = {
    "fill": "black", "fill-rule": "nonzero", "fill-opacity": "1", "stroke": "none", "stroke-width": "1",
    "stroke-linecap": "butt", "stroke-linejoin": "miter", "stroke-miterlimit": "4", "stroke-dasharray": "none",
    "stroke-dashoffset": "0", "stroke-opacity": "1", "opacity": "1", "color": "black", "display": "inline",
    "visibility": "visible", "paint-order": "normal", "marker-start": "none", "marker-mid": "none",
    "marker-end": "none", "clip-path": "none", "clip-rule": "nonzero", "mask": "none", "filter": "none",
    "font-size": "16px", "overflow": "visible", "mix-blend-mode": "normal", "isolation": "auto",
    "vector-effect": "none", "shape-rendering": "auto", "stop-color": "black", "stop-opacity": "1",
    "transform-origin": "0 0",
}
INHERITED = {"fill", "fill-rule", "fill-opacity", "stroke", "stroke-width", "stroke-linecap", "stroke-linejoin",
             "stroke-miterlimit", "stroke-dasharray", "stroke-dashoffset", "stroke-opacity", "color", "visibility",
             "shape-rendering",
             "paint-order", "marker-start", "marker-mid", "marker-end", "clip-rule", "font-size"}
# geometry properties (SVG 2): set by attribute or by CSS, not inherited
GEOMETRY = ("x", "y", "width", "height", "cx", "cy", "r", "rx", "ry")
PRESENTATION = set(INITIAL) | set(GEOMETRY)
# at-rules that cannot change what shapes draw
HARMLESS_AT_RULES = {"font-face", "charset", "page", "font-feature-values", "counter-style", "property"}
# CSS properties that change what is drawn but that aaeval does not apply
NOT_APPLIED = {"transform", "transform-box", "d", "clip"}
FONT_KEYWORDS = {"xx-small": 9, "x-small": 10, "small": 13, "medium": 16, "large": 18, "x-large": 24,
                 "xx-large": 32, "xxx-large": 48}
DEFAULT_FONT_SIZE = 16.0
# CSS units that need font metrics, a line height or a container: reported, not guessed
UNRESOLVED_UNITS = {"lh", "rlh", "ic", "ric", "cap", "rcap", "ch", "rch", "vi", "vb", "svw", "svh", "lvw", "lvh",
                    "dvw", "dvh", "cqw", "cqh", "cqi", "cqb", "cqmin", "cqmax"}


class LengthError(ValueError):
    """A length that is not valid, or in a unit aaeval does not resolve."""


LENGTH = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)([a-zA-Z%]*)\s*$")
ABSOLUTE = {"": 1.0, "px": 1.0, "in": 96.0, "cm": 96.0 / 2.54, "mm": 96.0 / 25.4, "q": 96.0 / 101.6,
            "pt": 4.0 / 3.0, "pc": 16.0}


class Lengths:
    """How lengths resolve for one element: its viewport, font size and the root's."""

    def __init__(self, viewport, font_size=DEFAULT_FONT_SIZE, root_viewport=None, root_font=DEFAULT_FONT_SIZE):
        self.viewport = viewport
        self.font_size = font_size
        self.root_viewport = root_viewport or viewport
        self.root_font = root_font

    def with_viewport(self, viewport) -> "Lengths":
        return Lengths(viewport, self.font_size, self.root_viewport, self.root_font)

    def with_font(self, font_size) -> "Lengths":
        return Lengths(self.viewport, font_size, self.root_viewport, self.root_font)

    def resolve(self, text, axis: str = "d") -> float:
        """A length in user units; ``axis`` ``x``, ``y`` or ``d`` says what a percentage is of."""
        match = LENGTH.match(str(text))
        if not match:
            raise LengthError(f"{str(text)[:40]!r} is not a length")
        value, unit = float(match.group(1)), match.group(2).lower()
        if unit in ABSOLUTE:
            return value * ABSOLUTE[unit]
        w, h = self.viewport
        if unit == "%":
            base = {"x": w, "y": h}.get(axis, math.hypot(w, h) / math.sqrt(2))
            return value / 100.0 * base
        if unit == "em":
            return value * self.font_size
        if unit == "ex":
            return value * self.font_size / 2
        if unit == "rem":
            return value * self.root_font
        rw, rh = self.root_viewport
        viewport_units = {"vw": rw, "vh": rh, "vmin": min(rw, rh), "vmax": max(rw, rh)}
        if unit in viewport_units:
            return value / 100.0 * viewport_units[unit]
        if unit in UNRESOLVED_UNITS:
            raise LengthError(f"the unit {unit!r} of {str(text)[:40]!r} is not resolved by aaeval")
        raise LengthError(f"{str(text)[:40]!r} is not a length")


def parse_color(text: str):
    """(r, g, b, alpha) in sRGB 0..1 (any CSS Color 4 colour, clipped to the sRGB gamut),
    ``"currentcolor"``, or None when not a colour."""
    from tinycss2 import color4

    color = color4.parse_color(str(text).strip())
    if color is None or isinstance(color, str):
        return color
    r, g, b = (min(1.0, max(0.0, float(v))) for v in _srgb_coordinates(color))
    return (r, g, b, float(color.alpha))


#: CSS Color 4's predefined RGB spaces as colour-science names them (each with its own
#: transfer function and white point).
_RGB_SPACES = {"display-p3": "Display P3", "a98-rgb": "Adobe RGB (1998)", "prophoto-rgb": "ProPhoto RGB",
               "rec2020": "ITU-R BT.2020"}
#: CSS Color 4's D50 white (xy), the white of xyz-d50, lab and lch.
_D50 = (0.3457, 0.3585)


def _srgb_coordinates(color) -> tuple[float, float, float]:
    """A CSS Color 4 colour (tinycss2) in sRGB, before clipping to the gamut: tinycss2 turns
    hsl and hwb into sRGB and lab, lch, oklab and oklch into CIE XYZ; colour-science does the
    rest (Bradford adaptation between D50 and D65, as CSS Color 4 specifies)."""
    import colour
    import numpy as np

    coordinates = np.array([c or 0.0 for c in color.coordinates], dtype=np.float64)
    space = color.space
    if space in ("srgb", "hsl", "hwb"):
        return tuple(color.to("srgb").coordinates)
    srgb = colour.RGB_COLOURSPACES["sRGB"]
    if space == "srgb-linear":
        linear = coordinates
    elif space in _RGB_SPACES:
        linear = colour.RGB_to_RGB(coordinates, colour.RGB_COLOURSPACES[_RGB_SPACES[space]], srgb,
                                   chromatic_adaptation_transform="Bradford", apply_cctf_decoding=True)
    else:  # xyz-d65 and xyz-d50 as given; lab and lch through D50, oklab and oklch through D65
        xyz = color if space.startswith("xyz") else color.to("xyz-d50" if space in ("lab", "lch") else "xyz-d65")
        d65 = colour.xy_to_XYZ(srgb.whitepoint)
        white = d65 if xyz.space == "xyz-d65" else colour.xy_to_XYZ(_D50)
        adapted = colour.adaptation.chromatic_adaptation_VonKries(np.asarray(xyz.coordinates, dtype=np.float64),
                                                                  white, d65, "Bradford")
        linear = srgb.matrix_XYZ_to_RGB @ adapted
    return tuple(float(v) for v in srgb.cctf_encoding(np.asarray(linear, dtype=np.float64)))


def parse_paint(text: str):
    """A fill or stroke: ``("none",)``, ``("color", value)`` (value as :func:`parse_color`),
    ``("url", id, fallback paint or None)``, ``("context", "fill" | "stroke")``; None if invalid."""
    import tinycss2

    text = str(text).strip()
    low = text.lower()
    if low == "none":
        return ("none",)
    if low in ("context-fill", "context-stroke"):
        return ("context", low.split("-")[1])
    tokens = [t for t in tinycss2.parse_component_value_list(text) if t.type not in ("whitespace", "comment")]
    if tokens and (tokens[0].type == "url" or (tokens[0].type == "function" and tokens[0].lower_name == "url")):
        ref = tokens[0].value if tokens[0].type == "url" else "".join(
            t.value for t in tokens[0].arguments if t.type == "string")
        rest = tinycss2.serialize(tokens[1:]).strip()
        fallback = parse_paint(rest) if rest else None
        if rest and fallback is None:
            return None
        return ("url", ref.strip()[1:] if ref.strip().startswith("#") else None, fallback)
    color = parse_color(text)
    return None if color is None else ("color", color)


class Styles:
    """The cascaded declarations of every element of a document (tree order)."""

    def __init__(self, root, svg_ns: str):
        import cssselect2
        import tinycss2

        self.problems: list[str] = []
        self.declared: dict[int, dict[str, str]] = {}
        matcher = cssselect2.Matcher()
        self.order = 0
        for el in root.iter():
            if el.tag not in (f"{svg_ns}style", "style"):
                continue
            kind = (el.get("type") or "").split(";")[0].strip().lower()
            if kind not in ("", "text/css"):
                continue  # not CSS: SVG says the user agent does not apply it
            rules = tinycss2.parse_stylesheet("".join(el.itertext()), skip_comments=True, skip_whitespace=True)
            self._add_rules(rules, matcher)
        wrapper = cssselect2.ElementWrapper.from_xml_root(root)
        for item in wrapper.iter_subtree():
            el = item.etree_element
            normal: dict[str, str] = {k: v for k, v in el.attrib.items() if k in PRESENTATION and _valid(k, v)}
            important: dict[str, str] = {}
            for _, _, pseudo, (_, declarations) in matcher.match(item) if self.order else ():
                if pseudo is None:
                    _apply(declarations, normal, important)
            style = el.get("style")
            if style:
                local_important: dict[str, str] = {}
                _apply(_declarations(style), normal, local_important)
                important.update(local_important)
            normal.update(important)
            self.declared[id(el)] = normal

    def _add_rules(self, rules, matcher) -> None:
        import cssselect2
        import tinycss2

        for rule in rules:
            if rule.type == "at-rule" and rule.lower_at_keyword in HARMLESS_AT_RULES:
                continue
            if rule.type == "at-rule" and rule.lower_at_keyword == "media" and rule.content is not None:
                applies = _media_applies(tinycss2.serialize(rule.prelude))
                if applies is None:
                    self.problems.append(f"<style>: CSS @media {tinycss2.serialize(rule.prelude).strip()[:40]} "
                                         "(a media feature) not applied")
                elif applies:
                    self._add_rules(tinycss2.parse_rule_list(rule.content, skip_comments=True, skip_whitespace=True),
                                    matcher)
                continue
            if rule.type == "at-rule":
                self.problems.append(f"<style>: CSS @{rule.lower_at_keyword} rule not applied")
                continue
            if rule.type != "qualified-rule":
                self.problems.append(f"<style>: CSS that could not be parsed ({rule.message})")
                continue
            declarations = _declarations(rule.content)
            try:
                selectors = cssselect2.compile_selector_list(rule.prelude)
            except cssselect2.SelectorError as exc:
                self.problems.append(f"<style>: CSS selector {tinycss2.serialize(rule.prelude).strip()[:60]!r} "
                                     f"not applied ({exc})")
                continue
            for selector in selectors:
                matcher.add_selector(selector, (self.order, declarations))
            self.order += 1

    def of(self, el) -> dict[str, str]:
        return self.declared.get(id(el), {})


def _media_applies(prelude: str) -> bool | None:
    """Whether a media query list of bare media types (``screen``, ``all``, ``not print``)
    holds for a screen rendering; None when it tests a media feature."""
    if "(" in prelude:
        return None
    for query in prelude.lower().split(","):
        words = [w for w in query.split() if w != "only"]
        negate = bool(words) and words[0] == "not"
        kind = words[1:] if negate else words
        matches = not kind or kind == ["all"] or kind == ["screen"]
        if matches != negate:
            return True
    return False


def _declarations(content):
    """(name, value, important) of each declaration in a block or a style attribute."""
    import tinycss2

    return [(item.lower_name, tinycss2.serialize(item.value).strip(), item.important)
            for item in tinycss2.parse_blocks_contents(content, skip_comments=True, skip_whitespace=True)
            if item.type == "declaration"]


def _valid(name: str, value: str) -> bool:
    """Whether a declaration parses for its property (CSS drops one that does not, so a
    lower-priority declaration applies); properties aaeval does not parse pass."""
    if value.strip().lower() in ("inherit", "initial", "unset"):
        return True
    if name in ("fill", "stroke"):
        return parse_paint(value) is not None
    if name in ("color", "stop-color"):
        return parse_color(value) is not None
    return True


def _apply(declarations, normal: dict, important: dict) -> None:
    for name, value, is_important in declarations:
        if _valid(name, value):
            target = important if is_important else normal
            # the CSS shorthand "marker" sets all three markers
            for prop in ("marker-start", "marker-mid", "marker-end") if name == "marker" else (name,):
                target[prop] = value


def font_size(value: str, parent: float, root_font: float) -> float | None:
    """A computed font size in px, or None when ``value`` is not one."""
    low = value.strip().lower()
    if low in FONT_KEYWORDS:
        return float(FONT_KEYWORDS[low])
    if low == "larger":
        return parent * 1.2
    if low == "smaller":
        return parent / 1.2
    match = LENGTH.match(low)
    if not match:
        return None
    number, unit = float(match.group(1)), match.group(2)
    if number < 0:
        return None
    if unit == "%":
        return number / 100 * parent
    if unit in ("em",):
        return number * parent
    if unit == "ex":
        return number * parent / 2
    if unit == "rem":
        return number * root_font
    return number * ABSOLUTE[unit] if unit in ABSOLUTE else None
