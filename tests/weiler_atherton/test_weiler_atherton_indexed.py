"""Weiler-Atherton's indexed loop (the pieces a clip polygon meets found through a grid of
buckets, growing pieces halved, a piece away from every clip edge taken whole): the same
image as catmull and as the chain loop, on illustrations, interpenetrating and degenerate
scenes; and which loop the default takes."""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.renderers import render
from aaeval.scenes.generate import illustration_like, random_polygons, random_triangles
from aaeval.weiler_atherton import box_filter
from aaeval.weiler_atherton.hidden_surface import INDEXED_ABOVE, _Problem, visible_arrays
from tests.helpers.randomscenes import degenerate_scene, random_scene


def image(scene, indexed, window=0):
    return box_filter(scene, visible_arrays(scene, indexed=indexed, window=window))


@pytest.mark.parametrize("seed", [3, 4])
def test_indexed_loop_agrees_with_catmull_on_an_illustration_with_holes(seed):
    # long concave outlines, holes (convex pieces of one polygon), strokes: the case the
    # indexed loop is for (pieces halved past 64 vertices, whole pieces inside outlines)
    scene = illustration_like(seed, n=60, size=128)
    assert scene.holed and _Problem(scene).longest > INDEXED_ABOVE
    want = render(scene, "catmull")
    np.testing.assert_allclose(image(scene, True), want, atol=1e-10, rtol=0)
    np.testing.assert_allclose(image(scene, False), want, atol=1e-10, rtol=0)
    np.testing.assert_allclose(render(scene, "weiler-atherton"), want, atol=1e-10, rtol=0)


@pytest.mark.parametrize("seed", range(8))
def test_indexed_loop_agrees_on_interpenetrating_and_degenerate_scenes(seed):
    # crossing planes (pieces split along crossing lines, recursion on cyclic overlap)
    # and shared vertices, edges on pixel lines, equal depths
    for scene in (random_scene(seed), degenerate_scene(seed), random_polygons(30, 48, 40, seed=seed)):
        want = render(scene, "catmull")
        np.testing.assert_allclose(image(scene, True), want, atol=1e-9, rtol=0)


def test_indexed_loop_with_screen_subdivision():
    scene = illustration_like(5, n=40, size=96)
    np.testing.assert_allclose(image(scene, True, window=8), render(scene, "catmull"), atol=1e-10, rtol=0)


def test_default_takes_the_chain_loop_up_to_64_vertices_and_the_indexed_loop_beyond():
    small = random_triangles(50, 32, 32, seed=2)
    assert np.array_equal(render(small, "weiler-atherton"), image(small, False))  # the recorded bits
    big = illustration_like(6, n=30, size=96)
    assert np.array_equal(render(big, "weiler-atherton"), image(big, True))
    assert np.array_equal(render(big, "weiler-atherton:indexed=false"), image(big, False))


def test_indexed_option_is_checked():
    with pytest.raises(ValueError, match="indexed"):
        render(random_triangles(3, 8, 8), "weiler-atherton:indexed=maybe")
