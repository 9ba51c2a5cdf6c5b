"""Faster font subsets for the figures' PDFs, the same bytes as matplotlib's own.

A PDF embeds the glyphs it shows as a TrueType (Type 42) subset of the font, which
matplotlib cuts with fontTools from the whole font file for every figure: most of that time
goes to reading the font's large layout tables (DejaVu Sans kerns thousands of glyphs).
Within :func:`subsets_from_base` the cut is made in two steps: once per process the font is
cut down to a *base* holding the characters a chart's text uses (Latin, Greek, punctuation,
super- and subscripts, mathematical signs, arrows and ligatures), and each figure's subset
is then cut from that small base.
Subsetting keeps what the requested glyphs reach (their substitutions, kerning pairs among
them), all of which the base kept, so the two steps give the same font file as one
(tests/report/test_pdf_fonts.py compares the bytes); a figure needing a glyph outside the
base is cut from the whole font as before.
"""

from __future__ import annotations

import contextlib
import io
from typing import NamedTuple

from matplotlib import font_manager
from matplotlib.backends import _backend_pdf_ps

__all__ = ["BASE_CHARACTERS", "subsets_from_base", "prepare_base"]

#: The code point ranges of the base (half-open): what a chart's labels, titles and legends write.
BASE_CHARACTERS = ((0x20, 0x7F), (0xA0, 0x180), (0x370, 0x400), (0x2000, 0x20A0),
                   (0x2190, 0x2200), (0x2200, 0x2300), (0xFB00, 0xFB07))  # the last: ligatures (fi, ffi)

_whole_font_subset = _backend_pdf_ps.get_glyphs_subset


class _Base(NamedTuple):
    data: bytes  # the base font file
    index: dict  # glyph index in the whole font -> in the base
    # the glyphs a subset may be cut from the base for: every character that the whole font
    # draws with one of them is in the base (its subset's cmap lists them all)
    whole: frozenset


class _FontBytes(io.BytesIO):
    """A font file in memory, in the shape matplotlib's subsetter takes (a path with a face index)."""

    face_index = 0


_bases: dict[tuple[str, int], _Base | None] = {}


def prepare_base(fontfile) -> None:
    """Cut the base of ``fontfile`` (a path, or matplotlib's FontPath) now, e.g. before
    forking workers that share it."""
    face = getattr(fontfile, "face_index", 0)
    key = (str(fontfile), face)
    if key in _bases:
        return
    charmap = font_manager.get_font(fontfile).get_charmap()
    glyphs = {charmap[c] for start, stop in BASE_CHARACTERS for c in range(start, stop) if c in charmap}
    elsewhere = {g for c, g in charmap.items() if not any(start <= c < stop for start, stop in BASE_CHARACTERS)}
    try:
        with _whole_font_subset(fontfile, glyphs) as base:
            index = dict(base.glyph_index_map)
            _bases[key] = _Base(_backend_pdf_ps.font_as_file(base.font).getvalue(), index,
                                frozenset(index.keys() - elsewhere))
    except Exception:  # noqa: BLE001 - a font fontTools cannot cut: every subset comes from the whole font
        _bases[key] = None


def _subset(fontfile, glyphs):
    glyphs = set(glyphs)
    prepare_base(fontfile)
    base = _bases[(str(fontfile), getattr(fontfile, "face_index", 0))]
    if base is None or not glyphs <= base.whole:
        return _whole_font_subset(fontfile, glyphs)
    return _composed(base, glyphs)


@contextlib.contextmanager
def _composed(base: _Base, glyphs: set):
    with _whole_font_subset(_FontBytes(base.data), {base.index[g] for g in glyphs}) as cut:
        # the caller looks glyphs up by their index in the whole font
        index = {whole: cut.glyph_index_map[b] for whole, b in base.index.items() if b in cut.glyph_index_map}
        yield _backend_pdf_ps.SubsetResults(cut.font, index)


@contextlib.contextmanager
def subsets_from_base():
    """Within this block matplotlib's PDF (and PS) backends cut font subsets from the bases."""
    _backend_pdf_ps.get_glyphs_subset = _subset
    try:
        yield
    finally:
        _backend_pdf_ps.get_glyphs_subset = _whole_font_subset
