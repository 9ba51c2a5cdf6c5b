"""Baseline anti-aliasing methods: properties across all methods, and each against references.

References independent of the sampling kernel: matplotlib's point-in-polygon test
(``Path.contains_points``) with numpy depth comparison for ``point`` and the A-buffer
masks; the exact ``catmull`` image (itself checked against GEOS in test_catmull.py) for
convergence; stratification and blending properties with known answers.
"""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.path import Path

from aaeval.renderers import METHODS, MethodError, render, resolve
from aaeval.scenes import parse_scene

from tests.helpers.randomscenes import random_scene

resolve("catmull")  # registers every built-in method
EIGHT_BIT_METHODS = {"blend2d"}  # methods whose image is stored in bytes
ALL_METHODS = sorted(m for m in METHODS if METHODS[m].requires is None)  # the others draw a scene's source


def scene_of(polygons, width=8, height=6, background=(0.0, 0.0, 0.0)):
    return parse_scene({"image": {"width": width, "height": height, "background": list(background)},
                        "polygons": polygons})


def rect(x0, y0, x1, y1, z=1.0, color=(1.0, 1.0, 1.0)):
    return {"color": list(color), "vertices": [[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]]}


def rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def point_oracle(scene, xs, ys):
    """Colour seen at each point (x, y): nearest polygon containing it, later one on ties."""
    pts = np.column_stack([xs.ravel(), ys.ravel()])
    best_z = np.full(len(pts), np.inf)
    rgb = np.tile(scene.background, (len(pts), 1))
    for p in scene.polygons:
        hit = Path(p.xy).contains_points(pts)
        z = p.plane[0] * pts[:, 0] + p.plane[1] * pts[:, 1] + p.plane[2]
        win = hit & (z <= best_z + 1e-9)  # one shared plane: the later polygon
        best_z[win] = z[win]
        rgb[win] = p.color
    return rgb.reshape(*xs.shape, 3)


def grid_oracle(scene, kx, ky):
    """Mean of :func:`point_oracle` over the kx x ky subcell centres of every pixel."""
    xs, ys = np.meshgrid((np.arange(scene.width * kx) + 0.5) / kx, (np.arange(scene.height * ky) + 0.5) / ky)
    return point_oracle(scene, xs, ys).reshape(scene.height, ky, scene.width, kx, 3).mean(axis=(1, 3))


# --- every method -----------------------------------------------------------------


@pytest.mark.parametrize("name", ALL_METHODS)
def test_shape_dtype_finite(name):
    scene = random_scene(5)
    image = render(scene, name)
    assert image.shape == (scene.height, scene.width, 3)
    assert image.dtype == np.float64
    assert np.isfinite(image).all()
    assert image.min() >= -1e-6 and image.max() <= 1 + 1e-6


@pytest.mark.parametrize("name", ALL_METHODS)
def test_background_only_and_polygon_outside_the_frame(name):
    background = (0.25, 0.5, 0.75)  # exact in float32 too
    empty = scene_of([], background=background)
    outside = scene_of([rect(9, 1, 12, 4, color=(1, 0, 0)), rect(-5, -5, -1, 3, color=(0, 1, 0))],
                       background=background)
    for scene in (empty, outside):
        np.testing.assert_array_equal(render(scene, name), np.broadcast_to(background, scene.shape))


@pytest.mark.parametrize("name", ALL_METHODS)
def test_polygon_covering_the_frame_gives_its_colour_exactly(name):
    color = (0.75, 0.125, 0.5)
    scene = scene_of([rect(-3.3, -2.7, 11.1, 9.6, z=2.0, color=color),
                      {"color": [0.5, 0.5, 0.5], "vertices": [[-20, -10, 5], [40, -7, 5], [0, 30, 5]]}],
                     background=(0.0, 1.0, 0.0))
    # an 8-bit image holds the colour to its nearest byte
    atol = 0.5 / 255 if name in EIGHT_BIT_METHODS else 0.0
    np.testing.assert_allclose(render(scene, name), np.broadcast_to(color, scene.shape), rtol=0, atol=atol)


@pytest.mark.parametrize("name", ALL_METHODS)
def test_flat_shared_plane_later_polygon_in_front(name):
    # checked two pixels inside the later polygon's edges: post-filters (fxaa) blend the edge pixels
    scene = scene_of([rect(1, 1, 15, 11, z=3.0, color=(1, 0, 0)), rect(2, 2, 14, 10, z=3.0, color=(0, 0, 1))],
                     width=16, height=12)
    image = render(scene, name)
    np.testing.assert_array_equal(image[4:8, 4:12], np.broadcast_to([0.0, 0.0, 1.0], (4, 8, 3)))


def test_unknown_or_bad_options_fail_loudly():
    for spec in ("supersample:q=3", "supersample:k=0", "jitter:k=2,seed=-1", "point:k=2", "abuffer:k=4"):
        with pytest.raises(MethodError):
            resolve(spec)


