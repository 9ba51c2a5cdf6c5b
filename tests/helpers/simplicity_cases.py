"""The outlines behind the simplicity check's same-answers regression.

Before the numba sweep line was replaced by the native one, its answers on every case here
were recorded (``tests/data/same_bits_simplicity.json``); the native check must give the
same answer on each (``tests/scenes/test_simplicity.py``). Record (only while the numba sweep still
exists) with ``python3 -m tests.helpers.simplicity_cases record``.

The cases: random rings on small integer grids (collinear edges, vertices on edges, shared
and repeated vertices, folds), random float rings, star rings with and without a defect,
outlines with holes inside, touching and crossing them, large spirals (the sweep at size)
with a vertex moved onto another edge, and near-degenerate float rings.
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[1] / "data" / "same_bits_simplicity.json"


def _spiral(n: int) -> np.ndarray:
    t = np.linspace(0.0, 40 * math.pi, n // 2, endpoint=False)
    outer = np.c_[(1 + t) * np.cos(t), (1 + t) * np.sin(t)]
    inner = np.c_[(1.5 + t) * np.cos(t), (1.5 + t) * np.sin(t)]
    return np.concatenate([outer, inner[::-1]])


def _star(rng, n: int, scale: float = 1000.0, integer: bool = True) -> np.ndarray:
    t = np.sort(rng.uniform(0, 2 * math.pi, n))
    r = rng.uniform(0.1, 1.0, n)
    ring = np.c_[scale * r * np.cos(t), scale * r * np.sin(t)]
    return np.round(ring) if integer else ring


def cases() -> Iterator[tuple[str, list[np.ndarray]]]:
    """``(case id, rings)`` in a fixed order."""
    for seed in range(150):
        rng = np.random.default_rng(seed)
        n = int(rng.integers(3, 12))
        side = int(rng.integers(2, 6))
        yield f"grid-{seed}", [rng.integers(0, side, (n, 2)).astype(float)]
    for seed in range(60):
        rng = np.random.default_rng(1000 + seed)
        yield f"float-{seed}", [rng.uniform(-1, 1, (int(rng.integers(3, 30)), 2))]
    for seed in range(60):
        rng = np.random.default_rng(2000 + seed)
        star = _star(rng, int(rng.integers(3, 40)), integer=seed % 2 == 0)
        second = rng.integers(-3, 4, (int(rng.integers(3, 6)), 2)).astype(float) * 333
        yield f"star-{seed}", [star]
        yield f"star-pair-{seed}", [star, second]
    for seed in range(30):
        rng = np.random.default_rng(3000 + seed)
        star = _star(rng, 300 + 50 * seed, integer=True)
        yield f"big-star-{seed}", [star]
        bad = star.copy()
        k = int(rng.integers(0, len(bad)))
        m = int(rng.integers(0, len(bad)))
        bad[k] = 0.5 * (bad[m] + bad[(m + 1) % len(bad)])
        yield f"big-star-defect-{seed}", [bad]
        hole = _star(rng, 20, scale=50.0, integer=True)
        yield f"big-star-hole-{seed}", [star, hole]
        yield f"big-star-hole-shifted-{seed}", [star, hole + [float(rng.integers(-900, 900)), 0.0]]
    square = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    hole = np.array([[0.5, 0.5], [1.5, 0.5], [1, 1.5]])
    yield "square", [square]
    yield "bow-tie", [np.array([[0, 0], [2, 2], [2, 0], [0, 2]], float)]
    yield "touch", [np.array([[0, 0], [4, 0], [4, 2], [2, 0.0], [0, 2]], float)]
    yield "fold", [np.array([[0, 0], [3, 0], [1, 0], [1, 1]], float)]
    yield "repeat", [np.array([[0, 0], [3, 0], [3, 3], [0, 0], [-3, 3]], float)]
    yield "hole-inside", [square, hole]
    yield "hole-touching", [square, hole - [0.5, 0]]
    yield "hole-crossing", [square, hole + [1, 0]]
    yield "empty", []
    for n in (2000, 6000, 20000):
        ring = _spiral(n)
        yield f"spiral-{n}", [ring]
        bad = ring.copy()
        bad[n // 4] = bad[3 * n // 4] * 0.5 + bad[3 * n // 4 - 1] * 0.5
        yield f"spiral-defect-{n}", [bad]
        yield f"spiral-defect-reversed-{n}", [bad[::-1].copy()]
        near = ring.copy()
        near[n // 3] += 1e-13
        yield f"spiral-nudged-{n}", [near]
    for seed in range(20):
        rng = np.random.default_rng(4000 + seed)
        base = _star(rng, 400, integer=False)
        a, b = sorted(rng.integers(0, len(base), 2))
        base[a] = base[b] + rng.uniform(-1e-12, 1e-12, 2)  # near-duplicate vertex
        yield f"near-duplicate-{seed}", [base]


def answers() -> Iterator[tuple[str, list]]:
    """``(case id, [sweep answer, default answer])``: the sweep forced for every size, and
    the check as shipped (brute force up to BRUTE_FORCE_EDGES edges)."""
    from aaeval.scenes import simplicity

    saved = simplicity.BRUTE_FORCE_EDGES
    for case_id, rings in cases():
        try:
            simplicity.BRUTE_FORCE_EDGES = 0
            sweep = simplicity.rings_contact(rings)
        finally:
            simplicity.BRUTE_FORCE_EDGES = saved
        default = simplicity.rings_contact(rings)
        yield case_id, [None if sweep is None else list(sweep), None if default is None else list(default)]


def record() -> Path:
    DATA.parent.mkdir(exist_ok=True)
    DATA.write_text(json.dumps(dict(answers()), indent=0, sort_keys=True) + "\n")
    return DATA


if __name__ == "__main__":
    if sys.argv[1:] != ["record"]:
        sys.exit("usage: python3 -m tests.helpers.simplicity_cases record")
    print(record())
