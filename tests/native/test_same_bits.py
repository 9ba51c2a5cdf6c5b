"""The kernels give the recorded bits on the regression's scenes.

How the expected digests were recorded and checked: ``tests/helpers/same_bits.py``; a mismatch
names the scene and method.
"""

from __future__ import annotations

import json

import pytest

from tests.helpers.same_bits import DATA, FAMILY_METHODS, digests_of, matches

RECORDED = sorted(f for f in FAMILY_METHODS if (DATA / f"same_bits_{f}.json").exists())


@pytest.mark.slow
@pytest.mark.xdist_group("same_bits")  # one worker: the scenes and filter images are made once
@pytest.mark.parametrize("family", RECORDED)
def test_native_images_have_the_recorded_bits(family):
    expected = json.loads((DATA / f"same_bits_{family}.json").read_text())
    got = dict(digests_of(family))
    assert len(expected) >= 100 * len(FAMILY_METHODS[family]) // 2
    differing = sorted(key for key in expected if not matches(got.get(key), expected[key]))
    assert got.keys() == expected.keys()
    assert not differing, f"{len(differing)} of {len(expected)} images differ, e.g. {differing[:5]}"
