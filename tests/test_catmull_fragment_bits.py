"""The native Catmull kernel's fragments keep the numba kernel's bits on the 115 scenes.

The digests were recorded by the numba kernel before it was deleted
(``tests/catmull_fragment_bits.py``); a mismatch names the scene.
"""

from __future__ import annotations

import json

import pytest

from tests.catmull_fragment_bits import FILE, fragment_digests


@pytest.mark.slow
def test_native_fragments_have_the_recorded_bits():
    expected = json.loads(FILE.read_text())
    got = dict(fragment_digests())
    assert got.keys() == expected.keys() and len(expected) == 230
    differing = sorted(key for key in expected if got[key] != expected[key])
    assert not differing, f"{len(differing)} of {len(expected)} differ, e.g. {differing[:5]}"
