"""The ``blend2d`` baseline against the exact renderer: 8-bit analytic coverage away from
seams, holes left empty, the painter's depth order and its conflation seam."""

from __future__ import annotations

import numpy as np

from aaeval.renderers import METHODS, render
from aaeval.scenes import parse_scene
from aaeval.scenes.generate import random_triangles

# 8-bit colour (1/2 step) plus Blend2D's 8-bit cell coverage (about 1 step per edge)
EIGHT_BIT = 3.0 / 255.0


def scene_of(polygons, width=16, height=12, background=(0.0, 0.0, 0.0)):
    return parse_scene({"image": {"width": width, "height": height, "background": list(background)},
                        "polygons": polygons})


def flat(points, z=1.0, color=(1.0, 1.0, 1.0)):
    return {"color": list(color), "vertices": [[float(x), float(y), z] for x, y in points]}


def test_blend2d_is_a_registered_method():
    assert "blend2d" in METHODS


def test_single_triangle_matches_exact_within_eight_bits():
    rng = np.random.default_rng(3)
    xy = rng.uniform(-1, 17, (3, 2))
    scene = scene_of([flat(xy, color=(0.9, 0.6, 0.3))], background=(0.1, 0.2, 0.7))
    diff = np.abs(render(scene, "blend2d") - render(scene, "catmull"))
    assert diff.max() < EIGHT_BIT, diff.max()


def test_holes_are_left_empty_whatever_their_winding():
    outline = [(1, 1), (15, 1), (15, 11), (1, 11)]
    for hole in ([(4, 3), (4, 9), (12, 9), (12, 3)], [(4, 3), (12, 3), (12, 9), (4, 9)]):
        polygon = flat(outline, color=(1.0, 0.5, 0.25))
        polygon["holes"] = [[[float(x), float(y), 1.0] for x, y in hole]]
        scene = scene_of([polygon])
        painted, exact = render(scene, "blend2d"), render(scene, "catmull")
        assert np.abs(painted - exact).max() < EIGHT_BIT
        np.testing.assert_array_equal(painted[5, 7], [0.0, 0.0, 0.0])  # inside the hole


def _away_from_edges(exact: np.ndarray) -> np.ndarray:
    """Pixels whose exact value equals all eight neighbours': no edge (so no seam) there."""
    padded = np.pad(exact, [(1, 1), (1, 1), (0, 0)], mode="edge")
    h, w = exact.shape[:2]
    same = np.ones((h, w), dtype=bool)
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            same &= np.abs(padded[dy:dy + h, dx:dx + w] - exact).max(axis=2) < 1e-12
    return same


def test_random_triangles_agree_with_exact_away_from_seams():
    scene = random_triangles(30, 64, 48, size=10.0, seed=5)
    painted, exact = render(scene, "blend2d"), render(scene, "catmull")
    diff = np.abs(painted - exact).max(axis=2)
    away = _away_from_edges(exact)
    assert away.sum() > 100
    assert diff[away].max() < 1.0 / 255.0  # only the 8-bit colour rounding
    assert np.median(diff) < EIGHT_BIT


def test_back_to_front_by_depth_and_background_leaks_through_a_shared_edge():
    near = flat([(1, 1), (8, 1), (8, 8), (1, 8)], z=1.0, color=(1, 0, 0))
    far = flat([(5, 3), (14, 3), (14, 10), (5, 10)], z=9.0, color=(0, 1, 0))
    image = render(scene_of([near, far]), "blend2d")
    np.testing.assert_array_equal(image[5, 6], [1.0, 0.0, 0.0])
    np.testing.assert_array_equal(image[9, 12], [0.0, 1.0, 0.0])
    diagonal = [(0.0, -1.0), (12.0, 11.0)]  # the shared edge halves pixels on its way
    left = flat([(-1, -1), *diagonal, (-1, 11)], z=1.0, color=(1.0, 0.5, 0.0))
    right = flat([(17, -1), (17, 11), *diagonal[::-1]], z=2.0, color=(1.0, 0.5, 0.0))
    seams = render(scene_of([left, right], background=(0.0, 0.0, 1.0)), "blend2d")
    leak = np.array([seams[r, r + 1, 2] for r in range(9)])
    assert (leak > 0.1).all(), leak
