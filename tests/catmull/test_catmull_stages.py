"""Each stage of the Catmull kernel on its own, on tiny hand-drawn cases (3x3 grids).

In the style of datashader's glyph tests: build the smallest input a stage reads, run the
stage, compare with an answer worked out by hand. A disagreement with GEOS in
``test_catmull.py`` can then be narrowed to one stage.
"""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.native import catmull as _catmull
from aaeval.native import catmull_testing as K

BACKGROUND = _catmull.BACKGROUND

# the square [0.5, 2.5]^2 on a 3x3 grid covers a quarter of each corner pixel, half of
# each edge pixel and the whole centre pixel
SQUARE = [(0.5, 0.5), (2.5, 0.5), (2.5, 2.5), (0.5, 2.5)]
SQUARE_COVER = np.array([[0.25, 0.5, 0.25], [0.5, 1.0, 0.5], [0.25, 0.5, 0.25]])
FLAT = (0.0, 0.0, 1.0)  # depth plane z = a x + b y + c


def polygons(*outlines, planes=None):
    """Kernel input: outlines (positive orientation, y down) and their depth planes."""
    length = np.array([len(o) for o in outlines], np.int64)
    start = np.concatenate([[0], np.cumsum(length)[:-1]]).astype(np.int64)
    xy = np.array([v for o in outlines for v in o], float)
    planes = np.array(planes if planes is not None else [FLAT] * len(outlines), float)
    return start, length, xy[:, 0].copy(), xy[:, 1].copy(), planes


def scan(polys, width=3):
    """The polygons sorted on their first scanline, with one band's workspaces."""
    return K.Scan(*polys, width)


def strip_of(polys, rows, width=3):
    """The scan after entering and clipping every row in ``rows`` (active list and strip)."""
    s = scan(polys, width)
    for row in rows:
        s.enter_polygons(row)
        s.clip_to_strip(row)
    return s


def piece_coverage(strip, k, width=3):
    """Strip piece k's coverage as a full row of ``width`` columns."""
    c0, c1, off = strip.span[k]
    row = np.zeros(width)
    row[c0:c1 + 1] = strip.cov[off:off + c1 - c0 + 1]
    return row


def fragment_image(frags, n_pix, source):
    """Per-pixel area of polygon ``source`` from fragment arrays."""
    pix, src, area = frags[0], frags[1], frags[2]
    return np.bincount(pix[src == source], weights=area[src == source], minlength=n_pix)


# --- I. and III.A ---------------------------------------------------------------------


def test_sort_polygons_orders_on_first_scanline_and_keeps_y_ranges():
    s = scan(polygons([(0, 2.2), (1, 2.2), (1, 2.9)], [(0, 0.3), (2, 0.3), (2, 1.7)], [(0, 1.5), (1, 1.5), (1, 2.0)]))
    np.testing.assert_array_equal(s.order, [1, 2, 0])
    np.testing.assert_array_equal(s.ymin, [2.2, 0.3, 1.5])
    np.testing.assert_array_equal(s.ymax, [2.9, 1.7, 2.0])


def test_enter_polygons_on_their_first_scanline_cut_at_the_top_of_the_image():
    above = [(0.0, -2.0), (2.0, -2.0), (2.0, 0.5), (0.0, 0.5)]  # reaches into row 0
    gone = [(0.0, -2.0), (2.0, -2.0), (2.0, -1.0)]  # wholly above the image
    later = [(0.0, 1.5), (2.0, 1.5), (2.0, 2.5)]  # first scanline 1
    s = scan(polygons(above, gone, later))
    s.enter_polygons(0)
    assert s.active_n == 1 and s.next_in == 2  # `gone` was passed over, `later` waits
    start, n, src = s.active_recs[0]
    assert src == 0
    ys = s.active_y[start:start + n]
    assert ys.min() == 0.0 and ys.max() == 0.5  # the part above y = 0 is cut away
    s.enter_polygons(1)
    assert s.active_n == 2 and s.active_recs[1, 2] == 2 and s.next_in == 3


# --- III.C ----------------------------------------------------------------------------


