"""Import stays exact on ordinary real input.

Every expected value comes from a route that shares nothing with the importer's geometry:
fontTools' own AreaPen (exact area of the quadratic outline, components decomposed by the
glyph set) for composite glyphs, Skia's own stroker on a fine flattening for stroke joins,
and GEOS on the raw path coordinates (winding numbers counted here, pixel by pixel
intersections with pixel squares) for fill rules.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
import skia
from shapely.geometry import LineString, box
from shapely.geometry import Polygon as ShapelyPolygon

from aaeval.importers.svg import import_svg
from aaeval.importers.text import DEFAULT_FONT, TextError, import_text, layout
from aaeval.scenes import parse_scene
from aaeval.scenes.sources import font_path

FONT = str(font_path(".", DEFAULT_FONT))


def _union(document):
    polys = [ShapelyPolygon([v[:2] for v in p["vertices"]], [[v[:2] for v in h] for h in p.get("holes", [])])
             for p in document["polygons"]]
    return shapely.unary_union(polys)


def _winding(pt, rings) -> int:
    x, y = pt
    total = 0
    for r in rings:
        a, b = np.asarray(r, float), np.roll(np.asarray(r, float), -1, axis=0)
        cross = (b[:, 0] - a[:, 0]) * (y - a[:, 1]) - (x - a[:, 0]) * (b[:, 1] - a[:, 1])
        up = (a[:, 1] <= y) & (b[:, 1] > y) & (cross > 0)
        down = (a[:, 1] > y) & (b[:, 1] <= y) & (cross < 0)
        total += int(up.sum()) - int(down.sum())
    return total


def _geos_fill(rings, rule):
    """The filled region of raw rings under a fill rule: GEOS's faces of the arrangement,
    each kept by its winding number counted here."""
    lines = shapely.unary_union([LineString(np.vstack([r, r[:1]])) for r in rings])
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(lines)))
    keep = [f for f in faces
            if (lambda w: w != 0 if rule == "nonzero" else w % 2 == 1)(_winding(f.representative_point().coords[0], rings))]
    return shapely.unary_union(keep)


# --- item 3: composite glyphs -----------------------------------------------------------

def _fonttools_area_and_length(glyph_name, scale):
    """Exact outline area (px^2) by fontTools' AreaPen through the glyph set (components
    decomposed with their transforms), and an upper bound of the outline length."""
    from fontTools.pens.areaPen import AreaPen
    from fontTools.pens.recordingPen import DecomposingRecordingPen
    from fontTools.ttLib import TTFont

    font = TTFont(FONT)
    glyphs = font.getGlyphSet()
    pen = AreaPen(glyphs)
    glyphs[glyph_name].draw(pen)
    rec = DecomposingRecordingPen(glyphs)
    glyphs[glyph_name].draw(rec)
    length, at, first = 0.0, None, None
    for op, args in rec.value:  # control polygon length bounds the curve length
        if op == "moveTo":
            at = first = np.array(args[0], float)
        elif op in ("lineTo", "qCurveTo", "curveTo"):
            for p in args:
                if p is None:
                    continue
                p = np.array(p, float)
                length += float(np.hypot(*(p - at)))
                at = p
        elif op == "closePath":
            length += float(np.hypot(*(first - at)))
            at = first
    return abs(pen.value) * scale * scale, length * scale, glyphs[glyph_name]


@pytest.mark.slow
@pytest.mark.parametrize("char", ["é", "μ", "Å", "ǅ", "ﬁ", "ő", "Ǻ"])
@pytest.mark.parametrize("tol", [1 / 16, 1 / 256])
def test_composite_glyph_area_matches_fonttools(char, tol):
    size = 40.0
    result = import_text(char, sizes=[size], tolerance=tol)
    scene = parse_scene(result.document)
    (glyph,) = layout(FONT, char, size, scene.extensions["text"].origins[0])
    expected, length, _ = _fonttools_area_and_length(glyph.glyph, glyph.scale)
    got = _union(result.document).area
    assert expected > 1.0
    # each flattened point lies within tol of the outline: the area moves by at most tol x length
    assert abs(got - expected) <= tol * length, (char, got, expected, tol * length)


def test_composites_are_in_the_font():
    """The sample really exercises components (else the test above proves nothing)."""
    from fontTools.ttLib import TTFont

    font = TTFont(FONT)
    cmap, glyf = font.getBestCmap(), font["glyf"]
    for char in "éμǅőǺ":  # (DejaVu's Å and ﬁ are simple glyphs; the sample keeps them as the issue named them)
        assert glyf[cmap[ord(char)]].isComposite(), char


def _dejavu_blocks():
    """One string per Unicode block of the characters DejaVu Sans maps (blocks of 128)."""
    from fontTools.ttLib import TTFont

    cmap = TTFont(FONT).getBestCmap()
    blocks: dict[int, list[str]] = {}
    for code in sorted(cmap):
        if code < 0x20 or 0xD800 <= code < 0xE000:
            continue
        blocks.setdefault(code >> 7, []).append(chr(code))
    return ["".join(v) for v in blocks.values()]


DEJAVU_PARTS = 4  # the blocks dealt into this many tests, so that parallel workers share them


@pytest.mark.slow
@pytest.mark.parametrize("part", range(DEJAVU_PARTS))
def test_every_dejavu_character_imports_or_refuses_in_one_line(part):
    """All 5906 characters DejaVu Sans maps (2437 of them composite), one string per block
    of 128 code points: each block imports, or is refused in one line naming the reason.
    The blocks are dealt into DEJAVU_PARTS tests (block i in part i mod DEJAVU_PARTS), which
    together take every block."""
    done = refused = 0
    blocks = _dejavu_blocks()
    assert sum(map(len, blocks)) > 5800
    mine = blocks[part::DEJAVU_PARTS]
    assert mine
    for string in mine:
        try:
            result = import_text(string, sizes=[11.0])
            assert result.document["polygons"] or string.isspace() or len(string) < 3
            done += 1
        except TextError as exc:
            assert "\n" not in str(exc)
            refused += 1
    assert refused == 0 and done == len(mine), (done, refused)


# --- item 4: stroke joins on true tangents ----------------------------------------------

MITER_PATH = "M1.999 2.399C1.999 2.399 3.726 2.085 4.197 3.497L4.197 0.672"
CUBIC = [(1.999, 2.399), (1.999, 2.399), (3.726, 2.085), (4.197, 3.497)]


def _skia_stroke_area(points, width, miter, cap=skia.Paint.kButt_Cap):
    """Area of Skia's own stroke (miter join) of a polyline, its overlaps resolved by GEOS."""
    path = skia.Path()
    path.moveTo(*points[0])
    for x, y in points[1:]:
        path.lineTo(float(x), float(y))
    paint = skia.Paint(Style=skia.Paint.kStroke_Style, StrokeWidth=width, StrokeJoin=skia.Paint.kMiter_Join,
                       StrokeMiter=miter, StrokeCap=cap)
    out = skia.Path()
    paint.getFillPath(path, out)
    rings, cur = [], []
    it = skia.Path.Iter(out, True)
    while True:
        verb, pts = it.next()
        if verb == skia.Path.kDone_Verb:
            break
        if verb == skia.Path.kMove_Verb:
            if cur:
                rings.append(np.array(cur))
            cur = [(pts[0].x(), pts[0].y())]
        elif verb == skia.Path.kLine_Verb:
            cur.append((pts[1].x(), pts[1].y()))
        elif verb == skia.Path.kClose_Verb:
            rings.append(np.array(cur))
            cur = []
        else:
            raise AssertionError(f"unexpected verb {verb}")
    if cur:
        rings.append(np.array(cur))
    return _geos_fill(rings, "nonzero").area