# --- point sampling -----------------------------------------------------------------


@pytest.mark.parametrize("seed", range(4))
def test_point_matches_point_in_polygon_oracle(seed):
    scene = random_scene(40 + seed, n_tri=6, n_star=3)  # concave stars, triangles leaving the frame
    rows, cols = np.mgrid[0 : scene.height, 0 : scene.width]
    np.testing.assert_array_equal(render(scene, "point"), point_oracle(scene, cols + 0.5, rows + 0.5))


def test_supersample_samples_lie_on_the_regular_grid():
    scene = random_scene(7, n_tri=6, n_star=3)
    np.testing.assert_allclose(render(scene, "supersample:k=3"), grid_oracle(scene, 3, 3), rtol=0, atol=1e-12)


def test_point_is_supersample_k1():
    scene = random_scene(8)
    np.testing.assert_array_equal(render(scene, "point"), render(scene, "supersample:k=1"))


def test_supersample_converges_to_exact_as_k_grows():
    scene = random_scene(11, width=24, height=20, n_tri=8, n_star=3, tilt=0.2)
    exact = render(scene, "catmull")
    ks = np.array([2, 4, 8, 16])
    errors = np.array([rmse(render(scene, f"supersample:k={k}"), exact) for k in ks])
    assert (errors[1:] < errors[:-1] / 1.4).all(), errors
    # edges of generic slope: between 1/K (axis-aligned edges) and 1/K^2; measured ~K^-1.5
    order = -np.polyfit(np.log(ks), np.log(errors), 1)[0]
    assert 0.9 < order < 2.1, (order, errors)


def test_jitter_is_reproducible_and_seeds_differ():
    scene = random_scene(12)
    a = render(scene, "jitter:k=2,seed=3")
    np.testing.assert_array_equal(a, render(scene, "jitter:k=2,seed=3"))
    assert not np.array_equal(a, render(scene, "jitter:k=2,seed=4"))


@pytest.mark.parametrize("k", [2, 3, 5])
def test_jitter_samples_stay_in_their_strata(k):
    # edges on stratum boundaries: every seed sees exactly m of k columns (rows) covered
    m = 2 if k > 2 else 1
    vertical = scene_of([rect(-1, -1, 3 + m / k, 7, color=(1, 1, 1))])
    horizontal = scene_of([rect(-1, -1, 9, 2 + m / k, color=(1, 1, 1))])
    for seed in range(3):
        v = render(vertical, f"jitter:k={k},seed={seed}")[..., 0]
        h = render(horizontal, f"jitter:k={k},seed={seed}")[..., 0]
        np.testing.assert_allclose(v[:, 3], m / k, atol=1e-12)
        np.testing.assert_allclose(h[2, :], m / k, atol=1e-12)


def test_jitter_mean_over_seeds_converges_to_exact():
    scene = random_scene(13, n_tri=6, n_star=2, tilt=0.2)
    exact = render(scene, "catmull")
    images = np.array([render(scene, f"jitter:k=2,seed={s}") for s in range(64)])
    err4 = rmse(images[:4].mean(axis=0), exact)
    err64 = rmse(images.mean(axis=0), exact)
    assert err64 < err4 / 2.5, (err4, err64)  # ~ 1/sqrt(N): 4x expected
    assert err64 < 0.01


# --- A-buffer -------------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(3))
def test_abuffer_coverage_is_the_count_of_32_subcell_centres(seed):
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-1, 9, (3, 2))  # a single triangle, vertices at arbitrary sub-pixel spots
    scene = scene_of([{"color": [1, 1, 1], "vertices": np.column_stack([xy, [1, 2, 3]]).tolist()}])
    image = render(scene, "abuffer")[..., 0]
    steps = image * 32
    np.testing.assert_allclose(steps, np.round(steps), rtol=0, atol=1e-12)
    np.testing.assert_allclose(image, grid_oracle(scene, 8, 4)[..., 0], rtol=0, atol=1e-12)


def test_abuffer_close_to_exact_without_interpenetration():
    # polygons at distinct constant depths: the masks alone decide, error <= quantisation
    rng = np.random.default_rng(3)
    polys = [{"color": rng.uniform(0, 1, 3).tolist(),
              "vertices": np.column_stack([rng.uniform(-2, 14, (3, 2)), np.full(3, float(i))]).tolist()}
             for i in range(8)]
    scene = scene_of(polys, width=12, height=10)
    diff = np.abs(render(scene, "abuffer") - render(scene, "catmull"))
    assert diff.max() < 0.25 and diff.mean() < 0.02


