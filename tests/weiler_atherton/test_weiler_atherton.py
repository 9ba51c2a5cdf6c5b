"""Weiler-Atherton clipper, hidden-surface removal and its uses, against independent
oracles: GEOS (shapely, tests only) for clipping, the Catmull scanline renderer for the
images, and area conservation."""

from __future__ import annotations

import glob
import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon as GeosPolygon

from aaeval.cli import main as cli_main
from aaeval.renderers import render
from aaeval.scenes import load_scene, parse_scene
from aaeval.scenes.generate import random_triangles
from aaeval.weiler_atherton import (
    InvalidShapeError,
    Shape,
    clip,
    coverage,
    oriented,
    polygons,
    ring_area,
    shape_area,
    visible_pieces,
)
from aaeval.native.weiler_atherton import INSIDE, OUTSIDE, clip_arrays, first_crossing
from aaeval.native.weiler_atherton_testing import separation as _separation
from aaeval.weiler_atherton.clipper import from_arrays, to_arrays
from aaeval.weiler_atherton.lines import visible_edges
from tests.helpers.randomscenes import degenerate_scene, random_scene

DATA = Path(__file__).parents[1] / "data"
SCENES = sorted(glob.glob(str(Path(__file__).parents[2] / "configs" / "scenes" / "*.toml")))
FAST = settings(max_examples=250, deadline=None, suppress_health_check=list(HealthCheck))


def geos(shape):
    """The shape as a GEOS geometry (weakly simple contours made valid)."""
    pos = [shapely.make_valid(GeosPolygon(r)) for r in shape.rings if ring_area(r) > 0]
    neg = [shapely.make_valid(GeosPolygon(r)) for r in shape.rings if ring_area(r) < 0]
    return shapely.difference(shapely.union_all(pos), shapely.union_all(neg))


def _orientation(p, q, r) -> int:
    """The sign of the turn p -> q -> r (exact: grid points are integers)."""
    d = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    return (d > 0) - (d < 0)


def _cross_properly(a, b, c, d) -> bool:
    """Whether segments ab and cd cross at one point inside both."""
    return (_orientation(a, b, c) * _orientation(a, b, d) < 0
            and _orientation(c, d, a) * _orientation(c, d, b) < 0)


def untangled(pts: list) -> list:
    """The same vertices, reordered by 2-opt moves until no two edges cross properly.

    Each move reverses the run between two crossing edges, which shortens the outline, so
    the loop ends; an outline that had no crossing comes back unchanged. Touching and
    collinear contacts are left as they are (the caller's validity check judges them).
    """
    pts = list(pts)
    n = len(pts)
    moved = True
    while moved:
        moved = False
        for i in range(n - 2):
            for j in range(i + 2, n - (i == 0)):
                if _cross_properly(pts[i], pts[i + 1], pts[j], pts[(j + 1) % n]):
                    pts[i + 1:j + 1] = pts[i + 1:j + 1][::-1]
                    moved = True
    return pts


@st.composite
def grid_polygon(draw, grid=6, reuse=()):
    """A valid simple polygon on a coarse integer grid (coarse: shared vertices, vertices
    on edges and collinear overlaps are frequent), maybe reusing given vertices.

    An outline that is not a valid polygon is repaired, not rejected: a repeated vertex
    is dropped and crossing edges are untangled (``untangled``). Most random outlines of
    6-8 points cross or repeat a point, and rejecting them cost about 30 draws per
    example. Outlines that were already valid are kept as drawn, so every polygon the
    plain rejection drew is still drawn; those that stay invalid (touching or collinear
    edges, zero area) are still rejected.
    """
    n = draw(st.integers(3, 8))
    pool = st.tuples(st.integers(0, grid), st.integers(0, grid))
    if reuse:
        pool = st.one_of(pool, st.sampled_from(list(reuse)))
    pts = draw(st.lists(pool, min_size=n, max_size=n))
    if not _valid_polygon(pts):
        pts = untangled(list(dict.fromkeys(pts)))
    if len(pts) < 3 or not _valid_polygon(pts):
        from hypothesis import assume

        assume(False)
    return pts