def _fine_cubic(ctrl, n):
    p = np.array(ctrl, float)
    t = np.linspace(0, 1, n)[:, None]
    return (1 - t) ** 3 * p[0] + 3 * (1 - t) ** 2 * t * p[1] + 3 * (1 - t) * t**2 * p[2] + t**3 * p[3]


def _stroke_svg(tmp_path, d, width, extra=""):
    f = tmp_path / "s.svg"
    f.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" width="8" height="6"><path d="{d}" fill="none" '
                 f'stroke="black" stroke-width="{width}" {extra}/></svg>')
    return f


@pytest.mark.parametrize("tol", [1 / 16, 1 / 64, 1e-3])
def test_miter_beyond_the_limit_on_the_true_tangent_is_a_bevel(tmp_path, tol):
    """True miter ratio 6.24 > 4: SVG draws a bevel. The last chord of the default (1/16 px)
    flattening gives 3.90, which drew a 0.74 px spike (area 2.156 against about 2.002,
    reaching y = 4.24)."""
    t_in = np.array(CUBIC[3]) - np.array(CUBIC[2])
    t_out = np.array([0.0, 0.672 - 3.497])
    turn = math.acos(np.dot(t_in, t_out) / np.linalg.norm(t_in) / np.linalg.norm(t_out))
    assert 1 / math.cos(turn / 2) == pytest.approx(6.24, abs=0.01)
    result = import_svg(_stroke_svg(tmp_path, MITER_PATH, 0.392), tolerance=tol)
    got = _union(result.document).area
    fine = np.vstack([_fine_cubic(CUBIC, 4001), [(4.197, 0.672)]])
    expected = _skia_stroke_area(fine, 0.392, 4.0)  # Skia decides the join on the fine last chord
    length = 2 * (np.hypot(*np.diff(fine, axis=0).T).sum() + 0.392)
    assert abs(got - expected) <= tol * length, (got, expected, tol * length)
    # nothing of the spike: the stroke stays within the bevel's reach of the corner
    assert _union(result.document).bounds[3] <= 3.497 + 0.392 / 2 + 1e-9 + tol