def test_strip_coverage_of_a_triangle_is_the_area_under_its_edge_per_column():
    # (0,0) (3,0) (0,1): the area in column c is the integral of 1 - x/3 over [c, c+1]
    xs = np.array([0.0, 3.0, 0.0])
    ys = np.array([0.0, 0.0, 1.0])
    cov = K.strip_coverage(xs, ys, 0, 3, 0.0, 0, 2)
    np.testing.assert_allclose(cov, [5 / 6, 1 / 2, 1 / 6], rtol=0, atol=1e-15)


def test_clip_to_strip_gives_each_row_of_the_square_and_keeps_the_rest():
    s = scan(polygons(SQUARE))
    for row in range(3):
        s.enter_polygons(row)
        s.clip_to_strip(row)
        assert s.strip_n == 1
        np.testing.assert_array_equal(piece_coverage(s, 0), SQUARE_COVER[row])
        start, n, src = s.pieces[0]
        assert src == 0 and s.strip_y[start:start + n].min() >= row and s.strip_y[start:start + n].max() <= row + 1
        if row < 2:  # the remainder starts on the next scanline
            start, n, _ = s.active_recs[0]
            assert s.active_n == 1 and s.active_y[start:start + n].min() == row + 1
    assert s.active_n == 0


def test_clip_to_strip_column_span_stays_inside_the_image():
    wide = [(-4.0, 0.25), (7.0, 0.25), (7.0, 0.75), (-4.0, 0.75)]
    strip = strip_of(polygons(wide), [0])
    np.testing.assert_array_equal(strip.span[0, :2], [0, 2])
    np.testing.assert_array_equal(piece_coverage(strip, 0), [0.5, 0.5, 0.5])


def test_bucket_by_x_lists_pieces_under_their_leftmost_column_in_order():
    # four thin pieces starting in columns 2, 0, 2, 1
    outlines = [[(x, 0.2), (x + 0.5, 0.2), (x + 0.5, 0.8)] for x in (2.1, 0.1, 2.3, 1.1)]
    strip = strip_of(polygons(*outlines), [0])
    strip.bucket_by_x()
    head = strip.bucket_head
    np.testing.assert_array_equal(head, [0, 1, 2, 4])
    sources = strip.pieces[strip.bucket_items[:4], 2]
    np.testing.assert_array_equal(sources, [1, 3, 0, 2])


# --- III.D/E --------------------------------------------------------------------------


def test_update_zlist_enters_leaves_and_sorts_front_to_back():
    near = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)]  # columns 0-1, z = 1
    far = [(0.0, 0.0), (3.0, 0.0), (3.0, 1.0), (0.0, 1.0)]  # columns 0-2, z = 5
    mid = [(1.0, 0.0), (3.0, 0.0), (3.0, 1.0), (1.0, 1.0)]  # columns 1-2, z = 3
    strip = strip_of(polygons(near, far, mid, planes=[(0, 0, 1), (0, 0, 5), (0, 0, 3)]), [0])
    strip.bucket_by_x()
    seen = [list(strip.pieces[strip.update_zlist(col, 0), 2]) for col in range(3)]
    assert seen == [[0, 1], [0, 2, 1], [2, 1]]


def test_update_zlist_puts_the_later_polygon_first_on_a_shared_plane():
    square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    strip = strip_of(polygons(square, square, planes=[FLAT, FLAT]), [0])
    strip.bucket_by_x()
    assert list(strip.pieces[strip.update_zlist(0, 0), 2]) == [1, 0]


def test_pixel_list_stops_at_a_solid_piece_that_hides_the_rest():
    sliver = [(0.0, 0.0), (1.0, 0.0), (0.0, 0.5)]  # irregular, in front
    solid = [(-1.0, 0.0), (4.0, 0.0), (4.0, 1.0), (-1.0, 1.0)]  # covers the row
    hidden = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)]  # behind the solid piece everywhere
    crossing = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]  # crosses the solid piece's plane
    # z = 4x + 3.5 is behind the solid piece (z = 5) at the pixel centre, in front for x < 3/8
    planes = [(0, 0, 1), (0, 0, 5), (0, 0, 9), (4, 0, 3.5)]
    strip = strip_of(polygons(sliver, solid, hidden, crossing, planes=planes), [0])
    strip.bucket_by_x()
    strip.update_zlist(0, 0)
    plist, solid_k = strip.pixel_list(0, 0, 1e-11)
    assert list(strip.pieces[plist, 2]) == [0, 1, 3]
    assert strip.pieces[solid_k, 2] == 1


