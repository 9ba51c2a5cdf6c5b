"""Benchmark: Weiler-Atherton 1977 against ``catmull`` on the same scenes, interleaved.

Random interpenetrating triangles (``random_triangles``, 40 px boxes, depth 0..100) in a
512x512 image, at several polygon counts. After one warm-up render per method (JIT
compilation excluded), the methods are rendered in turn, round after round (A B A B ...),
so that load from other processes falls on all alike; the table gives the median
wall-clock and process-CPU milliseconds per frame with the spread (smallest-largest wall
time) and each method's ratio of medians (wall and CPU) to ``catmull:threads=1``. W-A is
single-threaded, so that is the one-core comparison; ``catmull`` with its default (every
core) is listed too. The goal: at 2000 triangles W-A within 3x of catmull.

W-A's object-space cost grows with the number of overlapping polygon pairs it clips
(native: ``src/weiler_atherton/clipper.cpp``, ``solver.cpp``); catmull's with
the pixels each polygon covers. ``--windows`` adds W-A with screen subdivision
(``window=N``: at most N polygons per window).

    PYTHONPATH=. python3 benchmarks/bench_weiler_atherton.py [--counts 300 2000] [--rounds 7]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from aaeval import registries
from aaeval.renderers import render
from aaeval.scenes.generate import random_triangles
from aaeval.weiler_atherton import visible_arrays
from smoke import smallest

registries.load()  # a program fills the registries once, before it renders


def interleaved(scene, specs, rounds):
    """{spec: (wall seconds, cpu seconds) per round}, the specs rendered in turn."""
    for spec in specs:
        render(scene, spec)  # warm-up: JIT compilation and caches
    times = {spec: ([], []) for spec in specs}
    for _ in range(rounds):
        for spec in specs:
            w0, c0 = time.perf_counter(), time.process_time()
            render(scene, spec)
            times[spec][0].append(time.perf_counter() - w0)
            times[spec][1].append(time.process_time() - c0)
    return times


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--counts", type=int, nargs="+", default=[300, 2000])
    parser.add_argument("--windows", type=int, nargs="*", default=[],
                        help="also W-A with screen subdivision at these settings (0: none)")
    parser.add_argument("--size", type=float, default=40.0, help="triangle extent in pixels")
    parser.add_argument("--image", type=int, default=512, help="image side in pixels")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--seed", type=int, default=1)
    args = smallest(parser.parse_args(), counts=[40], image=96, rounds=1)
    side = args.image
    base = "catmull:threads=1"
    specs = [base, "catmull", "weiler-atherton"] + [f"weiler-atherton:window={w}" for w in args.windows if w]
    print(f"random interpenetrating triangles of extent {args.size:g} px in {side}x{side}, depth 0..100, "
          f"seed {args.seed}; {args.rounds} interleaved rounds after a warm-up; ratios to {base}")
    print(f"{'n':>6} {'pieces':>7} {'method':>28} {'wall ms':>8} {'(min-max)':>15} {'cpu ms':>8} "
          f"{'x base wall':>11} {'cpu':>6}")
    for n in args.counts:
        scene = random_triangles(n, side, side, size=args.size, seed=args.seed)
        pieces = len(visible_arrays(scene).sources)
        times = interleaved(scene, specs, args.rounds)
        base_wall = np.median(times[base][0])
        base_cpu = np.median(times[base][1])
        for spec in specs:
            wall, cpu = np.array(times[spec][0]), np.array(times[spec][1])
            spread = f"({wall.min() * 1e3:.1f}-{wall.max() * 1e3:.1f})"
            print(f"{n:6d} {pieces:7d} {spec:>28} {np.median(wall) * 1e3:8.1f} {spread:>15} "
                  f"{np.median(cpu) * 1e3:8.1f} {np.median(wall) / base_wall:11.2f} "
                  f"{np.median(cpu) / base_cpu:6.2f}", flush=True)


if __name__ == "__main__":
    main()
