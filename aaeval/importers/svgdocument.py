"""An SVG document before anything is drawn: the XML checked, element kinds, references.

:func:`check_document` parses the file and refuses, before anything is expanded, what is
not an SVG document (root ``<svg>``, a valid ``viewBox``), more than
:data:`~aaeval.importers.limits.MAX_ELEMENTS` elements once ``<use>`` is expanded
(:func:`count_elements`, counted without expanding) and more vertices than the limits
allow, estimated from the numbers in path data. :class:`Tree` holds the lookups the walk
needs (the element of each id, the parent of each element); the tables name which
elements are drawn as shapes or containers and which are listed as not imported.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from aaeval.importers.limits import MAX_EDGES, MAX_ELEMENTS, MAX_VERTICES

__all__ = ["SvgError", "Tree", "check_document", "count_elements", "svg_tag", "conditions_pass", "SVG_NS",
           "XLINK_HREF", "SHAPES", "MARKABLE", "CONTAINERS", "NOT_IMPORTED", "MAX_USE_DEPTH"]

SVG_NS = "{http://www.w3.org/2000/svg}"
XLINK_HREF = "{http://www.w3.org/1999/xlink}href"
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
SHAPES = ("rect", "circle", "ellipse", "line", "polyline", "polygon", "path")
MARKABLE = ("path", "line", "polyline", "polygon")
CONTAINERS = ("g", "a")
NOT_IMPORTED = {"text": "text element not imported (use 'aaeval import text')", "image": "image not imported",
                "foreignObject": "foreignObject not imported", "video": "video not imported",
                "audio": "audio not imported", "iframe": "iframe not imported", "canvas": "canvas not imported"}
# <use> and markers nested deeper than this draw nothing (a reference chain, not a drawing)
MAX_USE_DEPTH = 64


class SvgError(ValueError):
    """An SVG file that cannot be read or imported."""


class Tree:
    """The element of each id (the first one: it is the one referenced) and the parent
    of each element (by ``id()``), for the walk and what it resolves."""

    def __init__(self, root):
        self.root = root
        self.by_id: dict[str, object] = {}
        self.parent: dict[int, object] = {}
        for el in root.iter():
            ident = el.get("id")
            if ident is not None:
                self.by_id.setdefault(ident, el)  # the first element with an id is the one referenced
            for child in el:
                self.parent[id(child)] = el


def svg_tag(el) -> str | None:
    """The local name of an SVG element (no namespace is taken as SVG), else None."""
    tag = el.tag
    if not isinstance(tag, str):
        return None  # comments, processing instructions
    if tag.startswith(SVG_NS):
        return tag[len(SVG_NS):]
    return None if tag.startswith("{") else tag


#: The user language ``systemLanguage`` is tested against (the resvg method renders with it too).
LANGUAGE = "en"


def conditions_pass(el) -> bool:
    """SVG 2's conditional processing: requiredExtensions (none supported), systemLanguage."""
    if el.get("requiredExtensions") is not None:
        return False
    languages = el.get("systemLanguage")
    if languages is not None:
        return any(lang.strip().lower().split("-")[0] == LANGUAGE for lang in languages.split(","))
    return True



def _local_name(tag) -> str:
    tag = str(tag)
    return tag.rsplit("}", 1)[-1] if tag.startswith("{") else tag


def count_elements(root, limit: int = MAX_ELEMENTS) -> int:
    """Elements of the tree once every ``<use>`` is expanded, counted without expanding
    (each element's count once, memoised); stops early past ``limit``. A reference cycle
    raises :class:`SvgError`."""
    by_id = {}
    for el in root.iter():
        ident = el.get("id")
        if ident is not None:
            by_id.setdefault(ident, el)
    memo: dict[int, int] = {}
    state: dict[int, int] = {}  # 1 on the stack, 2 done

    def count(el) -> int:
        key = id(el)
        if state.get(key) == 2:
            return memo[key]
        if state.get(key) == 1:
            raise SvgError(f"<use> references form a cycle through {el.get('id') or _local_name(el.tag)!r}")
        state[key] = 1
        total = 1
        for child in el:
            total += count(child)
            if total > limit:
                break
        if _local_name(el.tag) == "use":
            href = el.get("href") or el.get(XLINK_HREF) or ""
            target = by_id.get(href[1:]) if href.startswith("#") else None
            if target is not None:
                total += count(target)
        state[key] = 2
        memo[key] = min(total, limit + 1)
        return memo[key]

    import sys

    old = sys.getrecursionlimit()
    sys.setrecursionlimit(max(old, 20000))
    try:
        return count(root)
    except RecursionError:
        raise SvgError("elements are nested too deeply to import") from None
    finally:
        sys.setrecursionlimit(old)


def check_document(data: bytes, path: Path):
    """The document's root element. Refuse, before anything is expanded, a file that is not an SVG document, a
    malformed viewBox, and more than MAX_ELEMENTS elements after ``<use>`` expansion."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.fromstring(data)
    except ET.ParseError as exc:
        raise SvgError(f"{path}: not a readable SVG (XML: {exc})") from None
    except Exception as exc:  # entity limits of the XML parser and the like
        raise SvgError(f"{path}: not a readable SVG ({type(exc).__name__}: {exc})") from None
    if _local_name(root.tag) != "svg":
        raise SvgError(f"{path}: not an SVG document (its root element is <{_local_name(root.tag)}>, not <svg>)")
    box = root.get("viewBox")
    if box is not None:
        parts = re.split(r"[\s,]+", box.strip())
        try:
            numbers = [float(v) for v in parts]
        except ValueError:
            numbers = []
        if len(numbers) != 4 or not all(map(math.isfinite, numbers)):
            raise SvgError(f"{path}: viewBox {box[:60]!r} is not four finite numbers")
        if numbers[2] <= 0 or numbers[3] <= 0:
            raise SvgError(f"{path}: viewBox {box[:60]!r} has a width or height that is not positive (an error in "
                           "SVG; zero disables rendering)")
    try:
        n = count_elements(root)
    except SvgError as exc:
        raise SvgError(f"{path}: {exc}") from None
    if n > MAX_ELEMENTS:
        raise SvgError(f"{path}: more than {MAX_ELEMENTS} elements once <use> references are expanded (the limit)")
    # vertices, estimated from the numbers in path data and point lists (two per vertex),
    # before any segment is built
    total = 0
    for el in root.iter():
        for key in ("d", "points"):
            raw = el.get(key)
            if not raw:
                continue
            vertices = len(NUMBER.findall(raw)) // 2
            total += vertices
            if vertices > MAX_EDGES:
                name = f"#{el.get('id')}" if el.get("id") else f"a <{_local_name(el.tag)}>"
                raise SvgError(f"{path}: {name} has about {vertices} vertices, over the limit of {MAX_EDGES} "
                               "for one outline")
    if total > MAX_VERTICES:
        raise SvgError(f"{path}: about {total} vertices in path data, over the limit of {MAX_VERTICES}")
    return root
