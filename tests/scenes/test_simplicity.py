"""The O(n log n) self-crossing check agrees with the test of every pair of edges."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from aaeval.scenes import simplicity
from aaeval.scenes.simplicity import _brute_force, ring_contact, rings_contact


def _pairs(rings):
    """Every meeting pair by brute force, as (ring, edge, ring, edge)."""
    pts = np.concatenate(rings)
    sizes = [len(r) for r in rings]
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    a = np.arange(len(pts))
    b = a + 1
    b[first + np.array(sizes) - 1] = first
    ring_of = np.repeat(np.arange(len(rings)), sizes)
    hits = set()
    i, j = np.triu_indices(len(a), k=1)
    for k in range(len(i)):
        sub = _brute_force(pts, np.array([a[i[k]], a[j[k]]]), np.array([b[i[k]], b[j[k]]]))
        if sub is not None:
            e, f = i[k], j[k]
            hits.add((int(ring_of[e]), int(e - first[ring_of[e]]), int(ring_of[f]), int(f - first[ring_of[f]])))
    return hits


@pytest.fixture
def sweep_only(monkeypatch):
    """Send every ring, however small, through the sweep line."""
    monkeypatch.setattr(simplicity, "BRUTE_FORCE_EDGES", 0)


def _check(rings):
    expected = _pairs(rings)
    got = rings_contact(rings)
    if expected:
        assert got in expected, (got, sorted(expected)[:5])
    else:
        assert got is None, got


grid_points = st.lists(st.tuples(st.integers(0, 4), st.integers(0, 4)), min_size=3, max_size=9)


@pytest.mark.slow
@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(grid_points)
def test_random_grid_rings_agree_with_every_pair(sweep_only, points):
    # a 5x5 grid: collinear edges, vertices on edges, shared vertices, vertical edges galore
    ring = np.array(points, dtype=float)
    if np.any(np.all(ring == np.roll(ring, -1, axis=0), axis=1)):
        return  # zero-length edges are refused before this check
    _check([ring])


@pytest.mark.slow
@settings(max_examples=300, deadline=None)
@given(st.lists(grid_points, min_size=1, max_size=3))
def test_the_native_brute_force_names_the_pair_its_numpy_reference_names(rings):
    # small outlines go to first_meeting_pair (src/samplers/simplicity.cpp); _brute_force is
    # its plain numpy reference: the same first pair, or None from both
    rings = [np.array(r, dtype=np.float64) for r in rings]
    pts = np.concatenate(rings)
    sizes = np.array([len(r) for r in rings])
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    a = np.arange(len(pts), dtype=np.int64)
    b = a + 1
    b[first + sizes - 1] = first
    e, f = simplicity._native_first_pair(pts, a, b)
    assert (None if e < 0 else (e, f)) == _brute_force(pts, a, b)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(st.tuples(st.floats(0, 2 * math.pi), st.floats(0.1, 1.0)), min_size=3, max_size=14, unique_by=lambda t: t[0]),
       st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)), min_size=3, max_size=5))
@pytest.mark.slow
def test_star_rings_and_a_second_ring_agree_with_every_pair(sweep_only, star, other):
    # integer coordinates: orientation signs are exact, so ties (touching, collinear) are
    # decided the same way by both tests; near-ties within rounding may go either way
    star = sorted(star)
    ring = np.round([[1000 * r * math.cos(t), 1000 * r * math.sin(t)] for t, r in star])
    second = np.array(other, dtype=float) * 333
    for r in (ring, second):
        if np.any(np.all(r == np.roll(r, -1, axis=0), axis=1)):
            return
    _check([ring])
    _check([ring, second])


def test_hand_drawn_cases(sweep_only):
    square = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    assert ring_contact(square) is None
    assert ring_contact(np.array([[0, 0], [2, 2], [2, 0], [0, 2]], float)) == (0, 2)  # bow tie
    # a vertex on a non-adjacent edge (touching, no crossing)
    assert ring_contact(np.array([[0, 0], [4, 0], [4, 2], [2, 0.0], [0, 2]], float)) is not None
    # folding back along the previous edge
    assert ring_contact(np.array([[0, 0], [3, 0], [1, 0], [1, 1]], float)) is not None
    # a hole inside, a hole touching the outline, a hole crossing it
    hole = np.array([[0.5, 0.5], [1.5, 0.5], [1, 1.5]])
    assert rings_contact([square, hole]) is None
    assert rings_contact([square, hole - [0.5, 0]]) is not None
    assert rings_contact([square, hole + [1, 0]])[0:3:2] == (0, 1)


def _spiral(n: int) -> np.ndarray:
    """A simple, deliberately awkward ring: a tight double spiral of n vertices."""
    t = np.linspace(0.0, 40 * math.pi, n // 2, endpoint=False)
    outer = np.c_[(1 + t) * np.cos(t), (1 + t) * np.sin(t)]
    inner = np.c_[(1.5 + t) * np.cos(t), (1.5 + t) * np.sin(t)]
    return np.concatenate([outer, inner[::-1]])


def test_a_large_ring_goes_through_the_sweep_and_agrees_on_a_local_defect():
    ring = _spiral(20000)
    assert len(ring) > simplicity.BRUTE_FORCE_EDGES
    assert ring_contact(ring) is None
    bad = ring.copy()
    bad[5000] = bad[15000] * 0.5 + bad[14999] * 0.5  # now vertex 5000 lies on edge 14999
    hit = ring_contact(bad)
    assert hit is not None
    i, j = hit
    n = len(bad)
    two = _brute_force(bad, np.array([i, j]), np.array([(i + 1) % n, (j + 1) % n]))
    assert two is not None  # the pair reported really meets
    assert ring_contact(bad[::-1].copy()) is not None  # and the other way round


def test_a_100000_vertex_polygon_validates_in_seconds(tmp_path):
    import time

    from aaeval.scenes import parse_scene

    ring = _spiral(100_000) * 2 + 300
    doc = {"image": {"width": 600, "height": 600},
           "polygons": [{"color": [1, 1, 1], "vertices": [[float(x), float(y), 0.0] for x, y in ring]}]}
    start = time.process_time()
    scene = parse_scene(doc)
    assert len(scene.polygons[0].vertices) == 100_000
    assert time.process_time() - start < 30  # was: MemoryError (37 GiB asked)


def test_the_sweep_gives_the_answers_recorded_before_the_port():
    # tests/helpers/simplicity_cases.py: 491 outlines (random grids, floats, stars, holes, spirals,
    # near-duplicates) whose answers the numba sweep gave, sweep forced and as shipped
    import json

    from tests.helpers.simplicity_cases import DATA, answers

    expected = json.loads(DATA.read_text())
    got = dict(answers())
    assert len(expected) >= 300 and got.keys() == expected.keys()
    differing = sorted(key for key in expected if got[key] != expected[key])
    assert not differing, f"{len(differing)} of {len(expected)} answers differ, e.g. {differing[:5]}"


@pytest.mark.parametrize("bad", [
    lambda p, a, b, o, i: (p.astype(np.float32), a, b, o, i),
    lambda p, a, b, o, i: (p[:, :1], a, b, o, i),
    lambda p, a, b, o, i: (np.asfortranarray(np.c_[p, p])[:, :2], a, b, o, i),
    lambda p, a, b, o, i: (p, a, b + 1, o, i),
    lambda p, a, b, o, i: (p, a, b, o[:-1], i),
    lambda p, a, b, o, i: (p, a, b, np.zeros_like(o), i),
    lambda p, a, b, o, i: (p, a, b, o, i[::-1].copy()),
    lambda p, a, b, o, i: (np.where(p == p[0], np.nan, p), a, b, o, i),
])
def test_the_native_sweep_refuses_inconsistent_arrays(bad):
    from aaeval.native import samplers as _samplers

    p = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    a = np.arange(4, dtype=np.int64)
    b = np.array([1, 2, 3, 0], dtype=np.int64)
    o = np.lexsort((p[:, 1], p[:, 0])).astype(np.int64)
    i = np.array([3, 0, 1, 2], dtype=np.int64)
    assert _samplers.sweep(p, a, b, o, i) == (-1, -1)
    with pytest.raises(ValueError):
        _samplers.sweep(*bad(p, a, b, o, i))
