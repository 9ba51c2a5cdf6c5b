"""Exact pixel filters (aaeval.filters, ``catmull:filter=F``) against independent references.

- the registry's piece coefficients against Mitsuba's formulas written out in
  ``filter_oracle.py``;
- the native stages on tiny hand-made polygons against closed forms;
- whole images against GEOS visible regions integrated by area quadrature, to 1e-9;
- the properties across every filter: partition of unity, the intensity sum under
  sub-pixel translation, values outside [0, 1] from negative lobes, unknown names.
"""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys
from math import factorial
from pathlib import Path

import numpy as np
import pytest

from aaeval.filters import FILTERS, axis_weights, get_filter
from aaeval.filters.exact import filtered_image, rings_from_pieces
from aaeval.catmull.filtered import filter_sums, filtered_pixels, knot_grid_sums
from aaeval.filters.evaluate import profile_array, profile_at
from aaeval.filters.registry import profile_args
from aaeval.filters.integrate import (accumulate_rings, column_part_integrals, combine_cells, combine_cells_numpy,
                                     filter_kernel_args,
                                     piece_integrals)
from aaeval.renderers import MethodError, render, resolve
from aaeval.catmull import resolve_flat, visible_fragments
from aaeval.scenes import load_scene, parse_scene
from tests.helpers.filter_oracle import PROFILES, filtered_oracle, triangle_rule
from tests.helpers.randomscenes import random_scene

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "configs" / "scenes"
SMOOTH = [name for name in FILTERS if name != "box"]
EXACT = 1e-9


# --- the registry --------------------------------------------------------------------


@pytest.mark.parametrize("name", list(FILTERS))
def test_profile_matches_mitsubas_formula(name):
    radius, reference = PROFILES[name]
    filt = get_filter(name)
    t = np.linspace(-2.6, 2.6, 5201) + 1e-7  # off the knots (box: 1/2 is an edge)
    assert filt.radius == radius
    np.testing.assert_allclose(filt.profile(t), reference(t), rtol=0, atol=1e-14)


@pytest.mark.parametrize("name", list(FILTERS))
def test_integral_and_partition_of_unity(name):
    filt = get_filter(name)
    t = np.linspace(0.0, 1.0, 101)[:-1] + 1e-7
    total = sum(filt.profile(t + i) for i in range(-4, 5))
    assert np.ptp(total) < 1e-14 if filt.partition_of_unity else np.ptp(total) > 1e-3
    from scipy.integrate import quad

    numeric = sum(quad(lambda x: float(filt.profile(x)), a, a + 0.5, epsabs=1e-14)[0] for a in np.arange(-3, 3, 0.5))
    assert abs(filt.integral(-3.0, 3.0) - numeric) < 1e-12


def test_border_pixels_collect_less_weight():
    # the tent at the image border keeps 7/8 of its weight per axis (field notes, Mitsuba)
    np.testing.assert_allclose(axis_weights(get_filter("tent"), 6), [0.875, 1, 1, 1, 1, 0.875], atol=1e-15)
    assert np.all(axis_weights(get_filter("box"), 4) == 1.0)


def test_unknown_filter_lists_the_valid_ones():
    with pytest.raises(ValueError, match="valid filters: box, tent, bspline, mitchell, catmullrom, gaussian"):
        get_filter("lanczos")
    with pytest.raises(MethodError, match="'lanczos' is not one of \\['box', 'tent'"):
        resolve("catmull:filter=lanczos")


# --- the native stages on hand-made polygons ----------------------------------------


def _integrals(name, xy, ox=0.0, oy=0.0):
    kind, radius, k, alpha, bias = filter_kernel_args(get_filter(name))
    xy = np.asarray(xy, dtype=np.float64)
    out = np.empty((k, k))
    piece_integrals(np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]), 0, len(xy), ox, oy,
                    kind, radius, k, alpha, bias, out)
    return out


