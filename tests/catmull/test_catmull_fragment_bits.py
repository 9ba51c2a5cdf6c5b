"""The native Catmull kernel's fragments keep the numba kernel's bits on the same-bits scenes.

The digests were recorded by the numba kernel before it was deleted
(``tests/helpers/catmull_fragment_bits.py``); a mismatch names the scene.
"""

from __future__ import annotations

import json

import pytest

from tests.helpers.catmull_fragment_bits import FILE, fragment_digests


@pytest.mark.slow
def test_native_fragments_have_the_recorded_bits():
    expected = json.loads(FILE.read_text())
    got = dict(fragment_digests())
    # 120 scenes x 2: the 115 the numba kernel recorded and five shipped since (the 21-bar
    # moire fence, the thin and wide highlight cylinders, the held-out tilted and upright
    # thin cylinders), added alone by `... add`
    assert got.keys() == expected.keys() and len(expected) == 240
    differing = sorted(key for key in expected if got[key] != expected[key])
    assert not differing, f"{len(differing)} of {len(expected)} differ, e.g. {differing[:5]}"
