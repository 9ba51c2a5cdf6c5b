"""Text to scenes: ``aaeval import text "STRING" --font FONT.ttf --size PX -o SCENE.toml``.

A glyph is its outline: fontTools reads the font, each glyph's quadratic (TrueType) or
cubic (CFF) outline is scaled to pixels, placed at its exact sub-pixel pen position and
flattened to the tolerance like every other curve (:mod:`aaeval.importers.flatten`);
the nonzero fill of its contours is resolved in float64 (:mod:`aaeval.importers.fill`)
into polygons with holes. Composite glyphs are decomposed through the font's glyph set,
each component drawn through its own transform. Pen positions
are never rounded: the advance widths and the font's ``kern`` table pairs (no GPOS
shaping; that would need HarfBuzz), scaled by size / units-per-em. :func:`layout` is the
one layout both the importer and the ``freetype`` method use, so FreeType draws the same
glyphs at the same places.

The default font is DejaVu Sans as matplotlib ships it (``matplotlib:DejaVuSans.ttf``),
so a text scene needs nothing from the network or the system.
"""

from __future__ import annotations

import math
import struct
from contextlib import contextmanager
from functools import lru_cache
from pathlib import Path
from typing import NamedTuple

import numpy as np

from aaeval.importers.flatten import DEFAULT_TOLERANCE, bezier_points
from aaeval.importers.limits import MAX_GLYPHS, ImportLimitError, VertexBudget, budget_scope, check_tolerance
from aaeval.importers.scene import ImportResult, Layer, scene_document
from aaeval.importers.shapes import Subpath, fill_regions
from aaeval.scenes.sources import font_path

__all__ = ["import_text", "layout", "glyph_subpaths", "PlacedGlyph", "DEFAULT_FONT", "TextError"]

DEFAULT_FONT = "matplotlib:DejaVuSans.ttf"
MAX_SIZE = 1e6  # pixels per em: a stated limit (a glyph would span a million pixels)


class TextError(ValueError):
    """A font that cannot be read, or text it cannot set."""


class PlacedGlyph(NamedTuple):
    char: str
    glyph: str  # the font's glyph name
    gid: int  # glyph index (FreeType's)
    x: float  # pen position on the baseline, image pixels (y down)
    y: float
    scale: float  # pixels per font unit


# unitsPerEm as the OpenType spec bounds it (head table): 0 would divide by zero, and a
# value far outside makes every glyph a point or a continent
UNITS_PER_EM = (16, 16384)


def font_container_error(path: str, data: bytes) -> str | None:
    """Why the bytes of ``path`` cannot be read as a font container, or None.

    WOFF2 is refused by name: its tables are Brotli-compressed and neither fontTools (without
    the optional ``brotli`` module) nor the FreeType the ``freetype`` method loads is sure to
    read it, so a WOFF2 file would be a traceback in one place and a blank image in the other.
    WOFF (zlib) is read by both.
    """
    if data[:4] == b"wOF2":
        return (f"{path}: a WOFF2 font, which is not supported (Brotli-compressed tables); "
                "convert it to .ttf/.otf (or WOFF) first")
    return None


@lru_cache(maxsize=8)
def _font(path: str):
    import io

    from fontTools.ttLib import TTFont

    from aaeval.readlimits import read_bytes

    data = read_bytes(path, what="font")  # a regular file of bounded size, read once
    refused = font_container_error(path, data)
    if refused:
        raise TextError(refused)
    # fontTools parses a damaged file with whatever its parser meets first (KeyError, TTLibError,
    # struct.error, ImportError for an optional codec, ...): every table layout and drawing use
    # is read here, once, so that any of those is one line naming the file, not a traceback
    # halfway through a layout
    try:
        with _fonttools_quiet():
            font = TTFont(io.BytesIO(data), lazy=True)
            order = font.getGlyphOrder()
            for tag in ("head", "hhea", "hmtx", "maxp", "cmap", "loca", "glyf", "CFF ", "kern"):
                if tag in font:
                    font[tag]  # noqa: B018  (loads the table's data: a length or offset past the file fails here)
            cmap = font.getBestCmap() or {}
            units = font["head"].unitsPerEm
    except RecursionError:
        raise TextError(f"{path}: not a readable TrueType/OpenType font (its tables nest without end)") from None
    except Exception as exc:  # noqa: BLE001 - a third-party parser of an untrusted file: see above
        raise TextError(f"{path}: not a readable TrueType/OpenType font ({type(exc).__name__}: "
                        f"{_short(exc)})") from None
    if not (UNITS_PER_EM[0] <= units <= UNITS_PER_EM[1]):
        raise TextError(f"{path}: the font's unitsPerEm is {units}; it must be {UNITS_PER_EM[0]} to "
                        f"{UNITS_PER_EM[1]} (head table)")
    known = set(order)
    hmtx = font["hmtx"]
    for code, name in cmap.items():
        # a maxp that counts fewer glyphs than the cmap uses: fontTools names the rest glyph00043
        if name not in known or name not in hmtx.metrics:
            raise TextError(f"{path}: the cmap maps U+{code:04X} to glyph {name!r}, beyond the "
                            f"{len(order)} glyphs maxp counts (a damaged or truncated font)")
    return font