@pytest.mark.parametrize("name", ["tent", "bspline", "mitchell"])
def test_a_strip_pieces_column_parts_integrate_as_their_geos_cut_polygons(name):
    # a render's front pieces are integrated column by column without being cut out; each
    # part must give what the polygon GEOS cuts to the column gives (the one-node-at-a-time
    # route), on concave pieces spanning several columns of one row strip
    from shapely.geometry import Polygon as ShapelyPolygon, box

    kind, radius, k, alpha, bias = filter_kernel_args(get_filter(name))
    rng = np.random.default_rng(7)
    compared = 0
    for _ in range(40):
        m = int(rng.integers(3, 9))
        angles = np.sort(rng.uniform(0, 2 * np.pi, m))
        radii = rng.uniform(0.5, 2.5, m)
        xy = np.column_stack([5.0 + radii * np.cos(angles), 3.0 + 0.5 * np.sin(angles) * rng.uniform(0.2, 1.0, m)])
        xy[:, 1] = np.clip(xy[:, 1], 2.5, 3.5)  # inside the row strip [2.5, 3.5]: cell row centred at 3
        strip = ShapelyPolygon(xy)
        if not strip.is_valid or strip.area < 1e-3:
            continue
        xy = np.asarray(strip.exterior.coords)[:-1]
        if strip.exterior.is_ccw is False:
            xy = xy[::-1]
        xs, ys = np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1])
        for col in range(int(np.floor(xs.min())), int(np.ceil(xs.max()))):
            part = strip.intersection(box(col, 2.5, col + 1, 3.5))
            fast = np.full((k, k), np.nan)
            assert column_part_integrals(xs, ys, 0, len(xs), col, col + 0.5, 3.0, kind, radius, k, alpha, bias, fast)
            expected = np.zeros((k, k))
            for poly in getattr(part, "geoms", [part]):
                if poly.is_empty or poly.area == 0.0:
                    continue
                ring = np.asarray(poly.exterior.coords)[:-1]
                expected += _integrals(name, ring if poly.exterior.is_ccw else ring[::-1], col + 0.5, 3.0)
            np.testing.assert_allclose(fast, expected, rtol=0, atol=1e-15)
            compared += 1
    assert compared > 100


def test_the_gaussian_has_no_column_part_form():
    kind, radius, k, alpha, bias = filter_kernel_args(get_filter("gaussian"))
    out = np.zeros((k, k))
    square = np.array([0.2, 0.8, 0.8, 0.2]), np.array([0.2, 0.2, 0.8, 0.8])
    assert not column_part_integrals(*square, 0, 4, 0, 0.5, 0.5, kind, radius, k, alpha, bias, out)


def test_moments_of_the_whole_cell():
    # ∫ u^a du over [-1/2, 1/2] is 0 for odd a and 2^-a / (a + 1) for even a
    one = np.array([0.0 if a % 2 else 0.5**a / (a + 1) for a in range(4)])
    square = [[2.5, 6.5], [3.5, 6.5], [3.5, 7.5], [2.5, 7.5]]
    np.testing.assert_allclose(_integrals("mitchell", square, 3.0, 7.0), np.outer(one, one), atol=1e-16)


def test_moments_of_a_right_triangle():
    # ∫∫ u^a v^b over u, v >= 0, u + v <= h is a! b! h^(a+b+2) / (a+b+2)!
    h = 0.4
    tri = [[0.0, 0.0], [h, 0.0], [0.0, h]]
    expected = np.array([[factorial(a) * factorial(b) * h ** (a + b + 2) / factorial(a + b + 2) for b in range(4)]
                         for a in range(4)])
    np.testing.assert_allclose(_integrals("bspline", tri), expected, rtol=1e-14, atol=0)
    # the other orientation (a hole) subtracts
    np.testing.assert_allclose(_integrals("bspline", tri[::-1]), -expected, rtol=1e-14, atol=0)
    # the tent needs moments up to degree 1 only
    np.testing.assert_allclose(_integrals("tent", tri), expected[:2, :2], rtol=1e-14)