def _valid_polygon(pts) -> bool:
    g = GeosPolygon(pts)
    return g.is_valid and g.area > 0


@st.composite
def polygon_with_holes(draw, grid=8, reuse=()):
    outer = draw(grid_polygon(grid, reuse))
    holes = []
    if draw(st.booleans()):
        hole = draw(grid_polygon(grid, tuple(outer)))
        g = GeosPolygon(outer, [hole])
        if g.is_valid and g.area > 0 and GeosPolygon(outer).contains(GeosPolygon(hole)):
            holes.append(hole)
    return [outer] + holes


def transformed(rings, angle, dx, dy):
    c, s = math.cos(angle), math.sin(angle)
    return [[(c * x - s * y + dx, s * x + c * y + dy) for x, y in r] for r in rings]


def check_clip(a_rings, b_rings):
    a, b = oriented(a_rings), oriented(b_rings)
    inside, outside = clip(a, b)
    ga = GeosPolygon(a_rings[0], a_rings[1:])
    gb = GeosPolygon(b_rings[0], b_rings[1:])
    want_in, want_out = ga.intersection(gb), ga.difference(gb)
    assert shape_area(inside) == pytest.approx(want_in.area, abs=1e-9)
    assert shape_area(outside) == pytest.approx(want_out.area, abs=1e-9)
    assert shape_area(inside) + shape_area(outside) == pytest.approx(ga.area, abs=1e-9)
    # the same point sets, not only the same areas
    assert _point_sets_differ_by(geos(inside), want_in) < 1e-9
    assert _point_sets_differ_by(geos(outside), want_out) < 1e-9


def _point_sets_differ_by(got, want) -> float:
    """Area of the symmetric difference, overlaid on a 1e-12 grid: GEOS's floating overlay
    fails on two rings a few ulps apart (the intersection of (0,4),(2,0),(7,1) and
    (1,4),(3,0),(7,0) against our own, a vertex 1 ulp away: the whole polygon came back
    as their difference); snap-rounding is robust, and moves a polygon's area by at most
    its perimeter x 1e-12. Only the polygons count (an overlay's zero-area lines and points
    have no area, and the grid overlay refuses mixed dimensions)."""
    got, want = (shapely.MultiPolygon([p for p in shapely.get_parts(shapely.get_parts(g)) if p.geom_type == "Polygon"])
                 for g in (got, want))
    return shapely.symmetric_difference(got, want, grid_size=1e-12).area


@pytest.mark.slow
@FAST
@given(st.data())
def test_clip_degenerate_grid_polygons_match_geos(data):
    a = data.draw(polygon_with_holes())
    b = data.draw(polygon_with_holes(reuse=tuple(a[0])))  # shares vertices often
    check_clip(a, b)


# GEOS itself fails on shifts of a few ulps (it loses a whole triangle to a 1e-123
# shift), so the oracle is only asked about shifts it resolves
SHIFT = st.floats(-3, 3).filter(lambda v: v == 0 or abs(v) > 1e-6)


@pytest.mark.slow
@settings(max_examples=120, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.data(), st.floats(0, 2 * math.pi), SHIFT, SHIFT)
def test_clip_float_polygons_match_geos(data, angle, dx, dy):
    a = data.draw(polygon_with_holes())
    b = transformed(data.draw(polygon_with_holes()), angle, dx, dy)
    check_clip(a, b)


@pytest.mark.slow
@settings(max_examples=100, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.data())
def test_clip_by_itself_and_by_own_pieces(data):
    """Exact shared boundaries: a polygon clipped by itself, and by its own pieces."""
    a = data.draw(polygon_with_holes())
    check_clip(a, a)
    b = data.draw(polygon_with_holes())
    inside, _ = clip(oriented(a), oriented(b))
    for piece in polygons(inside):
        again_in, again_out = clip(oriented(a), piece)
        assert shape_area(again_in) == pytest.approx(shape_area(piece), abs=1e-9)
        assert shape_area(again_in) + shape_area(again_out) == pytest.approx(shape_area(oriented(a)), abs=1e-9)


