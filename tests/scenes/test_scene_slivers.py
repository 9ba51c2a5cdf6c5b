"""A valid polygon thinner than rounding can measure is a scene, not an error; an
outline exactly on one line still is."""

from __future__ import annotations

import pytest
import shapely

from aaeval.renderers import render
from aaeval.scenes import SceneError, parse_scene

SLIVER = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 2e-16, 0.0]]


def test_the_sliver_is_valid_and_has_area_for_geos():
    outline = shapely.Polygon([v[:2] for v in SLIVER])
    assert outline.is_valid and outline.area == pytest.approx(1e-16)


@pytest.mark.parametrize("method", ["catmull", "weiler-atherton", "point", "abuffer", "skia"])
def test_a_geos_valid_sliver_renders_as_nearly_empty(method):
    scene = parse_scene({"image": {"width": 4, "height": 2}, "polygons": [{"color": [1, 1, 1], "vertices": SLIVER}]})
    assert abs(render(scene, method).sum()) <= 1e-12


@pytest.mark.parametrize("vertices", [
    [[0, 0, 0], [1, 1, 0], [2, 2, 0]],
    [[0, 0, 0], [2, 0, 0], [1, 0, 0]],
    [[0.1, 0.2, 0.3], [0.2, 0.4, 0.6], [0.4, 0.8, 1.2]],
])
def test_an_outline_exactly_on_one_line_is_still_refused(vertices):
    with pytest.raises(SceneError, match="degenerate polygon"):
        parse_scene({"image": {"width": 4, "height": 2}, "polygons": [{"color": [1, 1, 1], "vertices": vertices}]})
