"""Weiler-Atherton run time against polygon count, with and without screen subdivision,
next to catmull on the same scenes (random triangles in 256x256, interpenetrating).

Prints the median of ``--repeats`` runs after one warm-up run per method.
Usage: PYTHONPATH=. python experiments/bench_weiler_atherton.py [--counts 10 30 100] [--repeats 3]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from aaeval.renderers import render
from aaeval.scenes import parse_scene


def random_triangles(n: int, size: int = 256, seed: int = 0):
    rng = np.random.default_rng(seed)
    side = size / np.sqrt(n) * 1.5  # triangles shrink as they multiply: ~constant depth complexity
    polys = []
    for _ in range(n):
        c = rng.uniform(0, size, 2)
        v = np.column_stack([c + rng.uniform(-side, side, (3, 2)), rng.uniform(0, 100, 3)])
        polys.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": v.tolist()})
    return parse_scene({"image": {"width": size, "height": size}, "polygons": polys}, source=f"<{n} triangles>")


def median_time(scene, spec, repeats):
    render(scene, spec)  # warm-up (JIT, caches)
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        image = render(scene, spec)
        times.append(time.perf_counter() - t)
    return statistics.median(times), image


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--counts", type=int, nargs="+", default=[10, 30, 100, 300, 1000])
    ap.add_argument("--windows", type=int, nargs="+", default=[0, 8, 32])
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    specs = ["catmull"] + [f"weiler-atherton:window={w}" for w in args.windows]
    print(f"{'triangles':>9} " + " ".join(f"{s:>28}" for s in specs) + "   max |WA - catmull|")
    for n in args.counts:
        scene = random_triangles(n)
        row, ref, worst = [], None, 0.0
        for spec in specs:
            seconds, image = median_time(scene, spec, args.repeats)
            row.append(seconds)
            if ref is None:
                ref = image
            else:
                worst = max(worst, float(np.abs(image - ref).max()))
        print(f"{n:>9} " + " ".join(f"{s * 1e3:>25.1f} ms" for s in row) + f"   {worst:.1e}", flush=True)


if __name__ == "__main__":
    main()
