"""The figures' PDF font subsets cut from a per-process base are the bytes matplotlib cuts
from the whole font (the oracle: matplotlib's own subsetting, outside the block)."""

from __future__ import annotations

import io
import random

import pytest

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import font_manager  # noqa: E402
from matplotlib.backends import _backend_pdf_ps  # noqa: E402

from aaeval.report import pdf_fonts  # noqa: E402

pytestmark = pytest.mark.slow  # each subset from the whole font takes 0.07 s

FONT = font_manager.findfont(font_manager.FontProperties(family="DejaVu Sans"))


def _cut(glyphs):
    with _backend_pdf_ps.get_glyphs_subset(FONT, glyphs) as cut:
        return _backend_pdf_ps.font_as_file(cut.font).getvalue(), dict(cut.glyph_index_map)


def test_a_subset_cut_from_the_base_is_the_subset_cut_from_the_whole_font():
    charmap = font_manager.get_font(FONT).get_charmap()
    inside = sorted({charmap[c] for a, b in pdf_fonts.BASE_CHARACTERS for c in range(a, b) if c in charmap})
    outside = charmap[0x0416]  # Cyrillic: beyond the base
    also_outside = charmap[0x239B]  # a glyph the base holds for a ligature's sake, but its character is not in the base
    rng = random.Random(5)
    cases = [{inside[0]}] + [set(rng.sample(inside, k)) for k in (30, 200)]
    cases += [{outside, *inside[:10]}, {also_outside, *inside[:10]}]  # cut from the whole font
    # kerning and ligature partners (AV, fi) among the requested glyphs
    cases.append({charmap[ord(c)] for c in "AVAWTo fifl ffi -1.5e3 10⁻³ ≤ σ Δ × −"})
    cases.append({charmap[c] for c in (0xFB02, 0xFB03, ord("f"), ord("l"), ord(" "))})  # ligatures matplotlib shapes
    expected = [_cut(g) for g in cases]
    matplotlibs = _backend_pdf_ps.get_glyphs_subset
    with pdf_fonts.subsets_from_base():
        got = [_cut(g) for g in cases]
    assert _backend_pdf_ps.get_glyphs_subset is matplotlibs  # restored on leaving
    for want, have, glyphs in zip(expected, got, cases):
        assert have[0] == want[0], sorted(glyphs)
        assert {g: have[1][g] for g in glyphs} == {g: want[1][g] for g in glyphs}


def test_a_figures_pdf_is_the_same_with_subsets_cut_from_the_base():
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1], label="catmull σ≤0.5 — Δ×2")
    ax.set_title("Fan, difficulty 12: flicker (mean |Δ| per frame)")
    ax.legend()

    def pdf():
        buf = io.BytesIO()
        with matplotlib.rc_context({"pdf.fonttype": 42}):
            fig.savefig(buf, format="pdf", metadata={"CreationDate": None})
        return buf.getvalue()

    whole = pdf()
    with pdf_fonts.subsets_from_base():
        based = pdf()
    plt.close(fig)
    assert b"/FontFile2" in whole  # embedded TrueType
    assert based == whole
