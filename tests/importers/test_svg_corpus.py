"""SVG files imported as their authors drew them: a corpus of cases, one file per class
(colours, CSS, structure, units, paths, markers and paint order, strokes under any
transform), each checked against an independent renderer or an expected file built by
hand from the specification's rules.

- resvg (its own parser, cascade, markers and nested viewports) renders the same file;
  aaeval's exact image is taken with ``blend=srgb`` (coverage averaged in sRGB, as resvg
  blends), so the two differ only at edges, where resvg supersamples (up to 1/8 px of an
  edge: a quarter of the 8-bit range at most, never a shape's interior).
- Where resvg does not follow SVG 2 / CSS Values 4 (geometry properties in CSS; ``Q``
  and ``vw`` lengths), the expected file states the same drawing in plain px, its numbers computed here from the units' definitions (1 in = 96 px =
  2.54 cm, 1 Q = 1/40 cm, 1 pt = 1/72 in, 1 pc = 12 pt; 1 em = 16 px unless set, 1 ex =
  1/2 em).
- A stroke under a skew is the affine image of the stroke GEOS builds in user space.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString
from shapely.geometry import Polygon as ShapelyPolygon

from aaeval.fileio import linear_to_srgb, linear_to_srgb8, srgb_to_linear
from aaeval.importers.svg import import_svg
from aaeval.renderers import render
from aaeval.scenes import parse_scene

CORPUS = Path(__file__).parents[1] / "data" / "svg" / "corpus"
NS = "http://www.w3.org/2000/svg"
RESVG_CASES = ["colours", "css", "structure", "nested", "paths", "markers", "strokes", "clip", "dashes",
               "transform_origin", "clip_children"]


def imported(tmp_path, name: str, text: str | None = None):
    """(result, scene) of a corpus file (or of ``text``) imported next to its scene."""
    target = tmp_path / f"{name}.svg"
    if text is None:
        shutil.copy(CORPUS / f"{name}.svg", target)
    else:
        target.write_text(text)
    result = import_svg(target, file_ref=target.name)
    return result, parse_scene(result.document, source=str(tmp_path / f"{name}.toml"))


@pytest.mark.parametrize("name", RESVG_CASES)
def test_corpus_matches_resvg_in_srgb_blending(tmp_path, name):
    result, scene = imported(tmp_path, name)
    assert result.ignored == []  # resvg refuses scenes that left something out
    ours = linear_to_srgb8(render(scene, "catmull:blend=srgb")).astype(int)
    theirs = linear_to_srgb8(render(scene, "resvg")).astype(int)
    diff = np.abs(ours - theirs)
    # edges only: resvg's supersampling moves an edge by up to 1/8 px
    assert diff.max() <= 64, (name, np.argwhere(diff > 64)[:5].tolist())
    assert diff.mean() <= 1.5, (name, diff.mean())
    # and in linear light (the default) the same file differs only by blending space at edges
    linear = linear_to_srgb8(render(scene, "catmull")).astype(int)
    interior = (ours == linear).all(axis=2)
    assert interior.mean() > 0.5


def test_ink_is_where_the_files_say(tmp_path):
    """The corpus draws no red (every 'wrong' reading of a case paints red), and every
    case that should draw something does."""
    for name in RESVG_CASES:
        _, scene = imported(tmp_path, name)
        for p in scene.polygons:
            assert not (p.color[0] > 0.5 and p.color[1] < 0.1 and p.color[2] < 0.1), (name, p.color)
    result, _ = imported(tmp_path, "colours")
    colours = {tuple(np.round(linear_to_srgb(layer["color"]) * 255).astype(int))
               for layer in result.document["polygons"]}
    assert colours == {(0, 128, 0), (0, 0, 255), (0, 128, 255), (128, 0, 128), (0, 0, 128)}  # inherit: the group's blue


def px(value: float) -> str:
    return repr(float(value))


def test_an_invalid_declaration_leaves_the_one_before_it(tmp_path):
    """CSS drops a declaration that does not parse, so the one before it applies (resvg
    keeps the broken one and paints black)."""
    text = ('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"><style>rect { fill: navy }</style>'
            '<rect width="4" height="4" fill="red" style="fill: green; fill: invalid-colour"/>'
            '<rect width="2" height="2" fill="not-a-colour" style="stroke: 12"/></svg>')
    result, _ = imported(tmp_path, "invalid", text)
    colours = [np.round(linear_to_srgb(p["color"]) * 255).astype(int).tolist() for p in result.document["polygons"]]
    assert colours == [[0, 128, 0], [0, 0, 128]]


def test_units_match_the_same_drawing_in_px(tmp_path):
    inch = 96.0
    em, ex = 16.0, 8.0
    width, height = 3 * em, 2.25 * em
    diagonal = math.sqrt((width ** 2 + height ** 2) / 2)
    expected = f"""<svg xmlns="http://www.w3.org/2000/svg" width="{px(width)}" height="{px(height)}">
  <rect x="1" y="1" width="{px(10 * inch / 2.54 / 40)}" height="10" fill="green"/>
  <rect x="13" y="1" width="{px(0.125 * width)}" height="10" fill="green"/>
  <rect x="25" y="1" width="{px(0.625 * em)}" height="{px(1.25 * ex)}" fill="green"/>
  <circle cx="6" cy="18" r="5" fill="green"/>
  <circle cx="18" cy="18" r="3" fill="green"/>
  <rect x="25" y="13" width="10" height="10" rx="{px(0.1 * width)}" ry="{px(0.1 * width)}" fill="green"/>
  <rect x="37" y="13" width="10" height="10" rx="2" ry="2" fill="green"/>
  <rect x="1" y="25" width="10" height="8" fill="none" stroke="green" stroke-width="{px(0.05 * diagonal)}"/>
  <circle cx="20" cy="30" r="4" fill="green" stroke="navy" stroke-width="{px(0.0625 * inch)}"/>
  <rect x="28" y="26" width="{px(6 * inch / 72)}" height="{px(6 * 12 * inch / 72)}" fill="green"/>