@contextmanager
def _fonttools_quiet():
    """fontTools logs what it repairs in a damaged font ("too much 'hmtx' table data") as
    warnings on stderr: the one error line is the whole answer, so they are held back."""
    import logging

    log = logging.getLogger("fontTools")
    level = log.level
    if level == logging.CRITICAL:  # held back already (a whole import is): setLevel walks every logger
        yield
        return
    log.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        log.setLevel(level)


def _short(exc: BaseException, limit: int = 200) -> str:
    """An exception's text cut to ``limit`` characters (a parser may echo kilobytes)."""
    text = " ".join(str(exc).split())
    return text if len(text) <= limit else text[:limit] + "..."


def _kerning(font) -> dict:
    if "kern" not in font:
        return {}
    pairs: dict = {}
    for table in font["kern"].kernTables:
        if getattr(table, "format", 0) == 0 and hasattr(table, "kernTable"):
            for key, value in table.kernTable.items():
                pairs.setdefault(key, value)
    return pairs


def layout(font_file: str | Path, string: str, size: float, origin) -> list[PlacedGlyph]:
    """Glyphs of one line of text at their sub-pixel pen positions (no rounding).

    ``origin`` is the pen's start on the baseline (image pixels, y down); ``size`` is
    pixels per em. Characters the font lacks raise :class:`TextError`.
    """
    from fontTools.ttLib import TTLibError

    font = _font(str(font_file))
    try:
        scale = float(size) / font["head"].unitsPerEm
        cmap = font.getBestCmap() or {}
        kern = _kerning(font)
        order = {name: i for i, name in enumerate(font.getGlyphOrder())}
        hmtx = font["hmtx"]
    except (TTLibError, KeyError, IndexError, ValueError, TypeError, ZeroDivisionError, struct.error,
            AssertionError) as exc:
        raise TextError(f"{font_file}: the font's tables cannot be read ({type(exc).__name__}: {exc})") from None
    x, y = float(origin[0]), float(origin[1])
    placed, previous = [], None
    for char in string:
        if ord(char) not in cmap:
            raise TextError(f"{font_file}: the font has no glyph for {char!r} (U+{ord(char):04X})")
        name = cmap[ord(char)]
        if previous is not None:
            x += kern.get((previous, name), 0) * scale
        placed.append(PlacedGlyph(char, name, order[name], x, y, scale))
        x += hmtx[name][0] * scale
        previous = name
    return placed


def glyph_subpaths(font_file: str | Path, glyph: PlacedGlyph, tol: float) -> list[Subpath]:
    """A placed glyph's outline in image pixels, flattened to ``tol``."""
    from fontTools.pens.transformPen import TransformPen
    from fontTools.ttLib import TTLibError

    glyph_set = _glyph_set(_font(str(font_file)))
    pen = _flatten_pen()(glyph_set, tol)
    s = glyph.scale
    # font units (y up) to image pixels (y down) at the glyph's pen position
    try:
        with _fonttools_quiet():
            glyph_set[glyph.glyph].draw(TransformPen(pen, (s, 0, 0, -s, glyph.x, glyph.y)))
    except RecursionError:
        raise TextError(f"{font_file}: glyph {glyph.glyph!r} has components nested without end") from None
    except (TextError, ImportLimitError):
        raise
    except (KeyError, IndexError, ValueError, TypeError, struct.error, AssertionError, TTLibError) as exc:
        raise TextError(f"{font_file}: glyph {glyph.glyph!r} cannot be read ({type(exc).__name__}: {exc})") from None
    pen._finish()
    return pen.subpaths


@lru_cache(maxsize=8)
def _glyph_set(font):
    """The glyphs of ``font`` (as :func:`_font` read it) for drawing, made once per font."""
    return font.getGlyphSet()