def test_emit_strip_piece_keeps_the_coverage_area_and_finds_the_centroid():
    # the strip coverage's area is kept as given (it may differ from the clipped
    # polygon's by rounding); the centroid comes from the vertices
    xs = np.array([0.0, 1.0, 0.0])
    ys = np.array([0.0, 0.0, 1.0])
    out = K.FragmentSink()
    out.emit_strip_piece(5, 2, 0.5 + 1e-16, xs, ys, 0, 3)
    pix, src, area, cx, cy = out.arrays()
    assert (pix[0], src[0], area[0]) == (5, 2, 0.5 + 1e-16)
    np.testing.assert_allclose([cx[0], cy[0]], [1 / 3, 1 / 3])


def test_emit_piece_merges_pieces_of_one_polygon_in_one_pixel():
    # two halves of the unit square from polygon 3, and a quarter from polygon 4
    xs = np.array([0.0, 0.5, 0.5, 0.0, 0.5, 1.0, 1.0, 0.5, 0.0, 0.5, 0.5, 0.0])
    ys = np.array([0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.5, 0.5])
    out = K.FragmentSink()
    for src, start in ((3, 0), (4, 8), (3, 4)):
        out.emit_piece(0, src, xs, ys, start, 4)
    pix, src, area, cx, cy = out.arrays()
    np.testing.assert_array_equal(src, [3, 4])
    np.testing.assert_allclose(area, [0.5 + 0.5, 0.25])
    np.testing.assert_allclose(cx, [0.5, 0.25])
    np.testing.assert_allclose(cy, [0.5, 0.25])


def test_emit_rest_is_the_pixel_minus_what_was_emitted():
    # the lower-left triangle (0,0) (1,0) (0,1) has area 1/2, centroid (1/3, 1/3)
    xs = np.array([0.0, 1.0, 0.0])
    ys = np.array([0.0, 0.0, 1.0])
    out = K.FragmentSink()
    out.emit_piece(0, 7, xs, ys, 0, 3)
    out.emit_rest(0, BACKGROUND, 0.0, 0.0)
    pix, src, area, cx, cy = out.arrays()
    np.testing.assert_array_equal(src, [7, BACKGROUND])
    np.testing.assert_allclose(area, [0.5, 0.5])
    np.testing.assert_allclose(cx, [1 / 3, 2 / 3])
    np.testing.assert_allclose(cy, [1 / 3, 2 / 3])


# --- III.E.b: the pixel integrator ------------------------------------------------------


def integrate_unit_pixel(outlines, planes, solid_last=False):
    """Run the pixel integrator on the pixel [0,1]^2 over row-0 strip pieces."""
    strip = strip_of(polygons(*outlines, planes=planes), [0], width=1)
    n = strip.strip_n
    (pix, src, area, cx, cy), _ = strip.integrate(list(range(n)), n - 1 if solid_last else -1, 0.0, 0.0, 1e-11)
    order = np.argsort(src)
    return src[order], area[order], cx[order], cy[order]


def test_integrate_pixel_triangle_over_the_background():
    src, area, cx, cy = integrate_unit_pixel([[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]], [FLAT])
    np.testing.assert_array_equal(src, [BACKGROUND, 0])
    np.testing.assert_allclose(area, [0.5, 0.5], atol=1e-15)
    np.testing.assert_allclose(cx, [2 / 3, 1 / 3], atol=1e-15)


def test_integrate_pixel_nearer_polygon_behind_in_the_list_moves_to_the_front():
    # the list is given far triangle first; the nearer full square hides it entirely
    tri = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]
    square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    src, area, _, _ = integrate_unit_pixel([tri, square], [(0, 0, 9), (0, 0, 1)], solid_last=True)
    np.testing.assert_array_equal(src, [1])
    np.testing.assert_allclose(area, [1.0], atol=1e-15)