def test_clip_hole_cut_and_holding_lists():
    square = oriented([[(0, 0), (10, 0), (10, 10), (0, 10)]])
    small = oriented([[(3, 3), (5, 3), (5, 5), (3, 5)]])
    inside, outside = clip(square, small)
    assert shape_area(inside) == 4 and shape_area(outside) == 96
    (poly,) = polygons(outside)
    assert len(poly.rings) == 2 and ring_area(poly.rings[1]) == -4  # the hole is attached
    inside, outside = clip(small, square)
    assert shape_area(inside) == 4 and not outside.rings
    far = oriented([[(20, 0), (30, 0), (30, 5)]])
    inside, outside = clip(far, square)
    assert not inside.rings and shape_area(outside) == shape_area(far)


SQUARE = [(0, 0), (10, 0), (10, 10), (0, 10)]


@pytest.mark.parametrize(
    "rings, rule",
    [
        ([[(0, 0), (4, 4), (4, 0), (0, 4)]], "self-crossing"),  # a bow tie
        ([SQUARE, [(2, 2), (12, 3), (3, 4)]], "self-crossing"),  # a hole poking out of its main contour
        ([SQUARE, [(2, 2), (6, 2), (2, 6)], [(3, 1), (3, 8), (1, 8)]], "self-crossing"),  # two holes crossing
        ([[(0, 0), (4, 0), (math.nan, 4)]], "finite"),
        ([[(0, 0), (4, 0), (math.inf, 4)]], "finite"),
    ],
)
@pytest.mark.parametrize("role", ["subject", "clip shape"])
def test_clip_refuses_invalid_input_naming_the_rule(rings, rule, role):
    """No fill rule makes a crossing contour a region: the clipper says so instead of
    returning an answer that is inside the input under none."""
    bad = Shape.of(rings)
    good = oriented([[(1, 1), (3, 1), (2, 5)]])
    with pytest.raises(InvalidShapeError, match=rule) as err:
        clip(bad, good) if role == "subject" else clip(good, bad)
    assert isinstance(err.value, ValueError)
    assert str(err.value).startswith(role) and "\n" not in str(err.value)


def test_clip_refuses_short_contours():
    with pytest.raises(InvalidShapeError, match="at least 3"):
        clip(Shape.of([[(0, 0), (1, 1)]]), oriented([SQUARE]))


def test_clip_accepts_touching_contours():
    """A hole touching its main contour at a vertex, or a contour touching itself, is a
    region (the clipper's own output is like that) and is accepted."""
    touching = oriented([SQUARE, [(0, 5), (4, 3), (4, 7)]])
    inside, outside = clip(touching, oriented([[(-1, -1), (5, -1), (5, 11), (-1, 11)]]))
    assert shape_area(inside) == pytest.approx(5 * 10 - 8) and shape_area(outside) == pytest.approx(50)
    xs, ys, _, starts = to_arrays(touching)
    assert first_crossing(xs, ys, starts, 1e-12) == (-1, -1)


@pytest.mark.slow
@settings(max_examples=200, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.data())
def test_separation_shortcut_agrees_with_the_clipper(data):
    """The solver hands a piece whole to one side when it lies clear of a convex clip
    polygon, or clear inside it; the clipper must say the same."""
    a = data.draw(polygon_with_holes())
    tri = data.draw(st.lists(st.tuples(st.floats(-2, 10), st.floats(-2, 10)), min_size=3, max_size=3))
    assume_area = abs(ring_area(tri))
    if assume_area < 1e-3:
        return
    subject, clipper = oriented(a), oriented([tri])
    sx, sy, sl, ss = to_arrays(subject)
    cx, cy, cl, cs = to_arrays(clipper)
    eps = 1e-12
    side = _separation(sx, sy, cx, cy, eps)
    ix, iy, il, ist, ox, oy, ol, ost = clip_arrays(sx, sy, sl, ss, cx, cy, cl, cs, eps)
    if side == OUTSIDE:
        assert len(ist) == 1 and _is_the_subject(subject, (ox, oy, ol, ost))
    elif side == INSIDE:
        assert len(ost) == 1 and _is_the_subject(subject, (ix, iy, il, ist))


