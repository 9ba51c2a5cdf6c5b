"""Catmull 1978 renderer: exactness against independent references and properties."""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.renderers import render
from aaeval.catmull import kernel_inputs, visible_fragments
from aaeval.scenes import parse_scene

from tests.helpers.oracle import oracle_image
from tests.helpers.randomscenes import degenerate_scene, random_scene, star, with_plane


# seed 55 once left a rounding spike standing in for a whole region
@pytest.mark.slow
@pytest.mark.parametrize("seed", range(60))
def test_random_interpenetrating_scenes_match_geos(seed):
    scene = random_scene(seed)
    np.testing.assert_allclose(render(scene, "catmull"), oracle_image(scene), rtol=0, atol=1e-9)


@pytest.mark.parametrize("seed", range(4))
def test_many_polygons_in_one_pixel_match_geos(seed):
    # a dense tangle: every pixel holds many polygons, several of them interpenetrating
    scene = random_scene(100 + seed, width=5, height=4, n_tri=14, n_star=4, tilt=3.0)
    np.testing.assert_allclose(render(scene, "catmull"), oracle_image(scene), rtol=0, atol=1e-9)


def test_fan_of_thin_polygons_meeting_in_one_pixel():
    apex = np.array([4.37, 3.61])
    rng = np.random.default_rng(7)
    polys = []
    n = 24
    for k in range(n):
        a0, a1 = 2 * np.pi * k / n, 2 * np.pi * (k + 1) / n
        xy = np.array([apex, apex + 9 * np.array([np.cos(a0), np.sin(a0)]), apex + 9 * np.array([np.cos(a1), np.sin(a1)])])
        polys.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": with_plane(xy, rng, tilt=0.2)})
    scene = parse_scene({"image": {"width": 9, "height": 8}, "polygons": polys})
    np.testing.assert_allclose(render(scene, "catmull"), oracle_image(scene), rtol=0, atol=1e-9)


# Two of random_triangles(2000, 128, 128, size=20, seed=0): in pixel (47, 120) the thin
# triangle's piece (2.6e-6) ends up alone with the background square clipped to the same
# lines, which rounding made larger by 1.4e-17 (5e-9 of it); the integrator took the
# piece for a rounding remnant and gave it to the background (2.6e-6 off GEOS; 32000
# triangles at 512x512 had 38 such pixels, up to 9e-6).
THIN_TRIANGLE_PAIR = [
    [[121.59121344283813, 37.495345613333555, 92.23505260955798], [120.15598198316243, 48.032504973056675, 48.110897428738774],
     [121.18811914530288, 40.45450747535086, 88.22542859538872]],
    [[123.46459486786716, 40.228853443887, 51.5209213444222], [116.47652323635079, 54.45130983936481, 69.74528846984505],
     [104.9016547020138, 56.89012878216202, 79.10796470308121]],
]


def test_tiny_region_a_thin_triangle_covers_is_not_dropped_as_a_remnant():
    scene = parse_scene({"image": {"width": 122, "height": 48},
                         "polygons": [{"color": c, "vertices": v} for c, v in zip([[1, 0, 0], [0, 0, 1]], THIN_TRIANGLE_PAIR)]})
    np.testing.assert_allclose(render(scene, "catmull"), oracle_image(scene), rtol=0, atol=1e-9)


