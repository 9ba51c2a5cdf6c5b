"""The plain-Python pixel integrator (aaeval.catmull.reference) agrees with the native kernel.

Small grids: every pixel's visible area per polygon, from the reference run on each pixel
alone, against the native kernel's fragments (1e-12).
"""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.catmull import kernel_inputs, visible_fragments
from aaeval.catmull.reference import clip, pixel_areas
from tests.helpers.randomscenes import degenerate_scene, random_scene


def reference_areas(scene):
    start, length, x, y, planes, source, eps_z = kernel_inputs(scene)
    outlines = [list(zip(x[s:s + n], y[s:s + n])) for s, n in zip(start, length)]
    out = {}
    for row in range(scene.height):
        for col in range(scene.width):
            for k, a in pixel_areas(outlines, planes, col, row, eps_z).items():
                key = (row * scene.width + col, -1 if k == -1 else int(source[k]))
                out[key] = out.get(key, 0.0) + a
    return out


def native_areas(scene):
    f = visible_fragments(scene, threads=1)
    out = {}
    for pix, src, a in zip(f.pixel, f.polygon, f.area):
        out[(int(pix), int(src))] = out.get((int(pix), int(src)), 0.0) + a
    return out


@pytest.mark.parametrize("make", [lambda: random_scene(s, width=7, height=6, n_tri=4, n_star=1) for s in range(4)]
                         + [lambda: degenerate_scene(s) for s in range(3)])
def test_reference_integrator_matches_the_native_kernel(make):
    scene = make()
    ref, nat = reference_areas(scene), native_areas(scene)
    for key in ref.keys() | nat.keys():
        assert abs(ref.get(key, 0.0) - nat.get(key, 0.0)) <= 1e-12, key


def test_reference_clip_keeps_both_sides_and_marks_the_cut():
    square = [(0.0, 0.0, True), (1.0, 0.0, True), (1.0, 1.0, True), (0.0, 1.0, True)]
    left, right = clip(square, 1.0, 0.0, -0.25)  # x = 1/4
    assert sorted((x, y) for x, y, _ in left) == [(0.0, 0.0), (0.0, 1.0), (0.25, 0.0), (0.25, 1.0)]
    assert [free for x, y, free in left if x == 0.25 and y == 0.0] == [False]  # the edge along the cut is not free
    assert len(right) == 4