def test_gaussian_cell_integrals_are_products_of_1d_integrals():
    from scipy.integrate import quad

    _, k = PROFILES["gaussian"]
    square = [[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]]
    one = np.array([quad(lambda u: float(k(u + p + 0.5)), -0.5, 0.5, epsabs=1e-15)[0] for p in range(-2, 2)])
    np.testing.assert_allclose(_integrals("gaussian", square), np.outer(one, one), rtol=0, atol=1e-15)


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def test_gaussian_edge_quadrature_converged():
    # a sliver triangle with long edges across the cell, against a 40 x 40 area rule
    rng = np.random.default_rng(4)
    _, k = PROFILES["gaussian"]
    for _ in range(5):
        tri = rng.uniform(-0.5, 0.5, (3, 2))
        if _cross(tri[1] - tri[0], tri[2] - tri[0]) < 0:
            tri = tri[::-1]
        s, t, w = triangle_rule(40)
        e1, e2 = tri[1] - tri[0], tri[2] - tri[0]
        x = tri[0, 0] + s * e1[0] + t * e2[0]
        y = tri[0, 1] + s * e1[1] + t * e2[1]
        jac = abs(_cross(e1, e2))
        ref = np.array([[np.sum(w * jac * k(x + p + 0.5) * k(y + q + 0.5)) for q in range(-2, 2)] for p in range(-2, 2)])
        np.testing.assert_allclose(_integrals("gaussian", tri), ref, rtol=0, atol=1e-14)


def test_rings_cut_on_the_knot_grid():
    # a concave ring with a hole spanning many cells: per-cell integrals sum to the whole,
    # and the hole's share is removed
    outer = [[0.3, 0.2], [5.7, 0.6], [5.2, 4.9], [2.9, 2.1], [0.4, 4.4]]
    hole = [[3.5, 1.0], [3.3, 1.6], [4.4, 1.5]]  # opposite orientation
    rings = rings_from_pieces([outer, hole], [[1, 0, 0], [1, 0, 0]])
    kind, radius, k, alpha, bias = filter_kernel_args(get_filter("tent"))
    acc = np.zeros((6, 7, k, k, 4))
    accumulate_rings(rings.x, rings.y, rings.start, rings.length, rings.weights, 6, 5, kind, radius, k, alpha, bias, acc)

    def shoelace(p):
        p = np.asarray(p)
        return 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])

    assert abs(acc[..., 0, 0, 3].sum() - (shoelace(outer) + shoelace(hole))) < 1e-13
    # first moments about the cells' centres add up to the first moment about the origin
    m = np.arange(7)[None, :]
    first_x = (acc[..., 1, 0, 3] + m * acc[..., 0, 0, 3]).sum()
    poly = np.asarray(outer)
    cross = poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1]
    hx = np.asarray(hole)
    cross_h = hx[:, 0] * np.roll(hx[:, 1], -1) - np.roll(hx[:, 0], -1) * hx[:, 1]
    expected = (np.sum((poly[:, 0] + np.roll(poly[:, 0], -1)) * cross) + np.sum((hx[:, 0] + np.roll(hx[:, 0], -1)) * cross_h)) / 6
    assert abs(first_x - expected) < 1e-12


def test_combine_cells_places_pieces_on_the_right_pixels():
    # one unit of coverage-moment in cell (m, n) = (2, 1): pixel i gets piece p = m - i - 1
    filt = get_filter("tent")
    acc = np.zeros((4, 5, 2, 2, 1))
    acc[1, 2, 0, 0, 0] = 1.0  # area 1, centred on the cell: tent pieces at s = 0 give 1/2
    out = combine_cells(acc, filt, 4, 3)[..., 0]
    expected = np.zeros((3, 4))
    expected[0:2, 1:3] = 0.25
    np.testing.assert_allclose(out, expected, atol=1e-16)


@pytest.mark.parametrize("name", SMOOTH)
def test_native_combine_and_fused_sums_keep_numpys_bits(name):
    # the native x-then-y contraction (and its fused form, rows of cells contracted inside
    # the kernel's sink, whole cells of one colour from a per-colour cache) add in numpy's
    # einsum order: the same bits, on any number of threads, with 3 or 4 channels
    filt = get_filter(name)
    for seed, (w, h, n) in enumerate([(23, 17, 12), (40, 40, 40)]):
        scene = random_scene(seed, w, h, n_tri=n, n_star=3)
        cells = knot_grid_sums(scene, filt, threads=1)
        reference = combine_cells_numpy(cells, filt, w, h)
        assert combine_cells(cells, filt, w, h).tobytes() == reference.tobytes()
        assert combine_cells(cells, filt, w, h, threads=3).tobytes() == reference.tobytes()
        for threads in (1, 2, 3):
            assert filter_sums(scene, filt, threads).tobytes() == reference.tobytes()
        four = np.concatenate([cells, cells[..., :1] * 0.5], axis=-1)
        assert combine_cells(four, filt, w, h).tobytes() == combine_cells_numpy(four, filt, w, h).tobytes()