@pytest.mark.parametrize("seed", range(20))
def test_summed_coverage_equals_area_for_concave_polygons(seed):
    rng = np.random.default_rng(seed)
    xy = star(rng, rng.uniform([8, 8], [24, 24]), 0.3, 7.5, int(rng.integers(4, 30)))
    scene = parse_scene(
        {"image": {"width": 32, "height": 32}, "polygons": [{"color": [1, 1, 1], "vertices": with_plane(xy, rng)}]}
    )
    x, y = xy[:, 0], xy[:, 1]
    area = 0.5 * abs(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    covered = render(scene, "catmull")[..., 0].sum()
    assert covered == pytest.approx(area, rel=1e-9)


def test_pixel_areas_sum_to_one_and_centroids_lie_inside():
    scene = random_scene(3, n_tri=8, n_star=3)
    frags = visible_fragments(scene)
    per_pixel = np.bincount(frags.pixel, weights=frags.area, minlength=scene.width * scene.height)
    np.testing.assert_allclose(per_pixel, 1.0, atol=1e-12)
    col = frags.pixel % scene.width
    row = frags.pixel // scene.width
    assert np.all((frags.cx >= col - 1e-9) & (frags.cx <= col + 1 + 1e-9))
    assert np.all((frags.cy >= row - 1e-9) & (frags.cy <= row + 1 + 1e-9))


def test_translation_keeps_intensity_sum_where_point_sampling_does_not():
    rng = np.random.default_rng(5)
    xy = star(rng, (20.0, 16.0), 1.0, 6.0, 9)
    doc = {
        "image": {"width": 40, "height": 32},
        "animation": {"frames": 16, "translate": [0.173, 0.0961]},
        "polygons": [{"color": [0.9, 0.5, 0.2], "vertices": with_plane(xy, rng)}],
    }
    scene = parse_scene(doc)
    sums = [render(scene, "catmull", frame=k).sum() for k in range(scene.frames)]
    assert (max(sums) - min(sums)) / np.mean(sums) < 1e-12

    # point sampling at pixel centres, a few lines independent of the renderer
    from matplotlib.path import Path

    centres = np.column_stack([g.ravel() + 0.5 for g in np.meshgrid(np.arange(40), np.arange(32))])
    point_sums = []
    for k in range(scene.frames):
        inside = Path(scene.at_frame(k).polygons[0].xy).contains_points(centres)
        point_sums.append(inside.sum())
    assert (max(point_sums) - min(point_sums)) / np.mean(point_sums) > 1e-3


def test_coplanar_overlap_later_polygon_in_front():
    square = [[1, 1, 5], [7, 1, 5], [7, 6, 5], [1, 6, 5]]
    tri = [[0.5, 0.5, 5], [7.5, 0.7, 5], [3.3, 6.6, 5]]
    a = parse_scene({"image": {"width": 8, "height": 7}, "polygons": [
        {"color": [1, 0, 0], "vertices": square}, {"color": [0, 1, 0], "vertices": tri}]})
    b = parse_scene({"image": {"width": 8, "height": 7}, "polygons": [
        {"color": [0, 1, 0], "vertices": tri}, {"color": [1, 0, 0], "vertices": square}]})
    for scene in (a, b):
        np.testing.assert_allclose(render(scene, "catmull"), oracle_image(scene), atol=1e-12)
    assert not np.allclose(render(a, "catmull"), render(b, "catmull"))


def _tilted_stack(k, tilt):
    """k copies of one square, the first vertex's depth raised by i * tilt: every plane
    through the line where the others meet, neighbours within eps_z, the ends not."""
    return parse_scene({"image": {"width": 41, "height": 41}, "polygons": [
        {"color": [i / k, 0.5, 0.5], "vertices": [[4, 4, 1 + i * tilt], [40, 5, 1], [39, 40, 1], [3, 41, 1]]}
        for i in range(k)]})


def test_near_coplanar_stack_is_covered_exactly_by_polygons_within_eps_z_of_the_front():
    # the issue-13 fuzz case: the shared-plane tie is not transitive here, and the
    # integrator's move-to-front went round in cycles until MAX_STEPS (12 s), leaving
    # pixels uncovered (0.014 of a full pixel at (4, 4))
    k = 120
    scene = _tilted_stack(k, 1e-12)
    frags = visible_fragments(scene, threads=1)
    flat = visible_fragments(_tilted_stack(k, 0.0), threads=1)
    n = scene.width * scene.height
    cover = [np.bincount(f.pixel[f.polygon >= 0], f.area[f.polygon >= 0], n) for f in (frags, flat)]
    np.testing.assert_allclose(cover[0], cover[1], atol=1e-12)
    # what each pixel shows is within the shared-plane tolerance of the nearest depth there
    eps_z = 1e-11 * (1.0 + np.abs(scene.arrays.vertices[:, 2]).max())
    seen = frags.polygon >= 0
    planes = scene.arrays.planes
    z = planes[:, 0] * frags.cx[seen, None] + planes[:, 1] * frags.cy[seen, None] + planes[:, 2]
    assert np.max(z[np.arange(seen.sum()), frags.polygon[seen]] - z.min(axis=1)) < 1.5 * eps_z


def test_polygon_covering_whole_image_and_beyond():
    doc = {"image": {"width": 6, "height": 5, "background": [0, 0, 1]},
           "polygons": [{"color": [0.25, 0.5, 0.75], "vertices": [[-50, -40, 1], [90, -40, 1], [90, 70, 1], [-50, 70, 1]]}]}
    image = render(parse_scene(doc), "catmull")
    np.testing.assert_allclose(image, np.broadcast_to([0.25, 0.5, 0.75], image.shape), atol=0)


def test_empty_scene_is_background():
    scene = parse_scene({"image": {"width": 3, "height": 2, "background": [0.1, 0.2, 0.3]}})
    np.testing.assert_array_equal(render(scene, "catmull"), np.broadcast_to([0.1, 0.2, 0.3], (2, 3, 3)))


def test_jagged_mode_gives_full_pixels_of_polygon_colours():
    scene = random_scene(9)
    jag = render(scene, "catmull-jagged")
    colours = np.vstack([[p.color for p in scene.polygons], scene.background])
    # every pixel is exactly one of the scene's colours: no blending
    distance = np.abs(jag.reshape(-1, 1, 3) - colours[None]).max(axis=2).min(axis=1)
    assert distance.max() == 0.0
    assert not np.allclose(jag, render(scene, "catmull"))


@pytest.mark.parametrize("seed", range(40))
def test_degenerate_placements_match_geos(seed):
    scene = degenerate_scene(seed)
    np.testing.assert_allclose(render(scene, "catmull"), oracle_image(scene), rtol=0, atol=1e-9)


@pytest.mark.parametrize("method", ["catmull", "catmull-jagged"])
def test_output_is_bitwise_identical_for_every_thread_count(method):
    # 70 rows: three bands of rows, unevenly shared between the threads
    scene = random_scene(7, width=60, height=70, n_tri=30, n_star=5)
    images = [render(scene, f"{method}:threads={t}") for t in (1, 2, 3, 0)]
    for image in images[1:]:
        assert np.array_equal(image, images[0])


def test_image_written_by_the_kernel_equals_resolved_fragments_bitwise():
    from aaeval.catmull import resolve_flat

    scene = random_scene(11, width=40, height=45, n_tri=20, n_star=4)
    fragments = visible_fragments(scene, centroids=False, threads=2)
    assert np.array_equal(render(scene, "catmull"), resolve_flat(scene, fragments))
    assert all(np.array_equal(a, b) for a, b in zip(fragments, visible_fragments(scene, centroids=False, threads=1)))


@pytest.mark.parametrize("seed", range(3))
def test_polygons_crossing_row_bands_match_geos(seed):
    # the kernel runs bands of 32 rows, each starting afresh at its top row: tall
    # interpenetrating polygons crossing rows 32 and 64 must come out exact
    rng = np.random.default_rng(200 + seed)
    polys = []
    for _ in range(6):
        xy = np.column_stack([rng.uniform(-2, 12, 3), rng.uniform(-3, 75, 3)])
        polys.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": with_plane(xy, rng, tilt=0.5)})
    polys.append({"color": [0.2, 0.4, 0.6], "vertices": with_plane(star(rng, (5.0, 36.0), 3.0, 30.0, 9), rng, 0.3)})
    scene = parse_scene({"image": {"width": 10, "height": 72}, "polygons": polys})
    np.testing.assert_allclose(render(scene, "catmull"), oracle_image(scene), rtol=0, atol=1e-9)


@pytest.mark.parametrize("n, threads", [(64, 2), (5, 2), (7, 3), (1, 2), (3, 4), (10, 10)])
def test_threads_take_every_band_once_far_apart(n, threads):
    from aaeval.catmull import far_apart

    order = far_apart(n, threads)
    assert sorted(order) == list(range(n))
    if n >= 2 * threads:  # the first bands taken come from different runs of the image
        assert order[1] - order[0] >= n // threads


def test_triangles_wind_as_the_general_path_winds_them():
    # kernel_inputs turns polygons of one small size on a 2D path; nearly collinear
    # triangles (area at rounding level) must turn the same way as on the per-vertex path,
    # which a quadrilateral added to the scene forces
    rng = np.random.default_rng(5)
    polys = []
    for _ in range(400):
        p0, p1 = rng.uniform(0, 30, 2), rng.uniform(0, 30, 2)
        p2 = p0 + rng.uniform(-2, 2) * (p1 - p0) + rng.normal(0, 10.0 ** rng.integers(-12, 1), 2)
        a, b, c = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(50, 100)  # a plane of its own
        polys.append({"color": [1, 0, 0], "vertices": [[*p, c + a * p[0] + b * p[1]] for p in (p0, p1, p2)]})
    quad = {"color": [0, 1, 0], "vertices": [[40, 40, 5], [41, 40, 5], [41, 41, 5], [40, 41, 5]]}
    size = {"width": 32, "height": 32}
    triangles = kernel_inputs(parse_scene({"image": size, "polygons": polys}))
    mixed = kernel_inputs(parse_scene({"image": size, "polygons": [*polys, quad]}))
    kept = len(triangles[0])
    assert kept > 200
    np.testing.assert_array_equal(triangles[2], mixed[2][:3 * kept])
    np.testing.assert_array_equal(triangles[3], mixed[3][:3 * kept])