def test_abuffer_blends_crossing_planes_by_carpenters_estimate():
    # two planes of opposite slope crossing at x = 1.3 inside pixel column 1: the estimate
    # (g.zmax - f.zmin) / (spans) is then exactly the visible fraction
    t = 1.3
    f = {"color": [1, 0, 0], "vertices": [[-1, -1, -1 - t], [4, -1, 4 - t], [4, 3, 4 - t], [-1, 3, -1 - t]]}
    g = {"color": [0, 0, 1], "vertices": [[-1, -1, t + 1], [4, -1, t - 4], [4, 3, t - 4], [-1, 3, t + 1]]}
    scene = scene_of([f, g], width=3, height=2)
    image = render(scene, "abuffer")
    np.testing.assert_allclose(image, render(scene, "catmull"), rtol=0, atol=1e-12)
    np.testing.assert_allclose(image[0, 1], [0.3, 0, 0.7], atol=1e-12)


def test_tilted_shared_plane_later_polygon_in_front():
    # on a tilted plane the big polygon's z range starts lower in the small one's edge
    # pixels, so the A-buffer sorts it first there and must still give the bits away
    def on_plane(color, xy):
        return {"color": color, "vertices": [[x, y, 0.3 * x - 0.2 * y + 4] for x, y in xy]}

    big = on_plane([1, 0, 0], [(0.5, 0.5), (7.5, 0.2), (7, 5.5), (0.2, 5)])
    small = on_plane([0, 0, 1], [(2.1, 2.2), (6.5, 1.5), (3.3, 4.5)])
    scene = scene_of([big, small])
    np.testing.assert_allclose(render(scene, "abuffer"), grid_oracle(scene, 8, 4), rtol=0, atol=1e-12)
    np.testing.assert_allclose(render(scene, "supersample:k=4"), grid_oracle(scene, 4, 4), rtol=0, atol=1e-12)
    for name in ("point", "jitter:k=3,seed=1"):
        np.testing.assert_array_equal(render(scene, name)[2, 3], [0.0, 0.0, 1.0])


# --- concave polygons and the frame, against the exact image ---------------------------


@pytest.mark.parametrize("name", ["supersample:k=16", "jitter:k=16,seed=2", "abuffer"])
def test_concave_and_out_of_frame_polygons_approach_exact(name):
    scene = random_scene(21, n_tri=5, n_star=4, tilt=0.0)  # no interpenetration: no z guesses
    diff = np.abs(render(scene, name) - render(scene, "catmull"))
    assert diff.mean() < 0.01 and diff.max() < 0.2


# --- skia -----------------------------------------------------------------------------


def test_skia_leaks_background_along_a_shared_edge_where_catmull_does_not():
    color = (1.0, 0.5, 0.0)
    diagonal = [[0.0, -1.0], [8.0, 7.0]]  # the shared edge crosses pixel interiors
    left = {"color": list(color), "vertices": [[-1, -1, 1], *[[x, y, 1] for x, y in diagonal], [-1, 7, 1]]}
    right = {"color": list(color), "vertices": [[9, -1, 2], [9, 7, 2], *[[x, y, 2] for x, y in diagonal[::-1]]]}
    scene = scene_of([left, right], background=(0.0, 0.0, 1.0))
    seam = np.array([[r, c] for r in range(6) for c in range(8) if c == r + 1])  # pixels the edge halves
    exact = render(scene, "catmull")
    np.testing.assert_allclose(exact, np.broadcast_to(color, scene.shape), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(render(scene, "supersample:k=4"), np.broadcast_to(color, scene.shape))
    painted = render(scene, "skia")
    leak = painted[seam[:, 0], seam[:, 1], 2]  # blue of the background shows through
    assert (leak > 0.1).all(), leak
    off_seam = np.abs(seam[:, None, :] - np.argwhere(np.ones((6, 8)))[None]).sum(-1).min(0) > 1
    np.testing.assert_array_equal(painted.reshape(-1, 3)[off_seam], np.broadcast_to(color, (off_seam.sum(), 3)))


def test_skia_single_polygon_close_to_exact():
    rng = np.random.default_rng(0)
    xy = rng.uniform(-1, 9, (3, 2))
    scene = scene_of([{"color": [1, 1, 1], "vertices": np.column_stack([xy, [1, 1, 1]]).tolist()}])
    # Skia's coverage is approximate: measured up to ~0.06 per pixel on this triangle
    # (and ~0.1, with 9% of the area lost, on thin slivers)
    diff = np.abs(render(scene, "skia") - render(scene, "catmull"))
    assert diff.max() < 0.08 and diff.mean() < 0.01, (diff.max(), diff.mean())


def test_skia_paints_back_to_front_by_depth_not_file_order():
    near_first = scene_of([rect(1, 1, 5, 5, z=1.0, color=(1, 0, 0)), rect(3, 2, 7, 6, z=9.0, color=(0, 1, 0))])
    image = render(near_first, "skia")
    np.testing.assert_array_equal(image[3, 4], [1.0, 0.0, 0.0])
    np.testing.assert_array_equal(image[5, 6], [0.0, 1.0, 0.0])