def test_miter_just_under_the_limit_stays_a_miter(tmp_path):
    """A true ratio just under the limit (3.97 < 4): a miter, as Skia draws it on a fine
    flattening, and not the bevel."""
    ratio = 3.97
    turn = 2 * math.acos(1 / ratio)
    ctrl = [(1.0, 3.0), (1.0, 3.0), (2.0, 2.2), (3.0, 2.0)]  # C1 on the start point
    t_end = np.subtract(ctrl[3], ctrl[2]) / np.hypot(*np.subtract(ctrl[3], ctrl[2]))
    c, s = math.cos(turn), math.sin(turn)
    out = np.array([c * t_end[0] - s * t_end[1], s * t_end[0] + c * t_end[1]])
    end = np.array(ctrl[3]) + 1.5 * out
    d = (f"M{ctrl[0][0]} {ctrl[0][1]}C{ctrl[1][0]} {ctrl[1][1]} {ctrl[2][0]} {ctrl[2][1]} {ctrl[3][0]} {ctrl[3][1]}"
         f"L{float(end[0])!r} {float(end[1])!r}")
    result = import_svg(_stroke_svg(tmp_path, d, 0.3), tolerance=1e-3)
    got = _union(result.document).area
    fine = np.vstack([_fine_cubic(ctrl, 4001), [end]])
    miter = _skia_stroke_area(fine, 0.3, 4.0)
    bevel = _skia_stroke_area(fine, 0.3, 3.9)  # under the ratio: Skia bevels
    length = 2 * (np.hypot(*np.diff(fine, axis=0).T).sum() + 0.3)
    assert miter - bevel > 0.02  # the spike is worth telling apart
    assert abs(got - miter) <= 1e-3 * length, (got, miter, bevel)


# --- item 5: fill rules and holes in float64 --------------------------------------------

