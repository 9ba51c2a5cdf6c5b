"""The ground-truth cache is keyed by the pixel filter: a group judged through filter F gets
``mitsuba:filter=F`` from the cache, never the box image."""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.groundtruth.cache import groundtruth, groundtruth_key
from aaeval.scenes import parse_scene

SCENE = {"image": {"width": 6, "height": 5},
         "polygons": [{"color": [1, 0.5, 0], "vertices": [[0.3, 0.4, 1], [5.2, 1.1, 1], [2.1, 4.6, 1]]}]}


def test_the_filter_is_part_of_the_key_and_the_box_key_is_unchanged():
    scene = parse_scene(SCENE, source="<t>")
    box = groundtruth_key(scene, spp=16, sampler="stratified", seed=0)
    assert groundtruth_key(scene, spp=16, sampler="stratified", seed=0, filter="box") == box
    keys = {groundtruth_key(scene, spp=16, sampler="stratified", seed=0, filter=f)
            for f in ("box", "tent", "mitchell", "gaussian")}
    assert len(keys) == 4


def test_a_filtered_truth_is_cached_and_differs_from_the_box(tmp_path, monkeypatch):
    import mitsuba  # noqa: F401 - a dependency: a broken install fails here
    monkeypatch.setenv("AAEVAL_CACHE_DIR", str(tmp_path))
    scene = parse_scene(SCENE, source="<t>")
    tent = groundtruth(scene, spp=16, filter="tent")
    assert not tent.hit
    again = groundtruth(scene, spp=16, filter="tent")
    assert again.hit and np.array_equal(again.image, tent.image)
    box = groundtruth(scene, spp=16)
    assert not box.hit and not np.allclose(box.image, tent.image)
