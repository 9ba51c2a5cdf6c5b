"""Scene-format extensions ``[svg]`` and ``[text]``: where an imported scene came from.

They let a renderer that draws the source itself (``resvg`` for SVG, ``freetype`` for
text) draw exactly what was imported; every other method reads only the polygons, which
are the whole scene (:data:`SOURCE_TABLES`). Both
move with the scene's animation (an offset added to the source's placement).

``[svg]``: ``file`` (the SVG, relative to the scene file's folder unless absolute),
``scale`` (scene pixels per SVG pixel), ``tolerance`` (the flattening tolerance, px),
``ignored`` (what the importer left out, by element; a renderer of
the source must refuse a scene that ignored anything, since it would draw it).

``[text]``: ``font`` (a font file, relative to the scene file's folder, or
``"matplotlib:NAME.ttf"`` for a font shipped in matplotlib), ``color`` (linear RGB),
``tolerance``, and three lists of one entry per line of text: ``strings``, ``sizes``
(px per em) and ``origins`` ([x, y] of the pen's start on the baseline, px).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from aaeval._toml import refuse_unknown_keys
from aaeval.scenes.format import SceneError, number, register_section, rgb, vector

__all__ = ["SvgSource", "TextSource", "SOURCE_TABLES", "font_path", "source_path"]

# Tables that only record where the polygons came from: a method that draws the polygons
# draws the whole scene, and may ignore them.
SOURCE_TABLES = frozenset({"svg", "text"})


@dataclass(frozen=True)
class SvgSource:
    file: str
    scale: float
    tolerance: float
    ignored: tuple[str, ...]
    offset: np.ndarray  # (2,) px, the animation's translation at this frame


@dataclass(frozen=True)
class TextSource:
    font: str
    color: np.ndarray
    tolerance: float
    strings: tuple[str, ...]
    sizes: tuple[float, ...]
    origins: np.ndarray  # (lines, 2) px, at this frame


def source_path(scene_source: str, file: str) -> Path:
    """A file named in an extension table, resolved against the scene file's folder."""
    path = Path(file)
    return path if path.is_absolute() else Path(scene_source).parent / path


def font_path(scene_source: str, font: str) -> Path:
    """The font file of a ``[text]`` table (``matplotlib:NAME`` names a font matplotlib ships)."""
    if font.startswith("matplotlib:"):
        import matplotlib

        return Path(matplotlib.get_data_path()) / "fonts" / "ttf" / font.split(":", 1)[1]
    return source_path(scene_source, font)


def _string(table: Mapping, key: str, where: str) -> str:
    value = table.get(key)
    if not isinstance(value, str) or not value:
        raise SceneError(f"{where}: '{key}' must be a non-empty string, got {value!r}")
    return value


def _positive(table: Mapping, key: str, where: str) -> float:
    if key not in table:
        raise SceneError(f"{where}: missing required key '{key}'")
    value = number(table[key], f"{where}.{key}")
    if value <= 0:
        raise SceneError(f"{where}: '{key}' must be > 0, got {value}")
    return value


def _strings(value: Any, where: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise SceneError(f"{where}: expected a list of strings, got {value!r}")
    return tuple(value)


def _parse_svg(value: Any, where: str, document: dict) -> SvgSource:
    if not isinstance(value, Mapping):
        raise SceneError(f"{where}: must be a table")
    refuse_unknown_keys(value, {"file", "scale", "tolerance", "ignored"}, where, SceneError)
    return SvgSource(
        file=_string(value, "file", where),
        scale=_positive(value, "scale", where),
        tolerance=_positive(value, "tolerance", where),
        ignored=_strings(value.get("ignored", []), f"{where}.ignored"),
        offset=np.zeros(2),
    )


def _parse_text(value: Any, where: str, document: dict) -> TextSource:
    if not isinstance(value, Mapping):
        raise SceneError(f"{where}: must be a table")
    refuse_unknown_keys(value, {"font", "color", "tolerance", "strings", "sizes", "origins"}, where, SceneError)
    for key in ("color", "strings", "sizes", "origins"):
        if key not in value:
            raise SceneError(f"{where}: missing required key '{key}'")
    strings = _strings(value["strings"], f"{where}.strings")
    sizes, origins = value["sizes"], value["origins"]
    if not isinstance(sizes, list) or not isinstance(origins, list) or not (len(strings) == len(sizes) == len(origins)):
        raise SceneError(f"{where}: 'strings', 'sizes' and 'origins' must be lists of one entry per line")
    sizes = tuple(number(s, f"{where}.sizes") for s in sizes)
    if any(s <= 0 for s in sizes):
        raise SceneError(f"{where}: every size must be > 0")
    return TextSource(
        font=_string(value, "font", where),
        color=rgb(value["color"], f"{where}.color"),
        tolerance=_positive(value, "tolerance", where),
        strings=strings,
        sizes=sizes,
        origins=np.array([vector(o, 2, f"{where}.origins") for o in origins]).reshape(-1, 2),
    )


register_section("svg", _parse_svg, lambda s, shift: replace(s, offset=s.offset + shift))
register_section("text", _parse_text, lambda t, shift: replace(t, origins=t.origins + shift))
