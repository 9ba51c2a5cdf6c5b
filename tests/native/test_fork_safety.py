"""A render in a forked child after a threaded render in the parent (issue: the thread
pool was inherited without its threads, and the child waited forever)."""

from __future__ import annotations

import multiprocessing

import numpy as np
import pytest

from aaeval.catmull import render_flat
from aaeval.scenes.generate import random_triangles


def _render_sum(threads: int) -> float:
    return float(render_flat(random_triangles(40, 64, 64, seed=2), threads=threads).sum())


@pytest.mark.parametrize("threads", [0, 1, 2, 3])
def test_a_forked_child_renders_after_a_threaded_parent(threads):
    scene = random_triangles(40, 64, 64, seed=2)
    expected = float(render_flat(scene, threads=2).sum())  # the parent's pool now exists
    with multiprocessing.get_context("fork").Pool(1) as pool:
        result = pool.apply_async(_render_sum, (threads,))
        got = result.get(timeout=10)  # multiprocessing.TimeoutError when the child hangs
    assert np.isclose(got, expected, rtol=0, atol=1e-9)
