"""Weiler-Atherton's solver where its grid of buckets, its halving of growing pieces and its
whole pieces inside outlines are at work (long concave outlines, holes, crossing planes):
the same image as catmull on illustrations, interpenetrating and degenerate scenes."""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.renderers import render
from aaeval.scenes.document import parse_scene
from aaeval.scenes.generate import illustration_like, random_polygons
from aaeval.weiler_atherton import box_filter
from aaeval.weiler_atherton.hidden_surface import visible_arrays
from tests.helpers.randomscenes import degenerate_scene, random_scene


def image(scene, window=0):
    return box_filter(scene, visible_arrays(scene, window=window))


def longest_outline(scene) -> int:
    return int(scene.arrays.length.max())


@pytest.mark.parametrize("seed", [3, 4])
def test_solver_agrees_with_catmull_on_an_illustration_with_holes(seed):
    # long concave outlines, holes (convex pieces of one polygon), strokes: pieces halved
    # past 64 vertices, whole pieces inside outlines
    scene = illustration_like(seed, n=60, size=128)
    assert scene.holed and longest_outline(scene) > 64
    want = render(scene, "catmull")
    np.testing.assert_allclose(image(scene), want, atol=1e-10, rtol=0)
    np.testing.assert_allclose(render(scene, "weiler-atherton"), want, atol=1e-10, rtol=0)


@pytest.mark.parametrize("seed", range(8))
def test_solver_agrees_on_interpenetrating_and_degenerate_scenes(seed):
    # crossing planes (pieces split along crossing lines, recursion on cyclic overlap)
    # and shared vertices, edges on pixel lines, equal depths
    for scene in (random_scene(seed), degenerate_scene(seed), random_polygons(30, 48, 40, seed=seed)):
        want = render(scene, "catmull")
        np.testing.assert_allclose(image(scene), want, atol=1e-9, rtol=0)


def ring(rng, centre, radius, k, z):
    """A star-shaped ring of k vertices about centre, with depths z(x, y)."""
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    r = radius * (1 + 0.3 * np.sin(rng.integers(2, 6) * t + rng.uniform(0, 6)))
    xy = np.column_stack([centre[0] + r * np.cos(t), centre[1] + r * np.sin(t)])
    return np.column_stack([xy, z(xy)]).tolist()


def tilted_blobs_with_holes(seed, n=40, size=128):
    """Blobs of up to 100 vertices, most with a hole, each on its own tilted plane: the
    planes cross, so pieces lie partly in front of a polygon with holes and partly behind."""
    rng = np.random.default_rng(seed)
    polygons = []
    for i in range(n):
        a, b, z0 = *rng.uniform(-0.3, 0.3, 2), float(n - i) + 20
        z = lambda xy: z0 + a * (xy[:, 0] - size / 2) + b * (xy[:, 1] - size / 2)
        centre, radius = rng.uniform(0, size, 2), size * rng.uniform(0.08, 0.3)
        outer = ring(rng, centre, radius, int(rng.integers(24, 100)), z)
        polygon = {"color": rng.uniform(0, 1, 3).tolist(), "vertices": outer}
        if rng.uniform() < 0.7:
            polygon["holes"] = [ring(rng, centre, 0.3 * radius, int(rng.integers(8, 40)), z)[::-1]]
        polygons.append(polygon)
    return parse_scene({"image": {"width": size, "height": size}, "polygons": polygons}, source=f"tilted blobs {seed}")


@pytest.mark.parametrize("seed", range(3))
def test_solver_agrees_on_polygons_with_holes_on_crossing_planes(seed):
    # a piece wholly behind a polygon with holes is clipped by its whole outline (rings
    # rebuilt from its convex parts) once; one partly in front, by each part
    scene = tilted_blobs_with_holes(seed)
    assert len(scene.holed) > 10 and longest_outline(scene) > 64
    want = render(scene, "catmull")
    np.testing.assert_allclose(image(scene), want, atol=1e-10, rtol=0)


def test_solver_with_screen_subdivision():
    scene = illustration_like(5, n=40, size=96)
    np.testing.assert_allclose(image(scene, window=8), render(scene, "catmull"), atol=1e-10, rtol=0)