@pytest.mark.parametrize("name", SMOOTH)
def test_film_division_in_the_kernel_keeps_numpys_bits(name):
    # filtered_pixels divides by the film's weights inside the native call; numpy's
    # sums / (wy[:, None] * wx[None, :])[..., None] is the reference, on any thread count
    filt = get_filter(name)
    for seed, (w, h, n) in enumerate([(23, 17, 12), (1, 6, 3), (40, 40, 40)]):
        scene = random_scene(seed, w, h, n_tri=n, n_star=3)
        denom = axis_weights(filt, h)[:, None] * axis_weights(filt, w)[None, :]
        reference = filter_sums(scene, filt, 1) / denom[..., None]
        for threads in (1, 2):
            assert filtered_pixels(scene, filt, threads).tobytes() == reference.tobytes()


def test_profile_evaluation_is_native_and_numba_free():
    import aaeval.filters.evaluate as evaluate

    assert "numba" not in evaluate.__dict__
    t = np.linspace(-2.5, 2.5, 1001)
    for name in FILTERS:
        args = profile_args(get_filter(name))
        values = profile_array(*args, t)
        assert values[500] == profile_at(*args, 0.0)
        np.testing.assert_allclose(values, get_filter(name).profile(t), rtol=0, atol=0)


# --- whole images against the GEOS oracle --------------------------------------------

SHIPPED = ["catmull_fig1", "interpenetrating", "khan_concave_a", "abutting", "picket_fence", "beyond_image"]


