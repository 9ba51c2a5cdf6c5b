"""The native Weiler-Atherton kernels give the recorded arrays: clipper outputs on random
polygon pairs, the solver's visible pieces, the near-tie rule's flat arrays and the box
filter (how they were recorded: ``tests/helpers/same_bits_wa_clipper.py``)."""

from __future__ import annotations

import json

import pytest

from tests.helpers.same_bits_wa_clipper import RECORD, cases


@pytest.mark.slow
def test_native_clipper_and_solver_give_the_recorded_arrays():
    expected = json.loads(RECORD.read_text())
    got = dict(cases())
    assert got.keys() == expected.keys()
    assert sum(k.startswith("clip-") for k in expected) >= 500
    differing = sorted(k for k in expected if got[k] != expected[k])
    assert not differing, f"{len(differing)} of {len(expected)} differ, e.g. {differing[:5]}"
