"""An SVG element's own transform: its ``transform`` attribute about its ``transform-origin``.

SVG 2 maps the ``transform`` attribute to the CSS ``transform`` property, so
``transform-origin`` (CSS Transforms 1, 6) applies to it: the map is
``translate(origin) . transform . translate(-origin)``. With ``transform-box`` at its
initial ``view-box``, the reference box of keywords and percentages is the nearest
viewport: placed at the origin of the user space its viewBox establishes, sized as the
viewBox (its width and height, or the viewport's without one). An origin that does not
parse is its initial value ``0 0`` (a declaration CSS drops), so the transform is applied
as written.
"""

from __future__ import annotations

from aaeval.importers.svgpath import compose, parse_transform, translate
from aaeval.importers.svgstyle import LengthError, Lengths

__all__ = ["element_transform", "transform_origin"]

# keyword: (axis it fixes, or None for either, fraction of the reference box)
ORIGIN_KEYWORDS = {"left": ("x", 0.0), "right": ("x", 1.0), "top": ("y", 0.0), "bottom": ("y", 1.0),
                   "center": (None, 0.5)}


def element_transform(raw: str | None, origin: str, lengths: Lengths):
    """The map of an element's ``transform`` attribute ``raw`` about ``origin`` (its
    computed ``transform-origin``): None without a transform, ``False`` when ``raw`` is not
    a valid transform list (SVG: no transform)."""
    if raw is None:
        return None
    own = parse_transform(raw)
    if own is None:
        return False
    ox, oy = transform_origin(origin, lengths)
    if ox == 0.0 and oy == 0.0:
        return own
    return compose(translate(ox, oy), compose(own, translate(-ox, -oy)))


def transform_origin(value: str, lengths: Lengths) -> tuple[float, float]:
    """The point (user units) a ``transform-origin`` value names; (0, 0) when it is not valid.

    One value sets x (or y, for ``top``/``bottom``) and centres the other; two values are
    x then y, keywords in either order; a third (z) must be a length and is dropped, as a
    2-D transform ignores it.
    """
    words = str(value).split()
    if not 1 <= len(words) <= 3:
        return (0.0, 0.0)
    if len(words) == 3:
        try:
            lengths.resolve(words[2], "d")
        except LengthError:
            return (0.0, 0.0)
        if words[2].strip().endswith("%"):
            return (0.0, 0.0)
        words = words[:2]
    width, height = lengths.viewport
    size = {"x": width, "y": height}
    axes: dict[str, float] = {}
    pending = []  # 'center' keywords, placed once the other value's axis is known
    for k, word in enumerate(words):
        low = word.lower()
        if low in ORIGIN_KEYWORDS:
            axis, fraction = ORIGIN_KEYWORDS[low]
            if axis is None:
                pending.append(fraction)
                continue
        else:
            axis = "x" if k == 0 else "y"  # a length: first is x, second y
            if len(words) == 2 and k == 0 and words[1].lower() in ("left", "right"):
                return (0.0, 0.0)  # 'length left' is not valid
            try:
                value_px = lengths.resolve(word, axis)
            except LengthError:
                return (0.0, 0.0)
            if axis in axes:
                return (0.0, 0.0)
            axes[axis] = value_px
            continue
        if axis in axes:
            return (0.0, 0.0)  # 'left right', 'top bottom'
        axes[axis] = fraction * size[axis]
    for fraction in pending:
        axis = "x" if "x" not in axes else "y"
        if axis in axes:
            return (0.0, 0.0)
        axes[axis] = fraction * size[axis]
    return (axes.get("x", 0.5 * width), axes.get("y", 0.5 * height))