@lru_cache(maxsize=1)
def _flatten_pen():
    """The pen that flattens a glyph's outline (a class made once: fontTools is imported only
    when text is imported)."""
    from fontTools.pens.basePen import BasePen

    class FlattenPen(BasePen):
        # BasePen with a glyph set decomposes components: each component's outline is
        # drawn through its own 2x3 transform (nested components compose), as FreeType
        # does; a flipped component keeps its contour direction, as in FreeType.
        def __init__(self, glyph_set, tol: float):
            super().__init__(glyph_set)
            self.tol = tol
            self.subpaths: list[Subpath] = []
            self.points: list = []

        def _moveTo(self, pt):
            self._finish()
            self.points = [pt]

        def _lineTo(self, pt):
            self.points.append(pt)

        def _qCurveToOne(self, pt1, pt2):
            self.points.extend(bezier_points([self._getCurrentPoint(), pt1, pt2], self.tol))

        def _curveToOne(self, pt1, pt2, pt3):
            self.points.extend(bezier_points([self._getCurrentPoint(), pt1, pt2, pt3], self.tol))

        def _closePath(self):
            self._finish()

        _endPath = _closePath

        def _finish(self):
            if len(self.points) >= 3:
                self.subpaths.append(Subpath(np.array(self.points, dtype=np.float64), True))
            self.points = []

    return FlattenPen


def line_metrics(font_file: str | Path, size: float) -> tuple[float, float, float]:
    """(ascent, descent, line gap) in pixels at ``size`` (descent positive, below the baseline)."""
    font = _font(str(font_file))
    hhea, scale = font["hhea"], float(size) / font["head"].unitsPerEm
    return hhea.ascent * scale, -hhea.descent * scale, hhea.lineGap * scale


def import_text(
    string: str, *, font: str | None = None, sizes=(12.0,), color=(0.0, 0.0, 0.0), background=(1.0, 1.0, 1.0),
    origin=None, margin: float = 2.0, tolerance: float = DEFAULT_TOLERANCE, frames: int = 1,
    translate=(0.0, 0.0), font_ref: str | None = None,
) -> ImportResult:
    """Import ``string`` set once per size (one line each) as a scene dictionary.

    The first line's pen starts at ``origin`` (default: ``margin`` from the left, its
    ascent plus ``margin`` down); each next line starts one line height below. The
    image is just large enough for every line plus ``margin``. ``font_ref`` is how the
    scene's ``[text].font`` names the font (default: ``font`` as given, or DejaVu Sans).
    """
    if not string:
        raise TextError("nothing to import: the string is empty")
    sizes = [float(s) for s in sizes]
    if not sizes or any(not (math.isfinite(s) and s > 0) for s in sizes):
        raise TextError(f"sizes must be positive numbers of pixels, got {sizes}")
    if any(s > MAX_SIZE for s in sizes):
        raise TextError(f"sizes above {MAX_SIZE:g} px are over the limit, got {max(sizes):g}")
    if len(string) * len(sizes) > MAX_GLYPHS:
        raise TextError(f"{len(string)} characters at {len(sizes)} size(s) are {len(string) * len(sizes)} glyphs, "
                        f"over the limit of {MAX_GLYPHS}")
    reference = font_ref if font_ref is not None else (DEFAULT_FONT if font is None else str(font))
    file = font_path(".", font or DEFAULT_FONT)
    if not file.exists():
        raise TextError(f"{file}: no such font file")  # other kinds of file: refused by the reader
    ascent0 = line_metrics(file, sizes[0])[0]
    x0, y = (margin, margin + ascent0) if origin is None else (float(origin[0]), float(origin[1]))
    # the layout first (cheap): the image size bounds the tolerance before any flattening
    lines, origins, right, bottom = [], [], 0.0, 0.0
    for k, size in enumerate(sizes):
        ascent, descent, gap = line_metrics(file, size)
        if k > 0:
            y += previous_descent + gap + ascent
        origins.append([x0, y])
        lines.append((size, layout(file, string, size, (x0, y))))
        right = max(right, x0 + _advance(file, string, size))
        bottom = y + descent
        previous_descent = descent
    width, height = math.ceil(right + margin), math.ceil(bottom + margin)
    try:
        check_tolerance(tolerance, width, height)
    except ImportLimitError as exc:
        raise TextError(str(exc)) from None
    layers = []
    with budget_scope(VertexBudget()), _fonttools_quiet():
        for size, glyphs in lines:
            for glyph in glyphs:
                regions = fill_regions(glyph_subpaths(file, glyph, tolerance), "nonzero")
                if regions:
                    layers.append(Layer(np.asarray(color, dtype=np.float64), regions, f"{glyph.char!r} at {size:g} px"))
    source = {"font": reference, "color": [float(c) for c in color], "tolerance": float(tolerance),
              "strings": [string] * len(sizes), "sizes": sizes, "origins": origins}
    document, cut = scene_document(
        width, height, background, layers,
        extension=("text", source), frames=frames, translate=translate,
    )
    return ImportResult(document, [], cut)


def _advance(font_file, string: str, size: float) -> float:
    glyphs = layout(font_file, string, size, (0.0, 0.0))
    font = _font(str(font_file))
    return glyphs[-1].x + font["hmtx"][glyphs[-1].glyph][0] * glyphs[-1].scale
