"""``supersample`` and ``jitter`` through a filter converge to ``catmull`` with that filter.

The samplers splat every sample into each pixel its filter reaches and divide by the
weight collected (Mitsuba's film), so with more samples they must approach the exact
image; the box keeps today's per-pixel mean.
"""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.filters import FILTERS
from aaeval.renderers import MethodError, render, resolve
from tests.helpers.randomscenes import random_scene

SMOOTH = [name for name in FILTERS if name != "box"]


def rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


@pytest.mark.parametrize("name", SMOOTH)
def test_supersample_converges_to_exact(name):
    scene = random_scene(3, width=12, height=9)
    exact = render(scene, f"catmull:filter={name}")
    coarse, fine = (rmse(render(scene, f"supersample:k={k},filter={name}"), exact) for k in (4, 32))
    # edge error falls about as 1/k: x8 samples per side, at least 4x less error
    assert fine < coarse / 4 and fine < 5e-4
    # negative control: a different filter stays far away however many samples
    other = "catmullrom" if name != "catmullrom" else "bspline"
    assert rmse(render(scene, f"supersample:k=32,filter={other}"), exact) > 10 * fine


@pytest.mark.parametrize("name", ["tent", "mitchell", "gaussian"])
def test_jitter_seeds_average_towards_exact(name):
    scene = random_scene(4, width=12, height=9)
    exact = render(scene, f"catmull:filter={name}")
    images = np.stack([render(scene, f"jitter:k=4,seed={s},filter={name}") for s in range(16)])
    single = np.mean([rmse(im, exact) for im in images])
    # independent seeds: averaging 16 divides the error by about 4
    assert rmse(images.mean(axis=0), exact) < single / 2.5


def test_box_keeps_the_plain_per_pixel_mean():
    scene = random_scene(6, width=12, height=9)
    assert np.array_equal(render(scene, "supersample:k=3"), render(scene, "supersample:k=3,filter=box"))
    assert np.array_equal(render(scene, "jitter:k=3,seed=2"), render(scene, "jitter:k=3,seed=2,filter=box"))


def test_constant_image_stays_constant_at_the_border():
    # the film divides by the weight collected, so a flat field stays flat in border pixels
    from aaeval.scenes import parse_scene

    scene = parse_scene({"image": {"width": 5, "height": 4, "background": [0.3, 0.6, 0.9]}, "polygons": []})
    for name in SMOOTH:
        np.testing.assert_allclose(render(scene, f"supersample:k=4,filter={name}"), np.broadcast_to([0.3, 0.6, 0.9], (4, 5, 3)), atol=1e-14)


@pytest.mark.parametrize("spec", ["abuffer:filter=tent", "skia:filter=mitchell"])
def test_box_only_methods_refuse_other_filters(spec):
    with pytest.raises(MethodError, match=r"is not one of \['box'\]"):
        resolve(spec)