# non-dyadic coordinates, so float32 rounding would show (a few 1e-7 px)
OUTER_CW = [(1.1, 1.3), (30.7, 1.9), (29.3, 30.1), (2.3, 29.7)]
HOLE_SAME = [(4.1, 4.3), (14.7, 4.9), (13.3, 14.1), (5.3, 13.7)]       # wound like the outer
HOLE_OPPOSITE = [(17.3, 16.1), (17.9, 27.3), (27.1, 26.7), (26.3, 16.9)]  # wound the other way
ISLAND = [(19.7, 19.3), (24.1, 19.9), (23.3, 24.1), (20.3, 23.7)]        # inside the opposite hole
BOWTIE = [(3.3, 17.1), (13.9, 27.7), (13.1, 17.3), (3.7, 28.1)]           # crosses itself
STAR = [(8.0 + 7.3 * math.cos(k * 4 * math.pi / 5 + 0.1), 9.1 + 7.1 * math.sin(k * 4 * math.pi / 5 + 0.1))
        for k in range(5)]


def _d(*rings):
    return " ".join("M" + " L".join(f"{x!r} {y!r}" for x, y in r) + " Z" for r in rings)


def _pixel_coverage(region, width, height):
    cov = np.zeros((height, width))
    for j in range(height):
        for i in range(width):
            cov[j, i] = region.intersection(box(i, j, i + 1, j + 1)).area
    return cov


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
def test_straight_edged_fill_rules_render_within_1e9_of_geos(tmp_path, rule):
    from aaeval.renderers import render

    shapes = [[OUTER_CW, HOLE_SAME, HOLE_OPPOSITE, ISLAND], [BOWTIE], [STAR]]
    svg = tmp_path / "f.svg"
    paths = "".join(f'<path fill-rule="{rule}" fill="#000" d="{_d(*rings)}"/>' for rings in shapes)
    svg.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" width="32" height="32">{paths}</svg>')
    result = import_svg(svg)
    assert result.ignored == []
    scene = parse_scene(result.document)
    # the reference: GEOS on the raw coordinates written above, never the importer's output
    region = shapely.unary_union([_geos_fill([np.array(r) for r in rings], rule) for rings in shapes])
    expected = _pixel_coverage(region, 32, 32)
    got = 1.0 - render(scene, "catmull")[..., 0]
    err = np.abs(got - expected).max()
    assert err <= 1e-9, err
    # straight edges keep their exact coordinates: every input vertex is an output vertex
    out = {tuple(v[:2]) for p in result.document["polygons"] for ring in [p["vertices"], *p.get("holes", [])]
           for v in ring}
    kept = [v for v in OUTER_CW + HOLE_OPPOSITE + ISLAND if v in out]
    assert len(kept) == 12


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(4))
def test_fill_resolver_matches_geos_on_random_crossing_outlines(seed):
    """Random rings crossing each other and themselves (float coordinates, collinear and
    shared vertices from a coarse grid too): the float64 resolver's region equals GEOS's
    faces kept by winding number, to 1e-9 in area."""
    from aaeval.importers.fill import resolve_fill

    rng = np.random.default_rng(seed)
    for trial in range(12):
        if trial % 3 == 0:  # vertices on a coarse grid: shared vertices, collinear overlaps
            rings = [rng.integers(0, 6, (rng.integers(3, 9), 2)).astype(float) * 1.7 for _ in range(rng.integers(1, 4))]
        else:
            rings = [rng.uniform(0, 20, (rng.integers(3, 40), 2)) for _ in range(rng.integers(1, 4))]
        for rule in ("nonzero", "evenodd"):
            expected = _geos_fill(rings, rule)
            regions = resolve_fill(rings, rule)
            got = shapely.unary_union([ShapelyPolygon(o, h) for o, h in regions])
            assert all(ShapelyPolygon(o, h).is_valid or len(h) for o, h in regions)
            assert got.symmetric_difference(expected).area <= 1e-9, (seed, trial, rule)