def _is_the_subject(subject, part) -> bool:
    """Whether the clipper's part (xs, ys, labels, starts) is the subject: its very arrays,
    or, where a hole touches the outline, the same point set (the clipper traces a hole
    touching its outline at a point as one ring with it)."""
    if all(np.array_equal(got, want) for got, want in zip(part, to_arrays(subject))):
        return True
    outline, *holes = subject.rings
    touching = any(GeosPolygon(outline).exterior.intersects(GeosPolygon(h).exterior) for h in holes)
    return touching and geos(from_arrays(*part)).symmetric_difference(geos(subject)).area < 1e-12


def test_a_hole_touching_its_outline_stays_the_same_region_clear_of_the_clip():
    """Found by the property above: the hole's corner (2, 1) lies on the outline's edge, and
    the clipper gives the outline and hole back as one ring through that point."""
    subject = oriented([[(0, 2), (1, 0), (2, 0), (2, 3)], [(1, 1), (1, 2), (2, 1)]])
    clipper = oriented([[(0.0, 0.0), (0.0, 1.0), (0.5, 0.0)]])
    sx, sy, sl, ss = to_arrays(subject)
    cx, cy, cl, cs = to_arrays(clipper)
    assert _separation(sx, sy, cx, cy, 1e-12) == OUTSIDE
    ix, iy, il, ist, ox, oy, ol, ost = clip_arrays(sx, sy, sl, ss, cx, cy, cl, cs, 1e-12)
    assert len(ist) == 1 and _is_the_subject(subject, (ox, oy, ol, ost))


@pytest.mark.parametrize("seed", range(3))
def test_agrees_with_catmull_on_many_triangles(seed):
    """Hundreds of interpenetrating triangles (the benchmark's scene, smaller): every
    path of the compiled solver, shortcuts included, against catmull."""
    scene = random_triangles(150, 64, 48, size=16.0, seed=seed)
    np.testing.assert_allclose(render(scene, "weiler-atherton"), render(scene, "catmull"), rtol=0, atol=1e-9)


def test_coverage_matches_geos_per_pixel():
    rng = np.random.default_rng(3)
    ring = [tuple(p) for p in rng.uniform(-2, 9, (3, 2))]
    if ring_area(ring) < 0:
        ring = ring[::-1]
    got = coverage([ring], [1.0], 7, 5)
    g = GeosPolygon(ring)
    want = [[g.intersection(shapely.box(c, r, c + 1, r + 1)).area for c in range(7)] for r in range(5)]
    np.testing.assert_allclose(got, want, atol=1e-12)


def interpenetrating_scene(seed, n=6, width=16, height=12, grid=None):
    rng = np.random.default_rng(seed)
    polys = []
    for _ in range(n):
        c = rng.uniform(-2, [width + 2, height + 2])
        v = np.column_stack([c[0] + rng.uniform(-6, 6, 3), c[1] + rng.uniform(-6, 6, 3), rng.uniform(0, 10, 3)])
        if grid:
            v = np.round(v * grid) / grid  # shared vertices, shared edges, shared planes
        polys.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": v.tolist()})
    return parse_scene({"image": {"width": width, "height": height, "background": [0.1, 0.2, 0.3]}, "polygons": polys})


