"""The candidate filters of :func:`aaeval.weiler_atherton.near_ties.tie_groups` (similar
slopes, then similar depths at one reference point) may keep too many polygons, never too
few: the groups they give equal the definition's, every box-overlapping pair compared, on
stacks of near-coplanar quads (some pairs tied, some not), layered illustrations (distinct
and repeated depths), random interpenetrating scenes and the shipped scenes."""

from __future__ import annotations

import numpy as np
import pytest

from aaeval.native.weiler_atherton import components
from aaeval.scenes.generate import illustration_like
from aaeval.weiler_atherton.near_ties import NEAR_COPLANAR, _near_pairs, tie_groups
from tests.helpers.randomscenes import random_scene
from tests.helpers.same_bits import near_tie_stack, scenes


def _by_definition(boxes, planes, sources, eps_z):
    first, rows, near = _near_pairs(boxes, planes, sources, eps_z)
    component = components(len(sources), first, rows)
    tied = np.isin(component, np.unique(component[first[near]]))
    return sources[tied], sources[~tied]


def _inputs(scene, eps_z):
    polys = scene.polygons
    boxes = np.array([[p.vertices[:, 0].min(), p.vertices[:, 1].min(), p.vertices[:, 0].max(),
                       p.vertices[:, 1].max()] for p in polys])
    planes = np.array([p.plane for p in polys], dtype=np.float64)
    return boxes, planes, np.arange(len(polys), dtype=np.int64)


def _offset_stack(seed, k=6):
    """Quads over one plane at depths 0, d, 2d, ...: with d just inside and just outside
    the near-coplanar band, and one plane repeated (no pair of identical planes is tied)."""
    rng = np.random.default_rng(seed)
    eps_z = 1e-9
    step = NEAR_COPLANAR * eps_z * rng.choice([0.3, 0.9, 1.1, 3.0])
    polys = []
    for i in range(k):
        x0, y0 = rng.uniform(0, 4, 2)
        xy = np.array([[x0, y0], [x0 + 9, y0 + 1], [x0 + 8, y0 + 8], [x0 - 1, y0 + 7]])
        z = 5.0 + 0.01 * xy[:, 0] - 0.02 * xy[:, 1] + step * (i // 2)
        polys.append({"color": [0.5, 0.5, 0.5], "vertices": np.column_stack([xy, z]).tolist()})
    from aaeval.scenes import parse_scene

    return parse_scene({"image": {"width": 13, "height": 12}, "polygons": polys}, source="<offsets>"), eps_z


CASES = ([(f"near-tie-{s}", lambda s=s: (near_tie_stack(s, k=2 + s % 5), None)) for s in range(12)]
         + [(f"offsets-{s}", lambda s=s: _offset_stack(s)) for s in range(12)]
         + [(f"random-{s}", lambda s=s: (random_scene(s), None)) for s in range(6)]
         + [(f"illustration-{s}", lambda s=s: (illustration_like(s, size=256), None)) for s in (1, 3)])


def _check(scene, eps_z):
    for eps in ([eps_z] if eps_z else [1e-9, 1e-12, 1e-6]):
        boxes, planes, sources = _inputs(scene, eps)
        got = tie_groups(boxes, planes, sources, eps)
        want = _by_definition(boxes, planes, sources, eps)
        assert np.array_equal(np.sort(got[0]), np.sort(want[0])) and np.array_equal(np.sort(got[1]), np.sort(want[1]))
    return want


@pytest.mark.slow
@pytest.mark.parametrize("name,make", CASES, ids=[c[0] for c in CASES])
def test_tie_groups_equal_the_pairwise_definition(name, make):
    _check(*make())


def test_the_cases_hold_tied_and_untied_stacks():
    tied = [len(_check(*make())[0]) > 0 for name, make in CASES if name.startswith(("near-tie", "offsets"))]
    assert any(tied) and not all(tied)


def test_shipped_scenes():
    for name, make in scenes():
        if name.startswith("shipped:"):
            scene = make()
            if len(scene.polygons) > 1:
                _check(scene, None)