@pytest.mark.slow
@pytest.mark.parametrize("name", SMOOTH)
@pytest.mark.parametrize("scene_name", SHIPPED)
def test_shipped_scenes_agree_with_oracle(name, scene_name):
    scene = load_scene(SCENES / f"{scene_name}.toml")
    if scene.frames > 1:
        scene = scene.at_frame(scene.frames // 2 - 1)
    image = render(scene, f"catmull:filter={name}")
    reference = filtered_oracle(scene, name, order=4 if name != "gaussian" else 14)
    assert np.abs(image - reference).max() < EXACT


@pytest.mark.slow
@pytest.mark.parametrize("name", SMOOTH)
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_interpenetrating_scenes_agree_with_oracle(name, seed):
    scene = random_scene(seed, width=12, height=9)
    image = render(scene, f"catmull:filter={name}")
    reference = filtered_oracle(scene, name, order=4 if name != "gaussian" else 14)
    assert np.abs(image - reference).max() < EXACT


@pytest.mark.parametrize("name", ["tent", "mitchell", "gaussian"])
@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_degenerate_scenes_agree_with_oracle(name, seed):
    # shared vertices, edges on pixel boundaries, abutting mesh triangles, shared planes
    from tests.helpers.randomscenes import degenerate_scene

    scene = degenerate_scene(seed)
    reference = filtered_oracle(scene, name, order=4 if name != "gaussian" else 14)
    assert np.abs(render(scene, f"catmull:filter={name}") - reference).max() < EXACT


@pytest.mark.parametrize("name", ["mitchell", "gaussian"])
def test_polygons_with_holes_agree_with_oracle(name):
    from tests.helpers.randomscenes import random_holed_scene

    scene = random_holed_scene(2)
    assert scene.holed
    reference = filtered_oracle(scene, name, order=4 if name != "gaussian" else 14)
    assert np.abs(render(scene, f"catmull:filter={name}") - reference).max() < EXACT


def test_box_oracle_is_todays_catmull():
    # the oracle's box path is the plain GEOS area average, and catmull:filter=box is today's
    scene = random_scene(5, width=12, height=9)
    image = render(scene, "catmull:filter=box")
    assert np.array_equal(image, resolve_flat(scene, visible_fragments(scene, centroids=False)))
    assert np.array_equal(image, render(scene, "catmull"))
    assert np.abs(image - filtered_oracle(scene, "box")).max() < EXACT


def test_oracle_detects_a_wrong_filter():
    # negative control: Mitchell and Catmull-Rom differ well above the tolerance
    scene = random_scene(1, width=12, height=9)
    assert np.abs(render(scene, "catmull:filter=mitchell") - filtered_oracle(scene, "catmullrom")).max() > 1e-3


# --- properties --------------------------------------------------------------------


def _on_plane(xy, a, b, c):
    return [[x, y, a * x + b * y + c] for x, y in xy]


def _moving_scene():
    """Interpenetrating shapes at least 2R + 1 pixels from the border in every frame."""
    concave = [[8.2, 5.5], [9.7, 5.1], [10.3, 7.6], [8.9, 6.4], [8.0, 7.9]]
    return parse_scene(
        {
            "image": {"width": 20, "height": 16, "background": [0.2, 0.1, 0.05]},
            "animation": {"frames": 8, "translate": [0.137, 0.071]},
            "polygons": [
                {"color": [1, 0.5, 0], "vertices": [[5.3, 5.2, 0], [13.1, 6.4, 2], [7.7, 10.9, 1]]},
                {"color": [0, 0.7, 1], "vertices": [[6.1, 9.6, 2], [12.8, 5.3, 0], [11.4, 10.2, 1]]},
                {"color": [0.3, 1, 0.3], "vertices": _on_plane(concave, 0.3, -0.4, 1.0)},
            ],
        }
    )


def intensity_sums(name):
    scene = _moving_scene()
    return np.array([render(scene, f"catmull:filter={name}", frame=f).sum() for f in range(scene.frames)])


@pytest.mark.parametrize("name", [n for n in FILTERS if FILTERS[n].partition_of_unity])
def test_intensity_sum_invariant_under_translation(name):
    sums = intensity_sums(name)
    assert np.ptp(sums) < 1e-12 * max(1.0, abs(sums).max())


def test_gaussian_intensity_sum_varies_and_is_measured():
    # Gaussian profiles do not sum to one over integer shifts: the sum moves with the scene
    sums = intensity_sums("gaussian")
    variation = np.ptp(sums) / sums.mean()
    assert 1e-6 < variation < 1e-2, variation


@pytest.mark.parametrize("name", ["mitchell", "catmullrom"])
def test_negative_lobes_leave_unit_range_and_png_clips(name, tmp_path):
    from aaeval.imageio import linear_to_srgb8, save_image

    scene = parse_scene({"image": {"width": 8, "height": 6}, "polygons": [
        {"color": [1, 1, 1], "vertices": [[3.0, -1, 0], [9, -1, 0], [9, 7, 0], [3.0, 7, 0]]}]})
    image = render(scene, f"catmull:filter={name}")
    assert image.min() < -1e-3 and image.max() > 1 + 1e-3  # undershoot and overshoot at the edge
    save_image(tmp_path / "x.npy", image)
    assert np.array_equal(np.load(tmp_path / "x.npy"), image)
    srgb = linear_to_srgb8(image)
    assert srgb.min() == 0 and srgb.max() == 255


def test_cli_rejects_unknown_filter(tmp_path):
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}
    out = tmp_path / "x.npy"
    proc = subprocess.run([sys.executable, "-m", "aaeval", "render", str(SCENES / "catmull_fig1.toml"), "-m",
                           "catmull:filter=lanczos", "-o", str(out)], capture_output=True, text=True, env=env)
    assert proc.returncode == 2
    assert "box, tent" in proc.stderr or "'box', 'tent'" in proc.stderr
    assert "Traceback" not in proc.stderr and not out.exists()


@pytest.mark.parametrize("name", SMOOTH)
@pytest.mark.parametrize("seed", [7, 8])
def test_catmull_and_weiler_atherton_pieces_agree(name, seed):
    # two exact sources of visible pieces (the Catmull kernel on the knot grid, the W-A
    # object-space solver cut on it afterwards) through the same integration
    from aaeval.filters.exact import weiler_atherton_rings

    scene = random_scene(seed, width=10, height=8)
    filt = get_filter(name)
    assert np.abs(filtered_image(scene, filt) - filtered_image(scene, filt, weiler_atherton_rings(scene))).max() < 1e-12
