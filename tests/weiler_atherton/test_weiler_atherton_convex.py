"""The hidden-surface loop's short road (convex pieces cut by convex outlines, edge line
by edge line) and the first list kept per polygon: the stages on hand-drawn cases, and
the whole against the paper's clipper on every pair and against GEOS."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon as GeosPolygon

from aaeval.renderers import render
from aaeval.scenes import load_scene
from aaeval.scenes.generate import random_triangles
from aaeval.native.weiler_atherton import later_neighbours
from aaeval.native.weiler_atherton_testing import edge_line_values, plane_line_values, split_convex, vertex_sides
from aaeval.weiler_atherton import visible_pieces
from aaeval.weiler_atherton.lines import visible_edges
from tests.helpers.randomscenes import degenerate_scene, random_scene

DATA = Path(__file__).parents[1] / "data"
LINE = 99  # the label the cut edge gets in these cases


def split(xy, labels, d, tol=1e-12):
    """split_convex on a hand-drawn contour: both parts as (vertex list, label list)."""
    xy = np.asarray(xy, dtype=np.float64)
    n = len(xy)
    out = [np.zeros(n + 2) for _ in range(4)] + [np.zeros(n + 2, np.int64) for _ in range(2)]
    lx, ly, rx, ry, ll, rl = out
    nl, nr = split_convex(xy[:, 0].copy(), xy[:, 1].copy(), np.asarray(labels, np.int64), n,
                          np.asarray(d, np.float64), tol, LINE, lx, ly, ll, rx, ry, rl)
    left = (list(zip(lx[:nl].tolist(), ly[:nl].tolist())), ll[:nl].tolist())
    right = (list(zip(rx[:nr].tolist(), ry[:nr].tolist())), rl[:nr].tolist())
    return left, right


def test_split_convex_cuts_a_square_into_two_halves_labelling_the_cut():
    # the square 0..2 cut at x = 1 (d = x - 1): each half keeps the labels of the original
    # edges it runs along, and its edge on the line is labelled LINE
    left, right = split([(0, 0), (2, 0), (2, 2), (0, 2)], [10, 11, 12, 13], [-1, 1, 1, -1])
    assert left == ([(0, 0), (1, 0), (1, 2), (0, 2)], [10, LINE, 12, 13])
    assert right == ([(1, 0), (2, 0), (2, 2), (1, 2)], [10, 11, 12, LINE])


def test_split_convex_gives_a_vertex_on_the_line_to_both_parts():
    # the apex (1, 2) of the triangle lies on x = 1: both parts end there, and the left
    # part keeps the original edge from the apex down to (0, 0)
    left, right = split([(0, 0), (2, 0), (1, 2)], [10, 11, 12], [-1, 1, 0])
    assert left == ([(0, 0), (1, 0), (1, 2)], [10, LINE, 12])
    assert right == ([(1, 0), (2, 0), (1, 2)], [10, 11, LINE])
    # within tol of the line counts as on it
    left_t, right_t = split([(0, 0), (2, 0), (1, 2)], [10, 11, 12], [-1, 1, 1e-13], tol=1e-12)
    assert left_t == left and right_t == right


def test_split_convex_cuts_an_edge_at_the_same_point_walked_either_way():
    # two triangles sharing the edge (0, 0.3)-(3, 1.7), walked in opposite directions,
    # cut by one line: the point on the shared edge is the same to the bit
    a = np.array([(0.0, 0.3), (3.0, 1.7), (0.0, 3.0)])
    b = np.array([(3.0, 1.7), (0.0, 0.3), (3.0, -1.0)])
    line = (0.7, 0.0, 0.6, 3.0)  # a -> b, d = its line's value
    points = []
    for tri in (a, b):
        d = np.zeros(3)
        edge_line_values(tri[:, 0].copy(), tri[:, 1].copy(), 3, *line, d)
        left, right = split(tri, [0, 0, 0], d)
        points.append(set(left[0]) & set(right[0]))
    assert points[0] & points[1]


def test_line_values_and_sides():
    xs = np.array([0.0, 2.0, 2.0, 0.0])
    ys = np.array([0.0, 0.0, 2.0, 2.0])
    d = np.zeros(4)
    scale = edge_line_values(xs, ys, 4, 1.0, 0.0, 1.0, 2.0, d)  # upwards along x = 1: left is x < 1
    assert scale == 2.0 and d.tolist() == [-2.0, 2.0, 2.0, -2.0]
    assert vertex_sides(d, 4, 1e-12) == (True, True)
    assert plane_line_values(xs, ys, 4, 3.0, 4.0, -1.0, d) == 5.0 and d.tolist() == [-1.0, 5.0, 13.0, 7.0]
    assert vertex_sides(d, 4, 1e-12) == (True, True) and vertex_sides(d, 4, 20.0) == (False, False)


def testlater_neighbours_are_the_overlapping_boxes_later_in_the_order():
    rng = np.random.default_rng(3)
    lo = rng.uniform(0, 20, (60, 2)).round()  # integer corners: touching boxes happen
    boxes = np.hstack([lo, lo + rng.integers(0, 6, (60, 2))])
    order = rng.permutation(60)
    starts, rows = later_neighbours(boxes, order)
    b = boxes[order]
    for p in range(60):
        want = [q for q in range(p + 1, 60)
                if b[q, 0] < b[p, 2] and b[q, 2] > b[p, 0] and b[q, 1] < b[p, 3] and b[q, 3] > b[p, 1]]
        assert rows[starts[p] : starts[p + 1]].tolist() == want


def scenes():
    out = [random_triangles(150, 48, 48, size=14.0, depth_range=(0.0, 100.0), seed=s) for s in range(4)]
    out += [random_scene(s) for s in range(12)] + [degenerate_scene(s) for s in range(12)]
    return out + [load_scene(DATA / "wa_cyclic.toml")]


@pytest.mark.slow
@pytest.mark.parametrize("index", range(29))
def test_convex_road_gives_the_paper_clippers_image_and_regions(index):
    scene = scenes()[index]
    image = render(scene, "weiler-atherton")
    np.testing.assert_allclose(image, render(scene, "weiler-atherton:convex=false"), rtol=0, atol=1e-12)
    pieces = visible_pieces(scene)
    union = shapely.union_all([GeosPolygon(p.xy) for p in scene.polygons if len(p.xy) >= 3]).intersection(
        shapely.box(0, 0, scene.width, scene.height))
    assert sum(p.area for p in pieces) == pytest.approx(union.area, abs=1e-9)


@pytest.mark.slow
def test_convex_road_is_taken_on_triangles_and_draws_the_same_lines():
    scene = random_triangles(150, 48, 48, size=14.0, depth_range=(0.0, 100.0), seed=7)
    # the outside of a clip comes as convex pieces: more of them than the paper's
    assert len(visible_pieces(scene)) > 1.5 * len(visible_pieces(scene, convex=False))
    drawn = lambda es: shapely.union_all([shapely.LineString([p, q]) for p, q, _ in es])  # noqa: E731
    for sc in (scene, load_scene(DATA / "wa_cyclic.toml")):
        short, paper = drawn(visible_edges(sc)), drawn(visible_edges(sc, convex=False))
        assert paper.length > 0
        assert short.difference(paper.buffer(1e-9)).length < 1e-9
        assert paper.difference(short.buffer(1e-9)).length < 1e-9
