"""Benchmark: Weiler-Atherton 1977 time against polygon count, with and without screen
subdivision, next to ``catmull`` on the same scenes.

Random interpenetrating triangles (``random_triangles``) in a 256x256 image; the median
wall-clock milliseconds per frame over repeated renders after a warm-up render (JIT
compilation excluded). W-A is object-space Python: its cost grows with the number of
polygon pairs that overlap, which screen subdivision (``window=N``: at most N polygons per
window) is meant to cut down, at the price of clipping every polygon to the window
borders it crosses (measured: the price is the larger one here); Catmull's cost grows
with the pixels each polygon covers.

    PYTHONPATH=. python3 benchmarks/bench_weiler_atherton.py [--counts 10 30 100 300 1000]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from aaeval.renderers import render
from aaeval.scenes.generate import random_triangles
from aaeval.weiler_atherton import visible_pieces


def median_seconds(scene, spec, repeats, budget):
    """Median wall time of ``render(scene, spec)`` after one warm-up render; fewer repeats
    when one render takes long (at least one, at most ``budget`` seconds in all)."""
    t0 = time.perf_counter()
    render(scene, spec)  # warm-up: JIT compilation, caches
    first = time.perf_counter() - t0
    n = max(1, min(repeats, int(budget / max(first, 1e-9))))
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        render(scene, spec)
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), n


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--counts", type=int, nargs="+", default=[10, 30, 100, 300, 1000])
    parser.add_argument("--windows", type=int, nargs="+", default=[0, 8, 32],
                        help="W-A screen subdivision settings (0: none)")
    parser.add_argument("--size", type=float, default=20.0, help="triangle extent in pixels")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--budget", type=float, default=20.0, help="seconds per measurement at most (roughly)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    width = height = 256
    specs = ["catmull"] + [f"weiler-atherton:window={w}" if w else "weiler-atherton" for w in args.windows]
    print(f"random triangles of extent {args.size:g} px in {width}x{height}, depth 0..100 (interpenetrating); "
          f"median wall ms after warm-up (runs in brackets), one core")
    header = f"{'n':>5} {'pieces':>7} " + " ".join(f"{s.replace('weiler-atherton', 'W-A'):>18}" for s in specs)
    print(header)
    for n in args.counts:
        scene = random_triangles(n, width, height, size=args.size, seed=args.seed)
        pieces = len(visible_pieces(scene))
        cells = []
        for spec in specs:
            sec, runs = median_seconds(scene, spec, args.repeats, args.budget)
            cells.append(f"{sec * 1e3:12.1f} ({runs:>2})")
        print(f"{n:5d} {pieces:7d} " + " ".join(f"{c:>18}" for c in cells), flush=True)


if __name__ == "__main__":
    main()