</svg>"""
    result, scene = imported(tmp_path, "units")
    assert result.ignored == []
    _, reference = imported(tmp_path, "units_px", expected)
    assert (scene.width, scene.height) == (48, 36)
    np.testing.assert_allclose(render(scene, "catmull"), render(reference, "catmull"), atol=1e-12)


def test_geometry_set_through_css_matches_attributes(tmp_path):
    expected = """<svg xmlns="http://www.w3.org/2000/svg" width="32" height="16">
  <rect x="2" y="2" width="10" height="6" fill="green"/>
  <rect x="2" y="10" width="12" height="4" fill="green"/>
  <circle cx="24" cy="8" r="4" fill="navy"/>
</svg>"""
    _, scene = imported(tmp_path, "css_geometry")
    _, reference = imported(tmp_path, "css_geometry_px", expected)
    np.testing.assert_allclose(render(scene, "catmull"), render(reference, "catmull"), atol=1e-12)


@pytest.mark.parametrize("origin, point", [
    ("center", (40.0, 25.0)), ("right bottom", (80.0, 50.0)), ("bottom left", (0.0, 50.0)), ("top", (40.0, 0.0)),
    ("25% 60%", (20.0, 30.0)), ("12px", (12.0, 25.0)), ("left 1em", (0.0, 16.0)), ("center 10px", (40.0, 10.0)),
    ("0.5in 3 0", (48.0, 3.0)), ("left right", (0.0, 0.0)), ("10px left", (0.0, 0.0)), ("nonsense", (0.0, 0.0)),
])
def test_transform_origin_is_the_transform_conjugated_by_the_origin(tmp_path, origin, point):
    """CSS Transforms 1: the map is translate(origin) transform translate(-origin), with
    keywords and percentages of the viewport (here the viewBox, 80 x 50 user units); a value
    that does not parse is the initial 0 0. Set as an attribute and through CSS."""
    ox, oy = point
    body = '<rect x="30" y="15" width="20" height="20" fill="navy" transform="rotate(30) scale(1.5 0.75)" {}/>'
    svg = f'<svg xmlns="{NS}" width="160" height="100" viewBox="0 0 80 50">{{}}</svg>'
    expected = svg.format(f'<rect x="30" y="15" width="20" height="20" fill="navy" transform="translate({ox} {oy}) '
                          f'rotate(30) scale(1.5 0.75) translate({-ox} {-oy})"/>')
    _, reference = imported(tmp_path, "origin_expected", expected)
    for how in (f'transform-origin="{origin}"', f'style="transform-origin: {origin}"'):
        result, scene = imported(tmp_path, "origin", svg.format(body.format(how)))
        assert result.ignored == []
        np.testing.assert_allclose(render(scene, "catmull"), render(reference, "catmull"), atol=1e-12)


def test_transform_origin_on_a_clip_path_and_in_a_nested_viewport(tmp_path):
    """The reference box is the nearest viewport, sized as its viewBox: 'center' of a nested
    <svg viewBox="0 0 20 10"> is (10, 5) in its user space; on a clipPath it turns the clip."""
    nested = (f'<svg xmlns="{NS}" width="40" height="20"><svg x="4" y="2" width="32" height="16" viewBox="0 0 20 10">'
              '<rect x="5" y="2" width="10" height="6" fill="green" transform="rotate(90)" {}/></svg></svg>')
    _, scene = imported(tmp_path, "nested_origin", nested.format('transform-origin="center"'))
    _, reference = imported(tmp_path, "nested_expected", nested.format('').replace(
        'transform="rotate(90)"', 'transform="translate(10 5) rotate(90) translate(-10 -5)"'))
    np.testing.assert_allclose(render(scene, "catmull"), render(reference, "catmull"), atol=1e-12)
    clipped = (f'<svg xmlns="{NS}" width="40" height="40"><clipPath id="c" transform="rotate(45)" {{}}>'
               '<rect x="10" y="10" width="20" height="20"/></clipPath>'
               '<rect width="40" height="40" fill="navy" clip-path="url(#c)"/></svg>')
    _, scene = imported(tmp_path, "clip_origin", clipped.format('transform-origin="20 20"'))
    _, reference = imported(tmp_path, "clip_expected", clipped.format('').replace(
        'transform="rotate(45)"', 'transform="translate(20 20) rotate(45) translate(-20 -20)"'))
    np.testing.assert_allclose(render(scene, "catmull"), render(reference, "catmull"), atol=1e-12)
    assert render(scene, "catmull").tobytes() != render(imported(tmp_path, "clip_plain", clipped.format(''))[1],
                                                        "catmull").tobytes()


def test_a_clip_path_child_clipped_by_its_own_clip_path_keeps_the_intersection(tmp_path):
    """A clipPath child with a clip-path of its own contributes only the part inside it:
    the same region as the two clip paths nested on a group and its shape (GEOS
    intersection of the imported outlines). A cycle of such references is listed."""
    nested = (f'<svg xmlns="{NS}" width="30" height="30"><clipPath id="disc"><circle cx="15" cy="15" r="11"/>'
              '</clipPath><clipPath id="star"><path d="M 15 2 L 23 27 L 2 11 L 28 11 L 7 27 Z" {}/></clipPath>'
              '<g {}><rect width="30" height="30" fill="green" {}/></g></svg>')
    result, _ = imported(tmp_path, "child_clip", nested.format('clip-path="url(#disc)"', '',
                                                               'clip-path="url(#star)"'))
    expected, _ = imported(tmp_path, "group_clip", nested.format('', 'clip-path="url(#star)"',
                                                                 'clip-path="url(#disc)"'))
    assert result.ignored == [] and expected.ignored == []

    def union(document):
        return shapely.unary_union([ShapelyPolygon([v[:2] for v in p["vertices"]],
                                                   [[v[:2] for v in h] for h in p.get("holes", [])])
                                    for p in document["polygons"]])

    got, want = union(result.document), union(expected.document)
    assert want.area > 100 and got.symmetric_difference(want).area < 1e-9
    # a clip path on the clipPath itself cuts the union of its children
    own_clip = nested.replace('<clipPath id="star">', '<clipPath id="star" clip-path="url(#disc)">')
    result, _ = imported(tmp_path, "own_clip", own_clip.format('', '', 'clip-path="url(#star)"'))
    assert result.ignored == [] and union(result.document).symmetric_difference(want).area < 1e-9
    # in the child's user space, its transform included: the lower half of its own box, turned
    turned = (f'<svg xmlns="{NS}" width="30" height="30"><clipPath id="half" clipPathUnits="objectBoundingBox">'
              '<rect y="0.5" width="1" height="0.5"/></clipPath><clipPath id="c"><rect x="-10" y="-4" width="8" '
              'height="20" transform="translate(20 8) rotate(15)" clip-path="url(#half)"/></clipPath>'
              '<rect width="30" height="30" fill="navy" clip-path="url(#c)"/></svg>')
    result, _ = imported(tmp_path, "turned", turned)
    half = shapely.affinity.translate(shapely.affinity.rotate(shapely.box(-10, 6, -2, 16), 15, origin=(0, 0)), 20, 8)
    assert union(result.document).symmetric_difference(half).area < 1e-9
    cycle = (f'<svg xmlns="{NS}" width="30" height="30"><clipPath id="a"><rect width="20" height="20" '
             'clip-path="url(#b)"/></clipPath><clipPath id="b"><rect x="5" y="5" width="20" height="20" '
             'clip-path="url(#a)"/></clipPath><rect width="30" height="30" fill="green" clip-path="url(#a)"/></svg>')
    result, _ = imported(tmp_path, "cycle", cycle)
    assert any("#a" in item and "cycle" in item for item in result.ignored), result.ignored


def test_dashes_ending_on_a_segment_end_are_stroked(tmp_path):
    """pathLength 100 and dashes of 25 on a circle put every dash end on the end of a
    quarter arc, where rounding leaves a sliver of the next arc: the dashes are the two
    quarter arcs as paths of their own (the sliver once sent the stroker to its vertex limit)."""
    dashed = (f'<svg xmlns="{NS}" width="40" height="40"><circle cx="20" cy="20" r="14" fill="none" stroke="navy" '
              'stroke-width="4" stroke-dasharray="25" pathLength="100"/></svg>')
    quarters = (f'<svg xmlns="{NS}" width="40" height="40"><path d="M 34 20 A 14 14 0 0 1 20 34 M 6 20 A 14 14 0 0 1 '
                '20 6" fill="none" stroke="navy" stroke-width="4"/></svg>')
    result, scene = imported(tmp_path, "dashed", dashed)
    _, reference = imported(tmp_path, "quarters", quarters)
    assert result.ignored == []
    np.testing.assert_allclose(render(scene, "catmull"), render(reference, "catmull"), atol=1e-9)
    sliver = (f'<svg xmlns="{NS}" width="20" height="20"><path d="M 4 10 L 10 10 A 6 6 0 0 1 10.000000000000002 10" '
              'fill="none" stroke="navy" stroke-width="2"/></svg>')
    result, _ = imported(tmp_path, "sliver", sliver)
    (polygon,) = result.document["polygons"]
    assert sorted({tuple(v[:2]) for v in polygon["vertices"]}) == [(4, 9), (4, 11), (10, 9), (10, 11)]


@pytest.mark.parametrize("transform", ["skewX(30)", "scale(3 1)", "matrix(1 0.3 -0.2 0.5 0 0)"])
def test_strokes_are_outlined_in_user_space_then_transformed(tmp_path, transform):
    """GEOS buffers the polyline in user space; the affine image of that buffer is the
    stroke (a width of the square root of the determinant after the transform is not)."""
    points = [(2.0, 2.0), (10.0, 3.0), (6.0, 12.0)]
    d = "M " + " L ".join(f"{x} {y}" for x, y in points)
    text = (f'<svg xmlns="http://www.w3.org/2000/svg" width="48" height="24"><g transform="translate(12 4) '
            f'{transform}"><path d="{d}" fill="none" stroke="black" stroke-width="3" stroke-linejoin="bevel"/></g>'
            '</svg>')
    result, _ = imported(tmp_path, "skew", text)
    got = shapely.unary_union([ShapelyPolygon([v[:2] for v in p["vertices"]], [[v[:2] for v in h]
                                                                             for h in p.get("holes", [])])
                               for p in result.document["polygons"]])
    from aaeval.importers.svgpath import compose, parse_transform

    a, b, c, dd, e, f = compose(parse_transform("translate(12 4)"), parse_transform(transform))
    want = shapely.affinity.affine_transform(LineString(points).buffer(1.5, cap_style="flat", join_style="bevel"),
                                             [a, c, b, dd, e, f])
    assert got.symmetric_difference(want).area < 1e-9
    assert got.area == pytest.approx(want.area, rel=1e-12)


def test_srgb_blending_is_the_srgb_average_of_the_exact_coverage():
    """Half a pixel of red over blue: linear light averages the linear colours; blend=srgb
    averages their sRGB encodings (and decodes), as browsers do."""
    red, blue = np.array([1.0, 0.0, 0.0]), srgb_to_linear([0.2, 0.4, 0.9])
    scene = parse_scene({"image": {"width": 2, "height": 1, "background": blue.tolist()},
                         "polygons": [{"color": red.tolist(), "vertices": [[0, 0, 1], [1.5, 0, 1], [1.5, 1, 1],
                                                                           [0, 1, 1]]}]})
    for method in ("catmull", "weiler-atherton"):
        linear = render(scene, method)
        srgb = render(scene, f"{method}:blend=srgb")
        np.testing.assert_allclose(linear[0, 1], 0.5 * red + 0.5 * blue, atol=1e-12)
        np.testing.assert_allclose(srgb[0, 1], srgb_to_linear(0.5 * linear_to_srgb(red) + 0.5 * linear_to_srgb(blue)),
                                   atol=1e-12)
        np.testing.assert_allclose(srgb[0, 0], red, atol=1e-12)  # a covered pixel is its colour either way
        assert render(scene, f"{method}:blend=linear").tobytes() == linear.tobytes()


@pytest.mark.parametrize("body, words", [
    ('<rect width="2lh" height="4" fill="green"/>', ["rect[0]", "'lh'", "not resolved"]),
    ('<style>@media (min-width: 5px) { rect { fill: red } }</style><rect width="4" height="4"/>',
     ["@media", "not applied"]),
    ('<style>@import url(other.css);</style><rect width="4" height="4"/>', ["@import", "not applied"]),
    ('<style>rect { transform: rotate(45deg) }</style><rect width="4" height="4"/>', ["rect[0]", "transform"]),
    ('<style>svg|rect { fill: red }</style><rect width="4" height="4"/>', ["selector", "not applied"]),
    ('<rect width="4" height="4" fill="red" style="mix-blend-mode: multiply"/>', ["rect[0]", "mix-blend-mode"]),
])
def test_what_cannot_be_applied_is_listed_by_name(tmp_path, body, words):
    result, _ = imported(tmp_path, "listed", f'<svg xmlns="{NS}" width="8" height="8">{body}</svg>')
    assert any(all(w in item for w in words) for item in result.ignored), result.ignored


# sRGB red written in each CSS Color 4 space, as the specification and oklch.com publish it
# (rounded to the digits shown), and white and a mid grey by construction
CSS_COLOUR_4 = [("lab(54.29% 80.82 69.9)", (1, 0, 0)), ("lch(54.29% 106.84 40.85)", (1, 0, 0)),
                ("oklch(62.8% 0.2577 29.23)", (1, 0, 0)), ("color(display-p3 0.9175 0.2003 0.1387)", (1, 0, 0)),
                ("color(rec2020 0.7919 0.2310 0.0738)", (1, 0, 0)), ("color(a98-rgb 0.8587 0 0)", (1, 0, 0)),
                ("color(prophoto-rgb 0.7022 0.2757 0.1036)", (1, 0, 0)), ("lab(100% 0 0)", (1, 1, 1)),
                ("oklab(1 0 0)", (1, 1, 1)), ("color(xyz-d50 0.9642 1 0.8249)", (1, 1, 1)),
                ("color(xyz 0.9505 1 1.089)", (1, 1, 1)), ("color(srgb-linear 0.214 0.214 0.214)", (0.5, 0.5, 0.5))]


@pytest.mark.parametrize("css, srgb", CSS_COLOUR_4, ids=[c for c, _ in CSS_COLOUR_4])
def test_css_colour_4_spaces_import_as_their_srgb_colour(tmp_path, css, srgb):
    result, _ = imported(tmp_path, "colour4", f'<svg xmlns="{NS}" width="4" height="4">'
                                              f'<rect width="4" height="4" fill="{css}"/></svg>')
    assert result.ignored == []
    (layer,) = [p for p in result.document["polygons"]]
    np.testing.assert_allclose(linear_to_srgb(np.array(layer["color"])), srgb, atol=2e-3)


def test_a_bad_segment_draws_what_comes_before_it(tmp_path):
    text = ('<svg xmlns="http://www.w3.org/2000/svg" width="20" height="10">'
            '<path d="M 1 1 L 9 1 L 9 9 L 1 9 Z M 11 1 L 19 1 L 19 # 9 Z" fill="black"/></svg>')
    result, _ = imported(tmp_path, "bad", text)
    assert result.ignored == []
    (polygon,) = result.document["polygons"]
    assert sorted(map(tuple, np.array(polygon["vertices"])[:, :2].tolist())) == [(1, 1), (1, 9), (9, 1), (9, 9)]


@pytest.mark.parametrize("seed", range(4))
def test_viewport_clip_is_the_intersection_geos_gives(seed):
    """clip_regions (the clip of nested viewports and markers) against GEOS's intersection:
    self-crossing outlines resolved under both rules, clipped by a rotated rectangle."""
    from aaeval.importers.shapes import Region, Subpath, clip_regions, fill_regions

    rng = np.random.default_rng(seed)
    outline = rng.uniform(0, 20, (12, 2))
    angle = rng.uniform(0, math.pi)
    c, s = math.cos(angle), math.sin(angle)
    box = np.array([[-6, -4], [6, -4], [6, 4], [-6, 4]]) @ np.array([[c, s], [-s, c]]) + 10
    for rule in ("nonzero", "evenodd"):
        regions = fill_regions([Subpath(outline, True)], rule)
        geos = shapely.unary_union([ShapelyPolygon(r.outer, r.holes) for r in regions])
        got = shapely.unary_union([ShapelyPolygon(r.outer, r.holes) for r in clip_regions(regions, [Region(box, [])])])
        want = geos.intersection(ShapelyPolygon(box))
        assert got.symmetric_difference(want).area < 1e-9 * max(want.area, 1)
        assert got.area == pytest.approx(want.area, rel=1e-12)


@pytest.mark.parametrize("body, polygons", [
    ('<svg viewBox="0 0 0 10"><rect width="5" height="5"/></svg>', 0),  # a viewBox of no width disables
    ('<marker id="m" markerWidth="0"><rect width="4" height="4"/></marker>'
     '<path d="M 1 1 L 5 5" stroke="black" marker-start="url(#m)"/>', 1),  # a marker of no size draws nothing
    ('<marker id="m" overflow="visible"><path d="M 0 0 L 1 1" stroke="black" marker-end="url(#m)"/></marker>'
     '<path d="M 1 1 L 5 5" stroke="black" marker-end="url(#m)"/>', 2),  # a marker inside itself is not drawn
    ('<rect width="5" height="5" fill="url(#nothing"/>', 0),
    ('<rect width="5" height="5" fill="rgb(1, 2)"/>', 1),  # invalid: the initial black
    ('<style>@media print { rect { fill: red } } @media screen, print { circle { fill: none } }'
     '@font-face { font-family: x }</style><rect width="4" height="4"/><circle r="2"/>', 1),
])
def test_error_cases_draw_what_svg_says(tmp_path, body, polygons):
    result, _ = imported(tmp_path, "errors", f'<svg xmlns="{NS}" width="10" height="10">{body}</svg>')
    assert len(result.document["polygons"]) == polygons and result.ignored == []


def test_media_types_apply_as_on_a_screen(tmp_path):
    text = ('<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"><style>@media print { rect { fill: red } }'
            '@media only screen, print { rect { stroke: green } } @media not print { rect { fill: navy } }</style>'
            '<rect width="4" height="4"/></svg>')
    result, _ = imported(tmp_path, "media", text)
    colours = [np.round(linear_to_srgb(p["color"]) * 255).astype(int).tolist() for p in result.document["polygons"]]
    assert colours[0] == [0, 0, 128] and [0, 128, 0] in colours and result.ignored == []


def test_what_the_root_asks_is_applied_or_listed(tmp_path):
    body = '<rect width="4" height="4"/>'
    for attrs, polygons, listed in [('opacity="0"', 0, []), ('display="none"', 0, []),
                                    ('opacity="0.5"', 1, ["<svg>: opacity 0.5"]),
                                    ('filter="url(#f)"', 1, ["<svg>: filter"]),
                                    ('transform="rotate(3)"', 1, ["<svg>: transform"])]:
        result, _ = imported(tmp_path, "root", f'<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4" {attrs}>'
                                               f'{body}</svg>')
        assert len(result.document["polygons"]) == polygons
        assert all(any(w in item for item in result.ignored) for w in listed) and bool(listed) == bool(result.ignored)


@pytest.mark.parametrize("attrs, size", [('width="40" viewBox="0 0 20 10"', (40, 20)),
                                         ('height="30" viewBox="0 0 20 10"', (60, 30)),
                                         ('width="50%" height="3em" viewBox="0 0 20 10"', (10, 48)),
                                         ('viewBox="0 0 20 10"', (20, 10)), ('width="44mmx" height="7"', (100, 7))])
def test_the_root_size_follows_its_viewbox_where_a_side_is_missing(tmp_path, attrs, size):
    _, scene = imported(tmp_path, "size", f'<svg xmlns="{NS}" {attrs}><rect width="4" height="4"/></svg>')
    assert (scene.width, scene.height) == size


def test_clip_path_is_the_intersection_geos_gives(tmp_path):
    """A rotated square clipped by an even-odd frame: the clip path is in the square's own
    user space (its transform included), so the result is GEOS's intersection of the
    user-space shapes, rotated."""
    text = ('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="40"><clipPath id="c">'
            '<path d="M 0 0 H 40 V 40 H 0 Z M 10 10 H 30 V 30 H 10 Z" clip-rule="evenodd"/></clipPath>'
            '<rect x="4" y="4" width="32" height="32" transform="rotate(20 20 20)" clip-path="url(#c)"/></svg>')
    result, _ = imported(tmp_path, "clipped", text)
    got = shapely.unary_union([ShapelyPolygon([v[:2] for v in p["vertices"]], [[v[:2] for v in h]
                                                                             for h in p.get("holes", [])])
                               for p in result.document["polygons"]])
    square = ShapelyPolygon([(4, 4), (36, 4), (36, 36), (4, 36)])
    frame = ShapelyPolygon([(0, 0), (40, 0), (40, 40), (0, 40)], [[(10, 10), (30, 10), (30, 30), (10, 30)]])
    want = shapely.affinity.rotate(square.intersection(frame), 20, origin=(20, 20))
    assert got.symmetric_difference(want).area < 1e-9
    assert got.area == pytest.approx(want.area, rel=1e-12)


def dashed_by_geos(points, pattern, offset, width):
    """GEOS's dashes of a polyline (substrings laid from the offset), buffered with flat caps."""
    from shapely.ops import substring

    line = LineString(points)
    pieces, s, k = [], -offset, 0
    while s < line.length:
        e = s + pattern[k % len(pattern)]
        if k % 2 == 0 and e > 0:
            pieces.append(substring(line, max(s, 0.0), min(e, line.length)).buffer(width / 2, cap_style="flat",
                                                                                     join_style="mitre"))
        s, k = e, k + 1
    return shapely.unary_union(pieces)


