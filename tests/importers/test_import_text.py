"""``aaeval import text`` and the ``freetype`` method: the imported pangram's area matches
FreeType's own outline area (its 26.6 outline, integrated exactly) to the flattening
tolerance, catmull and weiler-atherton agree with the GEOS oracle on it, FreeType's
rasterizer draws the same glyphs in the same places, and text scrolls by 1/8 px with its
intensity sum unchanged under the exact method."""

from __future__ import annotations

import math
from pathlib import Path

import freetype
import numpy as np
import pytest

from aaeval.cli import main
from aaeval.importers.text import DEFAULT_FONT, import_text, layout
from aaeval.renderers import render
from aaeval.scenes import parse_scene
from aaeval.scenes.holes import ring_area
from aaeval.scenes.sources import font_path

from tests.helpers.oracle import oracle_image

ROOT = Path(__file__).parents[2]
PANGRAM = "The quick brown fox jumps over the lazy dog"
FONT = str(font_path(".", DEFAULT_FONT))
GAUSS_T, GAUSS_W = np.polynomial.legendre.leggauss(3)  # exact for B x B' of a cubic (degree 5)
GAUSS_T, GAUSS_W = (GAUSS_T + 1) / 2, GAUSS_W / 2


def freetype_outline(gid, size):
    """Area (px^2, unsigned) and outline length of FreeType's own unhinted outline of a glyph."""
    face = freetype.Face(FONT)
    face.set_char_size(int(round(size * 64)))
    face.load_glyph(gid, freetype.FT_LOAD_NO_HINTING | freetype.FT_LOAD_NO_BITMAP)
    acc = {"area": 0.0, "length": 0.0, "at": None}

    def v(p):
        return np.array([p.x, p.y], dtype=np.float64) / 64.0

    def segment(*control):  # a Bézier from the current point: exact (1/2) integral of B x B'
        pts = np.array([acc["at"], *control])
        k = len(pts) - 1
        for t, w in zip(GAUSS_T, GAUSS_W):
            b = sum(math.comb(k, i) * t**i * (1 - t) ** (k - i) * pts[i] for i in range(k + 1))
            d = sum(k * math.comb(k - 1, i) * t**i * (1 - t) ** (k - 1 - i) * (pts[i + 1] - pts[i]) for i in range(k))
            acc["area"] += 0.5 * w * (b[0] * d[1] - b[1] * d[0])
        acc["length"] += np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()
        acc["at"] = pts[-1]

    def move_to(a, _):
        acc["at"] = v(a)

    face.glyph.outline.decompose(
        None, move_to=move_to, line_to=lambda a, _: segment(v(a)),
        conic_to=lambda a, b, _: segment(v(a), v(b)), cubic_to=lambda a, b, c, _: segment(v(a), v(b), v(c)))
    return abs(acc["area"]), acc["length"]


@pytest.mark.slow
@pytest.mark.parametrize("tol", [1 / 16, 1 / 4])
@pytest.mark.parametrize("size", [9.0, 12.0, 16.0])
def test_imported_pangram_area_matches_freetype_outline_area(size, tol):
    result = import_text(PANGRAM, sizes=[size], tolerance=tol)
    scene = parse_scene(result.document)
    (origin,) = scene.extensions["text"].origins
    expected, length = 0.0, 0.0
    for glyph in layout(FONT, PANGRAM, size, origin):
        a, s = freetype_outline(glyph.gid, size)
        expected += a
        length += s
    got = sum(_area(p) for p in result.document["polygons"])
    # flattening moves the outline by <= tol; FreeType's 26.6 rounding by <= sqrt(2)/128
    assert abs(got - expected) <= (tol + np.sqrt(2) / 128) * length, (got, expected)
    # and the flattened outline errs to both sides: the net area is far closer still
    assert abs(got - expected) <= 0.1 * tol * length
    # the exact renderer's ink is exactly the imported area
    ink = (1.0 - render(scene, "catmull")[..., 0]).sum()
    assert ink == pytest.approx(got, rel=1e-10)


def _area(polygon):
    xy = np.array(polygon["vertices"])[:, :2]
    return abs(ring_area(xy)) - sum(abs(ring_area(np.array(h)[:, :2])) for h in polygon.get("holes", []))


def test_exact_methods_match_geos_on_text():
    result = import_text("Hello, glyphs @ 9px!", sizes=[9.0, 13.0])
    scene = parse_scene(result.document)
    assert scene.holed  # e, o, g, @ have holes
    moved = parse_scene({**result.document, "animation": {"frames": 2, "translate": [0.375, 0.125]}}).at_frame(1)
    for s in (scene, moved):
        expected = oracle_image(s)
        np.testing.assert_allclose(render(s, "catmull"), expected, atol=1e-9, rtol=0)
        np.testing.assert_allclose(render(s, "weiler-atherton"), expected, atol=1e-9, rtol=0)


def test_freetype_draws_the_same_glyphs_in_the_same_places():
    scene = parse_scene(import_text(PANGRAM, sizes=[9.0, 12.0, 16.0]).document)
    exact = render(scene, "catmull")
    ft = render(scene, "freetype")
    # FreeType: 8-bit coverage, 1/64 px positions, its own flattening; a glyph in the wrong
    # place would put whole strokes off (errors near 1)
    assert np.sqrt(np.mean((ft - exact) ** 2)) < 0.01
    assert np.abs(ft - exact).max() < 0.1
    ink_ft, ink_exact = (1 - ft[..., 0]).sum(), (1 - exact[..., 0]).sum()
    assert abs(ink_ft - ink_exact) < 0.002 * ink_exact


def test_scrolling_text_keeps_its_intensity_sum_under_the_exact_method():
    doc = import_text(PANGRAM, sizes=[9.0], frames=8, translate=(0.0, 0.125), margin=3.0).document
    scene = parse_scene(doc)
    sums = [render(scene, "catmull", frame=k).sum() for k in range(scene.frames)]
    assert np.ptp(sums) < 1e-9 * sums[0]
    first, last = scene.extensions["text"].origins, scene.at_frame(7).extensions["text"].origins
    np.testing.assert_allclose(last - first, [[0.0, 0.875]])
    # FreeType's sum moves a little (8-bit coverage, rounding): it must still track the text
    ft = [render(scene, "freetype", frame=k) for k in (0, 4)]
    assert not np.array_equal(ft[0], ft[1])


def test_cli_text_and_refusals(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["import", "text", "Ag", "--size", "10", "-o", "t.toml"]) == 0
    assert 'font = "matplotlib:DejaVuSans.ttf"' in (tmp_path / "t.toml").read_text()
    bad_font = tmp_path / "bad.ttf"
    bad_font.write_bytes(b"not a font")
    for args in (["import", "text", "Ag", "--font", str(bad_font), "-o", "u.toml"],
                 ["import", "text", "Ag", "--size", "-3", "-o", "u.toml"],
                 ["import", "text", "\u4e2d", "-o", "u.toml"],
                 ["render", str(ROOT / "configs" / "scenes" / "abutting.toml"), "-m", "freetype", "-o", "x.npy"],
                 ["render", "t.toml", "-m", "resvg", "-o", "x.npy"]):
        capsys.readouterr()
        assert main(args) == 2, args
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "u.toml").exists()
