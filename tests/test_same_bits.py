"""The native kernels give the numba kernels' bits on the regression's 115 scenes (issue 20).

The expected digests were recorded by the numba kernels before they were deleted
(``tests/same_bits.py``); a mismatch names the scene and method.
"""

from __future__ import annotations

import json

import pytest

import numpy as np

from tests.same_bits import (DATA, FAMILY_METHODS, FILTERS, FAST_ROUTE_TOLERANCE, digests_of, made, matches, recorded_image,
                              render_recorded, scenes)

RECORDED = sorted(f for f in FAMILY_METHODS if (DATA / f"same_bits_{f}.json").exists())


@pytest.mark.slow
@pytest.mark.xdist_group("same_bits")  # one worker: the scenes and recorded filter images are made once
@pytest.mark.parametrize("family", RECORDED)
def test_native_images_have_the_recorded_bits(family):
    expected = json.loads((DATA / f"same_bits_{family}.json").read_text())
    got = dict(digests_of(family))
    assert len(expected) >= 100 * len(FAMILY_METHODS[family]) // 2
    differing = sorted(key for key in expected if not matches(got.get(key), expected[key]))
    assert got.keys() == expected.keys()
    assert not differing, f"{len(differing)} of {len(expected)} images differ, e.g. {differing[:5]}"


@pytest.mark.slow
@pytest.mark.xdist_group("same_bits")
@pytest.mark.parametrize("filt", FILTERS)
def test_the_filters_fast_route_stays_within_rounding_of_the_recorded_images(filt):
    # the exact filters' one explained difference (tests/same_bits.py): the method's own
    # route against the recorded one, which holds the recorded bits, on every scene
    spec = f"catmull:filter={filt}"
    worst, where, changed = 0.0, None, 0
    for scene_id, make in scenes():
        scene = made(scene_id, make)
        try:
            recorded = recorded_image(scene_id, scene, spec)
        except (ValueError, NotImplementedError):
            continue
        image = render_recorded(scene, spec, recorded=False)
        gap = float(np.abs(image - recorded).max())
        changed += gap > 0.0
        if gap > worst:
            worst, where = gap, scene_id
    assert worst <= FAST_ROUTE_TOLERANCE, f"{spec} differs by {worst:.3g} on {where}"
    assert changed > 0  # the shortcut is taken (else the two routes were never compared)
