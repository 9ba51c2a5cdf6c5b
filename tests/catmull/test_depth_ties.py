"""The scene format's one near-tie rule (docs/scene_format.md, "Near ties"), in every
method that resolves depth.

At a point, every polygon within eps = 1e-11 (1 + max |z|) of the nearest depth there is
tied with it, and the latest listed of them is visible. The references here are built
without aaeval's geometry: GEOS (shapely) regions from the raw quads and the planes the
test itself tilted, and plain arithmetic for constant depths.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from aaeval.renderers import render
from aaeval.scenes import parse_scene

QUAD = [(5.25, 6.5), (57.75, 4.125), (59.5, 58.25), (3.125, 55.875)]
PIVOT = (31.0, 31.0)
SIZE = 64
DEPTH_METHODS = ["catmull", "weiler-atherton", "point", "supersample:k=4", "jitter:k=4", "abuffer", "skia",
                 "mitsuba:spp=16"]


def tilted_planes(k: int, tilt: float, seed: int = 0) -> np.ndarray:
    """k planes z = 1 + a (x - 31) + b (y - 31), each tilted by ``tilt`` in a random direction."""
    theta = np.random.default_rng(seed).uniform(0, 2 * np.pi, k)
    return np.stack([tilt * np.cos(theta), tilt * np.sin(theta)], axis=1)


def stack_scene(slopes: np.ndarray, colors: list) -> object:
    polygons = []
    for (a, b), color in zip(slopes, colors):
        vertices = [[x, y, 1.0 + a * (x - PIVOT[0]) + b * (y - PIVOT[1])] for x, y in QUAD]
        polygons.append({"color": list(color), "vertices": vertices})
    return parse_scene({"image": {"width": SIZE, "height": SIZE}, "polygons": polygons})


def geos_rule_image(planes: np.ndarray, colors: list, eps: float) -> np.ndarray:
    """Per-pixel colour by the rule, from GEOS: polygon i is tied where no other polygon is
    more than eps nearer, and visible where it is tied and no later polygon is.
    ``planes[i] = (a, b, c)`` with z = a x + b y + c."""
    quad = shapely.Polygon(QUAD)
    x0, y0, x1, y1 = quad.bounds
    box = [(x0 - 1, y0 - 1), (x1 + 1, y0 - 1), (x1 + 1, y1 + 1), (x0 - 1, y1 + 1)]

    def nearer_than(i: int, j: int):  # where z_j < z_i - eps
        da, db, dc = planes[j] - planes[i]
        dc += eps
        values = [da * x + db * y + dc for x, y in box]
        kept = []
        for k in range(4):
            p, q, dp, dq = box[k], box[(k + 1) % 4], values[k], values[(k + 1) % 4]
            if dp <= 0:
                kept.append(p)
            if (dp < 0 < dq) or (dq < 0 < dp):
                t = dp / (dp - dq)
                kept.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
        return shapely.Polygon(kept) if len(kept) >= 3 else shapely.Polygon()

    n = len(planes)
    # tied[i]: where polygon i is within eps of the nearest (no other more than eps nearer)
    tied = [shapely.difference(quad, shapely.union_all([nearer_than(i, j) for j in range(n) if j != i]))
            for i in range(n)]
    image = np.zeros((SIZE, SIZE, 3))
    pixels = [[shapely.box(c, r, c + 1, r + 1) for c in range(SIZE)] for r in range(SIZE)]
    for i in range(n):
        region = shapely.difference(tied[i], shapely.union_all(tied[i + 1:])) if i + 1 < n else tied[i]
        for r in range(SIZE):
            for c in range(SIZE):
                image[r, c] += region.intersection(pixels[r][c]).area * np.asarray(colors[i])
    return image


@pytest.mark.slow
@pytest.mark.parametrize("gap", [0.0, 1e-13, 1e-12, 1.5e-11])
@pytest.mark.parametrize("method", DEPTH_METHODS)
def test_two_planes_within_eps_show_the_later_polygon(method, gap):
    # eps = 1e-11 (1 + max |z|) is about 2e-11 here: the later (farther) blue square is tied
    scene = parse_scene({"image": {"width": 16, "height": 16}, "polygons": [
        {"color": [1, 0, 0], "vertices": [[2, 2, 1.0], [12, 2, 1.0], [12, 12, 1.0], [2, 12, 1.0]]},
        {"color": [0, 0, 1], "vertices": [[4, 4, 1 + gap], [14, 4, 1 + gap], [14, 14, 1 + gap], [4, 14, 1 + gap]]},
    ]})
    np.testing.assert_allclose(render(scene, method)[8, 8], [0, 0, 1], atol=1e-6)


@pytest.mark.parametrize("method", DEPTH_METHODS)
def test_two_planes_beyond_eps_show_the_nearer_polygon(method):
    scene = parse_scene({"image": {"width": 16, "height": 16}, "polygons": [
        {"color": [1, 0, 0], "vertices": [[2, 2, 1.0], [12, 2, 1.0], [12, 12, 1.0], [2, 12, 1.0]]},
        {"color": [0, 0, 1], "vertices": [[4, 4, 1 + 1e-9], [14, 4, 1 + 1e-9], [14, 14, 1 + 1e-9], [4, 14, 1 + 1e-9]]},
    ]})
    np.testing.assert_allclose(render(scene, method)[8, 8], [1, 0, 0], atol=1e-6)


@pytest.mark.parametrize("method", DEPTH_METHODS)
def test_the_band_is_relative_to_the_nearest_depth_not_chained(method):
    # constant depths 0, 0.8 eps, 1.6 eps in file order (eps = 1e-11 here): the first two
    # are tied with the nearest and the second is visible; the third is 1.6 eps behind the
    # nearest, although within eps of the second
    eps = 1e-11
    square = [[1, 1], [7, 1], [7, 7], [1, 7]]
    colors = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    scene = parse_scene({"image": {"width": 8, "height": 8}, "polygons": [
        {"color": c, "vertices": [[x, y, z] for x, y in square]} for c, z in zip(colors, [0.0, 0.8 * eps, 1.6 * eps])
    ]})
    np.testing.assert_allclose(render(scene, method)[4, 4], [0, 1, 0], atol=1e-6)


@pytest.mark.parametrize("tilt", [1e-13, 1e-12, 1e-11, 1e-10, 1e-9])
@pytest.mark.parametrize("k", [2, 4, 12, 40])
@pytest.mark.parametrize("method", ["catmull", "weiler-atherton"])
def test_near_coplanar_stack_covers_exactly_the_quad(method, k, tilt):
    scene = stack_scene(tilted_planes(k, tilt), [[1.0, 0.0, 0.0]] * k)
    assert render(scene, method)[..., 0].sum() == pytest.approx(shapely.Polygon(QUAD).area, abs=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("tilt", [1e-12, 1e-10])
@pytest.mark.parametrize("method", ["catmull", "weiler-atherton"])
def test_a_stack_of_120_covers_exactly_the_quad(method, tilt):
    scene = stack_scene(tilted_planes(120, tilt, seed=3), [[0.0, 1.0, 0.0]] * 120)
    assert render(scene, method)[..., 1].sum() == pytest.approx(shapely.Polygon(QUAD).area, abs=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize("tilt", [1e-13, 1e-12, 1e-10, 1e-9])
@pytest.mark.parametrize("k", [4, 12])
def test_near_coplanar_stack_follows_the_rule_per_pixel(k, tilt):
    slopes = tilted_planes(k, tilt, seed=k)
    colors = np.random.default_rng(5).uniform(0, 1, (k, 3)).tolist()
    scene = stack_scene(slopes, colors)
    eps = 1e-11 * (1 + np.abs(scene.arrays.vertices[:, 2]).max())
    # the planes through the scene's float vertices, not the slopes the test chose: at a
    # tilt of 1e-12 the rounding of a vertex's z (1e-16) moves a tie line by 1e-4 px
    expected = geos_rule_image(np.asarray(scene.arrays.planes), colors, eps)
    for method in ("catmull", "weiler-atherton"):
        np.testing.assert_allclose(render(scene, method), expected, atol=1e-9, err_msg=method)
    # the samplers apply the rule point by point: a fine grid converges to the same image
    np.testing.assert_allclose(render(scene, "supersample:k=16"), expected, atol=0.02)


@pytest.mark.parametrize("k", [3, 110, 120])
@pytest.mark.parametrize("method", ["catmull", "weiler-atherton"])
def test_the_tilted_stack_of_squares_keeps_its_area(method, k):
    # the stack the issue-13 fuzz found (one corner raised by i * 1e-12, the others on
    # z = 1): W-A covered 1138.6 of 1296 px² from k = 110 on
    square = [[4, 4], [40, 5], [39, 40], [3, 41]]
    scene = parse_scene({"image": {"width": 41, "height": 41}, "polygons": [
        {"color": [1.0, 0.0, 0.0], "vertices": [[*square[0], 1 + i * 1e-12], [*square[1], 1], [*square[2], 1], [*square[3], 1]]}
        for i in range(k)]})
    inside = shapely.Polygon(square).intersection(shapely.box(0, 0, 41, 41)).area
    assert render(scene, method)[..., 0].sum() == pytest.approx(inside, abs=1e-9)