def test_integrate_pixel_splits_interpenetrating_planes_where_they_cross():
    # z = x and z = 1 - x over the whole pixel: each is in front on one half
    square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    big = [(-1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (-1.0, 1.0)]
    src, area, cx, cy = integrate_unit_pixel([square, big], [(1, 0, 0), (-1, 0, 1)], solid_last=True)
    np.testing.assert_array_equal(src, [0, 1])
    np.testing.assert_allclose(area, [0.5, 0.5], atol=1e-15)
    np.testing.assert_allclose(cx, [0.25, 0.75], atol=1e-15)
    np.testing.assert_allclose(cy, [0.5, 0.5], atol=1e-15)


def test_integrate_pixel_ends_a_cycle_of_near_coplanar_ties_with_the_pixel_covered():
    # three parallel planes 0.6 eps_z apart: B ties A and is later, C ties B and is later,
    # but A is in front of C by 1.2 eps_z; the shared-plane tolerance is not transitive, so
    # moving the nearer polygon to the front went round A -> B -> C -> A until MAX_STEPS
    # and the pixel came out empty
    square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    eps_z = 1e-11
    planes = [(0.0, 0.0, 1.0), (0.0, 0.0, 1.0 + 0.6 * eps_z), (0.0, 0.0, 1.0 + 1.2 * eps_z)]
    src, area, _, _ = integrate_unit_pixel([square, square, square], planes)
    assert len(src) == 1 and src[0] in (0, 1, 2)  # each is within 1.2 eps_z of the front
    np.testing.assert_allclose(area, [1.0], atol=1e-15)


def test_integrate_pixel_grows_its_workspace_and_gives_the_same_answer():
    rng = np.random.default_rng(4)
    outlines = [[tuple(p) for p in rng.uniform(-0.5, 1.5, (3, 2))] for _ in range(12)]
    outlines = [o if _area(o) > 0 else o[::-1] for o in outlines]
    planes = rng.uniform(-1, 1, (12, 3)).tolist()
    strip = strip_of(polygons(*outlines, planes=planes), [0], width=1)
    plist = list(range(strip.strip_n))
    results = [strip.integrate(plist, -1, 0.0, 0.0, 1e-11, tiny=tiny) for tiny in (False, True)]
    assert results[1][1] > 8  # the tiny workspace did grow
    for a, b in zip(results[0][0], results[1][0]):
        np.testing.assert_array_equal(a, b)
    assert results[0][0][2].sum() == pytest.approx(1.0, abs=1e-12)


def _area(o):
    x, y = np.array(o).T
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


# --- the whole kernel on 3x3 ----------------------------------------------------------


def kernel_fragments(polys, width, height, jagged, centroids):
    return _catmull.fragments(*polys, 1e-11, width, height, jagged, centroids, 1)


def test_sweep_row_and_kernel_give_the_square_its_exact_coverage():
    frags = kernel_fragments(polygons(SQUARE), 3, 3, False, True)
    np.testing.assert_array_equal(fragment_image(frags, 9, 0), SQUARE_COVER.ravel())
    np.testing.assert_array_equal(fragment_image(frags, 9, BACKGROUND), 1.0 - SQUARE_COVER.ravel())
    pix, src, _, cx, cy = frags
    # the corner pixel (0, 0): the square's quarter has centroid (0.75, 0.75)
    at = (pix == 0) & (src == 0)
    np.testing.assert_allclose([cx[at][0], cy[at][0]], [0.75, 0.75], atol=1e-15)


def test_kernel_nearer_square_hides_the_farther_one_in_the_overlap():
    # the near square [0.5, 2.5]^2 over a far one [0, 1.5]^2: the far one shows only
    # where the near one is absent
    far = [(0.0, 0.0), (1.5, 0.0), (1.5, 1.5), (0.0, 1.5)]
    frags = kernel_fragments(polygons(far, SQUARE, planes=[(0, 0, 5), (0, 0, 1)]), 3, 3, False, False)
    expected_far = np.array([[0.75, 0.25, 0], [0.25, 0, 0], [0, 0, 0]])
    np.testing.assert_allclose(fragment_image(frags, 9, 0), expected_far.ravel(), atol=1e-15)
    np.testing.assert_allclose(fragment_image(frags, 9, 1), SQUARE_COVER.ravel(), atol=1e-15)


def test_jagged_kernel_gives_each_pixel_to_its_nearest_piece():
    frags = kernel_fragments(polygons(SQUARE), 3, 3, True, False)
    np.testing.assert_array_equal(fragment_image(frags, 9, 0), np.ones(9))


# --- solid runs ---------------------------------------------------------------------


def test_hidden_until_is_the_last_column_where_the_plane_stays_in_front():
    # z_p = x against z_q = 2.5: p is nearer on the whole square [x0, x0+1] while x0 + 1 < 2.5
    planes = np.array([(1.0, 0.0, 0.0), (0.0, 0.0, 2.5)])
    assert K.hidden_until(planes, 0, 1, 0, 5, 0, 6) == 1
    assert K.hidden_until(planes, 0, 1, 2, 5, 0, 6) == 1  # not even at column 2
    assert K.hidden_until(planes, 1, 0, 0, 5, 0, 6) == -1  # q in front at column 0
    assert K.hidden_until(planes, 1, 0, 3, 5, 0, 6) == 5  # ... and hidden from column 3 on


def test_solid_run_stops_before_a_piece_entering_in_front_and_takes_in_those_behind():
    solid = [(-1.0, 0.0), (7.0, 0.0), (7.0, 1.0), (-1.0, 1.0)]  # z = 5, whole row
    behind = [(2.2, 0.1), (2.8, 0.1), (2.8, 0.9)]  # enters at column 2, z = 9
    front = [(4.2, 0.1), (4.8, 0.1), (4.8, 0.9)]  # enters at column 4, z = 1
    strip = strip_of(polygons(solid, behind, front, planes=[(0, 0, 5), (0, 0, 9), (0, 0, 1)]), [0], width=6)
    strip.bucket_by_x()
    k = strip.update_zlist(0, 0)[0]
    end, zl = strip.solid_run(k, 0, 0)
    assert end == 3
    assert sorted(strip.pieces[zl, 2]) == [0, 1]  # `behind` joined the z-list, `front` waits


# --- the two-layer shortcut (areas only) -------------------------------------------------


def _overlap(outlines, col=1):
    return strip_of(polygons(*outlines), [0], width=3).two_layer_overlap(0, 1, float(col))


def test_two_layer_overlap_of_two_half_pixel_triangles_is_their_quarter_by_hand():
    # in pixel [1,2]x[0,1]: A below the diagonal y = x - 1, B left of x = 1.5
    a = [(1.0, 0.0), (2.0, 0.0), (2.0, 1.0)]
    b = [(1.0, 0.0), (1.5, 0.0), (1.5, 1.0), (1.0, 1.0)]
    # A ∩ B is the triangle (1,0), (1.5,0), (1.5,0.5): area 1/8
    assert _overlap([a, b]) == pytest.approx(0.125, abs=1e-15)


def test_two_layer_overlap_declines_a_front_part_that_is_not_convex():
    notch = [(1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.5, 0.3), (1.0, 1.0)]
    b = [(0.0, 0.0), (3.0, 0.0), (3.0, 1.0), (0.0, 1.0)]
    assert _overlap([notch, b]) == -1.0


def test_two_layer_overlap_equals_geos_on_random_convex_fronts():
    import shapely  # noqa: F401 - the test extra installs the oracle
    from shapely.geometry import Polygon, box

    rng = np.random.default_rng(7)
    checked = overlapping = 0
    for _ in range(600):
        a = rng.uniform(-0.5, 3.5, (3, 2))  # a triangle: convex
        b = rng.uniform(-0.5, 3.5, (int(rng.integers(3, 6)), 2))
        if not Polygon(b).is_valid or Polygon(b).area < 1e-6 or Polygon(a).area < 1e-6:
            continue
        # the kernel's positive orientation is a positive shoelace area
        a = [tuple(p) for p in (a if _area(a) > 0 else a[::-1])]
        b = [tuple(p) for p in (b if _area(b) > 0 else b[::-1])]
        strip = strip_of(polygons(a, b), [0], width=3)
        if strip.strip_n != 2:
            continue
        ka = [k for k in range(2) if strip.pieces[k, 2] == 0][0]
        got = strip.two_layer_overlap(ka, 1 - ka, 1.0)
        want = Polygon(a).intersection(Polygon(b)).intersection(box(1, 0, 2, 1)).area
        assert got == pytest.approx(want, abs=1e-12)
        checked += 1
        overlapping += want > 1e-3
    assert checked > 150 and overlapping > 50