@pytest.mark.parametrize("grid", [None, 1, 2])
@pytest.mark.parametrize("seed", range(12))
def test_agrees_with_catmull_on_random_interpenetrating_scenes(seed, grid):
    try:
        scene = interpenetrating_scene(seed, grid=grid)
    except ValueError:
        pytest.skip("rounding made a polygon degenerate")  # refused by the scene format
    want = render(scene, "catmull")
    for spec in ("weiler-atherton", "weiler-atherton:window=2"):
        np.testing.assert_allclose(render(scene, spec), want, atol=1e-9, rtol=0)


@pytest.mark.parametrize("path", SCENES + [str(DATA / "wa_cyclic.toml")], ids=lambda p: Path(p).stem)
def test_agrees_with_catmull_on_shipped_scenes(path):
    scene = load_scene(path)
    for k in sorted({0, scene.frames - 1}):
        s = scene.at_frame(k)
        want = render(s, "catmull")
        np.testing.assert_allclose(render(s, "weiler-atherton"), want, atol=1e-9, rtol=0)
        np.testing.assert_allclose(render(s, "weiler-atherton:window=3"), want, atol=1e-9, rtol=0)


@pytest.mark.parametrize("window", [0, 1, 4])
def test_visible_pieces_tile_the_covered_area(window):
    """Visible pieces do not overlap and cover exactly the union of the polygons."""
    scene = load_scene(DATA / "wa_cyclic.toml")
    pieces = visible_pieces(scene, window=window)
    union = shapely.union_all([GeosPolygon(p.xy) for p in scene.polygons]).intersection(
        shapely.box(0, 0, scene.width, scene.height)
    )
    assert sum(p.area for p in pieces) == pytest.approx(union.area, abs=1e-9)
    assert shapely.union_all([geos(p.shape) for p in pieces]).area == pytest.approx(union.area, abs=1e-9)


def test_hidden_lines_cyclic_scene(tmp_path):
    scene = load_scene(DATA / "wa_cyclic.toml")
    edges = visible_edges(scene)
    # the two coplanar squares: the later (index 7) is in front, so the earlier one's
    # edge x = 16 under it is hidden, and its own edge y = 15 left of x = 16 is drawn
    assert not any(s == 6 and p[0] == q[0] == 16 and min(p[1], q[1]) > 15 for p, q, s in edges)
    # the interpenetrating triangles (4, 5) draw the line where their planes cross
    a, b = scene.polygons[4].plane, scene.polygons[5].plane
    d = a - b
    crossing = [
        (p, q) for p, q, s in edges
        if s in (4, 5) and max(abs(d[0] * x + d[1] * y + d[2]) for x, y in (p, q)) < 1e-9
    ]
    assert crossing
    # no cut between visible pieces of one polygon is drawn: subdivision into windows
    # changes nothing of the drawn point set (segments may be split differently)
    drawn = lambda es: shapely.union_all([shapely.LineString([p, q]) for p, q, _ in es])  # noqa: E731
    # (compared within 1e-9: an intersection vertex may come out 4e-16 off in one of them,
    # which makes the plain line difference the whole segment)
    whole = drawn(edges)
    for window in (1, 2, 4):
        with_windows = drawn(visible_edges(scene, window=window))
        assert with_windows.difference(whole.buffer(1e-9)).length < 1e-9
        assert whole.difference(with_windows.buffer(1e-9)).length < 1e-9
    out = tmp_path / "lines.svg"
    assert cli_main(["hidden-lines", str(DATA / "wa_cyclic.toml"), "-o", str(out), "--quiet"]) == 0
    assert out.read_text().count("<line ") == len(edges)
    assert cli_main(["hidden-lines", str(DATA / "wa_cyclic.toml"), "-o", str(tmp_path / "x.png")]) == 2


@pytest.mark.parametrize("seed", range(20))
def test_agrees_with_catmull_on_shared_random_and_degenerate_scenes(seed):
    for scene in (random_scene(seed), degenerate_scene(seed)):
        np.testing.assert_allclose(render(scene, "weiler-atherton"), render(scene, "catmull"), rtol=0, atol=1e-9)