def test_dashes_are_the_substrings_geos_cuts(tmp_path):
    points = [(3.0, 4.0), (20.0, 4.0), (26.0, 16.0), (8.0, 20.0)]
    text = ('<svg xmlns="http://www.w3.org/2000/svg" width="32" height="24"><polyline points="'
            + " ".join(f"{x} {y}" for x, y in points) + '" fill="none" stroke="black" stroke-width="2" '
            'stroke-dasharray="7 2.5" stroke-dashoffset="3" stroke-miterlimit="10"/></svg>')
    result, _ = imported(tmp_path, "dashed", text)
    got = shapely.unary_union([ShapelyPolygon([v[:2] for v in p["vertices"]], [[v[:2] for v in h]
                                                                             for h in p.get("holes", [])])
                               for p in result.document["polygons"]])
    want = dashed_by_geos(points, [7.0, 2.5], 3.0, 2.0)
    assert got.symmetric_difference(want).area < 1e-9
    assert got.area == pytest.approx(want.area, rel=1e-12)


@pytest.mark.parametrize("dashed, plain", [
    ('stroke-dasharray="6 3" pathLength="20"', 'stroke-dasharray="12 6"'),  # 40 px drawn as 20 units
    ('stroke-dasharray="4 -1"', ""),  # a negative value: solid
    ('stroke-dasharray="0 0"', ""),  # a pattern of no length: solid
    ('stroke-dasharray="3" stroke-dashoffset="-3"', 'stroke-dasharray="3 3" stroke-dashoffset="3"'),
])
def test_dash_patterns_as_svg_defines_them(tmp_path, dashed, plain):
    line = f'<svg xmlns="{NS}" width="48" height="8">' + '<path d="M 4 4 H 44" stroke="black" {}/></svg>'
    _, scene = imported(tmp_path, "dashed", line.format(dashed))
    _, reference = imported(tmp_path, "plain", line.format(plain))
    np.testing.assert_allclose(render(scene, "catmull"), render(reference, "catmull"), atol=1e-12)


