"""``Scene.window``: the scene seen through a pixel window renders as the full render's crop.

A box-filtered pixel depends only on what covers its own square, so the window's image is
the independent check: the full image rendered, then cropped. Flat scenes (animated, with
depth and with holes) and shaded ones (a point light and a spin, which the window must move
too), under the exact box filter, the exact shading and Amanatides' clamp."""

from __future__ import annotations

import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from aaeval.renderers import render
from aaeval.scenes import SceneError, load_scene, parse_scene

from tests.helpers.randomscenes import random_holed_document

SCENES = Path(__file__).resolve().parents[2] / "configs" / "scenes"


def _assert_window_is_crop(scene, spec, x0, y0, width, height, frames):
    window = scene.window(x0, y0, width, height)
    assert (window.width, window.height) == (width, height)
    for k in frames:
        full = render(scene, spec, frame=k)
        np.testing.assert_allclose(render(window, spec, frame=k), full[y0:y0 + height, x0:x0 + width],
                                   rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", ["picket_fence.toml", "interpenetrating.toml"])
def test_flat_window_is_the_full_renders_crop(name):
    scene = load_scene(SCENES / name)
    _assert_window_is_crop(scene, "catmull", 5, 2, 11, 5, frames=(0, scene.frames - 1))


def test_window_of_polygons_with_holes_is_the_crop():
    scene = parse_scene(random_holed_document(3), source="<holed 3>")
    _assert_window_is_crop(scene, "catmull", 3, 4, 9, 7, frames=(0, 2))


def _point_lit_spinning_cylinder() -> dict:
    document = tomllib.loads((SCENES / "shaded" / "thin-highlight.toml").read_text(encoding="utf-8"))
    # a point light near the window: shading that missed moving it would differ there
    document["shaded"]["light"] = {"type": "point", "position": [24.0, 14.0, 40.0]}
    document["shaded"]["cylinders"][0]["spin"] = {"axis": [0.0, 0.0, 1.0], "degrees": 0.7}
    return document


@pytest.mark.parametrize("spec", ["catmull:shading=exact", "catmull:specular=amanatides", "catmull:specular=none"])
def test_shaded_window_is_the_full_renders_crop(spec):
    scene = parse_scene(_point_lit_spinning_cylinder(), source="<point-lit cylinder>")
    _assert_window_is_crop(scene, spec, 12, 9, 13, 17, frames=(0, 5))


def test_the_window_moves_the_point_light():
    # the control: the same window with the light left where the full image has it is
    # another picture, so the crop check above turns on the light being moved
    scene = parse_scene(_point_lit_spinning_cylinder(), source="<point-lit cylinder>")
    window = scene.window(12, 9, 13, 17)
    unmoved = replace(window.extensions["shaded"], light=scene.extensions["shaded"].light)
    stale = replace(window, extensions={"shaded": unmoved})
    crop = render(scene, "catmull:shading=exact")[9:26, 12:25]
    assert np.abs(render(stale, "catmull:shading=exact") - crop).max() > 1e-3


@pytest.mark.parametrize("box", [(-1, 0, 4, 4), (0, 0, 0, 4), (30, 0, 11, 4), (0, 0, 4, 41), (0.5, 0, 4, 4)])
def test_a_window_outside_the_image_is_refused(box):
    scene = load_scene(SCENES / "shaded" / "thin-highlight.toml")
    with pytest.raises(SceneError, match="window"):
        scene.window(*box)