def _fine_path(d, n=3000):
    """A fine polyline of an SVG path (one subpath) from svgelements' own point evaluation."""
    import svgelements as se

    path = se.Path(d)
    return np.array([(p.x, p.y) for p in (path.point(t) for t in np.linspace(0, 1, n))])


@pytest.mark.slow
@pytest.mark.parametrize("d, width, extra", [
    ("M1 6 C 9 1 1 1 9 6", 1.2, ""),                       # a cusp at t = 1/2 (tangent reverses)
    ("M1 7 C 9 0 1 0 9 7", 0.8, ""),                       # another cusp
    ("M1 6 C 9 0 0 0 9 6", 1.0, ""),                       # a tight loop (no cusp)
    ("M2 5 Q 5 -3 8 5", 3.0, ""),                          # inner offset folds (radius < width/2)
    ("M2 5 A 3 2 0 1 1 8 5", 1.0, 'stroke-linecap="round"'),
    ("M2 5 A 3 2 0 1 1 8 5", 1.0, 'stroke-linecap="square"'),
    ("M1 1 C 1 1 4 1 7 5 S 2 8 5 2", 0.6, ""),             # C1 on the start point, smooth S join
])
def test_curved_strokes_match_geos_sweep_of_a_fine_flattening(tmp_path, d, width, extra):
    """The stroke of a curve is the sweep of the width's normal segment along it (plus a
    round join where a cubic turns back at a cusp): away from the ends that is every point
    within width/2 of the curve, which GEOS's buffer of a 3000-point flattening gives
    (round joins at its tiny turns, flat/round/square caps). Within tol x outline length."""
    tol = 1e-3
    f = tmp_path / "c.svg"
    f.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><path d="{d}" fill="none" '
                 f'stroke="black" stroke-width="{width}" {extra}/></svg>')
    got = _union(import_svg(f, tolerance=tol).document)
    fine = _fine_path(d)
    cap = {'stroke-linecap="round"': "round", 'stroke-linecap="square"': "square"}.get(extra, "flat")
    expected = LineString(fine).buffer(width / 2, quad_segs=256, cap_style=cap, join_style="round")
    length = 2 * np.hypot(*np.diff(fine, axis=0).T).sum() + 4 * width
    assert abs(got.area - expected.area) <= tol * length, (got.area, expected.area, tol * length)
    assert got.symmetric_difference(expected).area <= 2 * tol * length


# --- the fill rules' candidate pairs: every overlapping pair of edge boxes, small or large --

@pytest.mark.parametrize("n", [2, 17, 64, 65, 300])
@pytest.mark.parametrize("with_active", [False, True])
def test_candidate_pairs_are_the_overlapping_pairs_checked_one_by_one(n, with_active):
    # both ways: every pair checked at once (up to ALL_PAIRS_EDGES boxes) and the grid (above)
    from aaeval.importers.fillpairs import ALL_PAIRS_EDGES, candidate_pairs

    assert 2 <= ALL_PAIRS_EDGES < 300
    rng = np.random.default_rng(n)
    lo = np.round(rng.random((n, 2)) * 20.0, 1)  # on a 0.1 grid: boxes that touch and share edges
    hi = lo + np.round(rng.random((n, 2)) * rng.choice([0.0, 0.5, 4.0], (n, 1)), 1)
    lo[0], hi[0] = (0.0, 0.0), (25.0, 25.0)  # a box over all the others: pairs whatever the draw
    eps = 1e-9
    active = (rng.random(n) < 0.3) | (np.arange(n) == n - 1) if with_active else None
    expected = [(a, b) for a in range(n) for b in range(a + 1, n)
                if all(lo[a, k] <= hi[b, k] + eps and lo[b, k] <= hi[a, k] + eps for k in (0, 1))
                and (active is None or active[a] or active[b])]
    i, j = candidate_pairs(lo, hi, eps, active)
    assert i.dtype == j.dtype == np.int64
    assert list(zip(i.tolist(), j.tolist())) == expected
    assert expected  # the boxes do overlap somewhere