def test_deeply_nested_groups_import(tmp_path):
    depth = 3000  # deeper than Python's default recursion limit
    text = f'<svg xmlns="{NS}" width="8" height="8">' + "<g>" * depth + '<rect width="4" height="4"/>' + "</g>" * depth
    result, _ = imported(tmp_path, "deep", text + "</svg>")
    assert len(result.document["polygons"]) == 1


def test_a_dash_over_the_start_of_a_closed_subpath_is_one_dash(tmp_path):
    """On a closed square of perimeter 40 with dashes of 7 every 10, the last dash (30 to
    37) would end at 37; with an offset of 5 the first runs from 0 to 2 and the last from 35
    to 40: they are one dash turning the corner at the start, mitred there, as GEOS buffers
    the joined polyline."""
    text = (f'<svg xmlns="{NS}" width="20" height="20"><path d="M 5 5 H 15 V 15 H 5 Z" fill="none" stroke="black" '
            'stroke-width="2" stroke-dasharray="7 3" stroke-dashoffset="5"/></svg>')
    result, _ = imported(tmp_path, "closed", text)
    got = shapely.unary_union([ShapelyPolygon([v[:2] for v in p["vertices"]], [[v[:2] for v in h]
                                                                             for h in p.get("holes", [])])
                               for p in result.document["polygons"]])
    square = [(5, 5), (15, 5), (15, 15), (5, 15), (5, 5)]
    from shapely.ops import substring

    ring = LineString(square)
    joined = LineString(list(substring(ring, 35, 40).coords) + list(substring(ring, 0, 2).coords)[1:])
    pieces = [joined, substring(ring, 5, 12), substring(ring, 15, 22), substring(ring, 25, 32)]
    want = shapely.unary_union([p.buffer(1, cap_style="flat", join_style="mitre") for p in pieces])
    assert got.symmetric_difference(want).area < 1e-9


def test_absolute_units_match_resvg(tmp_path):
    """in, cm, mm, pt, pc as resvg resolves them at CSS's 96 px per inch."""
    text = (f'<svg xmlns="{NS}" width="48" height="36"><rect x="1" y="1" width="0.5in" height="1cm" fill="green"/>'
            '<rect x="1" y="16" width="30pt" height="1.5pc" fill="navy"/><circle cx="36" cy="18" r="25.4mm" '
            'fill="none" stroke="black" stroke-width="1.5pt"/></svg>')
    result, scene = imported(tmp_path, "absolute", text)
    assert result.ignored == []
    diff = np.abs(linear_to_srgb8(render(scene, "catmull:blend=srgb")).astype(int)
                  - linear_to_srgb8(render(scene, "resvg")).astype(int))
    assert diff.max() <= 64 and diff.mean() <= 1.5


def test_segments_of_no_length_give_markers_no_direction(tmp_path):
    """A repeated point is a vertex of its own, oriented as if the empty segment were not
    there (SVG WG): its marker lies exactly on the one at the same point."""
    marker = (f'<svg xmlns="{NS}" width="48" height="36"><marker id="m" markerWidth="6" markerHeight="6" refX="3" '
              'refY="3" orient="auto" markerUnits="userSpaceOnUse"><path d="M0 0 L6 3 L0 6 Z" fill="navy"/></marker>'
              '<path d="{}" fill="none" stroke="black" marker-start="url(#m)" marker-mid="url(#m)" '
              'marker-end="url(#m)"/></svg>')
    _, doubled = imported(tmp_path, "doubled", marker.replace("{}", "M 5 30 L 20 10 L 20 10 L 40 20 L 40 20"))
    _, single = imported(tmp_path, "single", marker.replace("{}", "M 5 30 L 20 10 L 40 20"))
    np.testing.assert_allclose(render(doubled, "catmull"), render(single, "catmull"), atol=1e-12)
