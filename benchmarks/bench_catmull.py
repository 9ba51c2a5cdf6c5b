"""Benchmark: Catmull 1978 on 512x512 with 2000 random interpenetrating triangles.

Prints the median milliseconds per frame (wall clock and process CPU time) over
repeated renders after a warm-up render (JIT compilation excluded), and pixels per
second, on one core (``threads=1``). Goal: <= 250 ms a frame.

    PYTHONPATH=. python3 benchmarks/bench_catmull.py [--repeats 7] [--size 60]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from aaeval import registries
from aaeval.renderers import render
from aaeval.catmull import visible_fragments
from aaeval.scenes.generate import random_triangles
from smoke import smallest

registries.load()  # a program fills the registries once, before it renders


def measure(scene, spec, repeats):
    render(scene, spec)  # warm-up: JIT compilation and caches
    wall, cpu = [], []
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        render(scene, spec)
        wall.append(time.perf_counter() - w0)
        cpu.append(time.process_time() - c0)
    return float(np.median(wall)), float(np.median(cpu))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--triangles", type=int, default=2000)
    parser.add_argument("--size", type=float, nargs="+", default=[20.0, 40.0, 60.0],
                        help="triangle extent in pixels (bounding box side); several values allowed")
    parser.add_argument("--seed", type=int, default=1)
    args = smallest(parser.parse_args(), triangles=50, size=[20.0], repeats=1)
    width = height = 512
    print(f"{args.triangles} random interpenetrating triangles, {width}x{height}, "
          f"median of {args.repeats} after warm-up, one core")
    print(f"{'size':>5} {'depth':>6} {'frags/px':>8} {'method':>24} {'wall ms':>8} {'cpu ms':>8} {'Mpix/s':>7}")
    for size in args.size:
        scene = random_triangles(args.triangles, width, height, size=size, depth_range=(0.0, 100.0), seed=args.seed)
        frags = visible_fragments(scene, centroids=False)
        tri = scene.arrays.vertices[:, :2].reshape(-1, 3, 2)
        e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
        coverage = np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum() / 2  # depth complexity
        for spec in ("catmull:threads=1", "catmull-jagged:threads=1"):
            wall, cpu = measure(scene, spec, args.repeats)
            print(f"{size:5.0f} {coverage / (width * height):6.2f} {len(frags.pixel) / (width * height):8.2f} "
                  f"{spec:>24} {wall * 1e3:8.1f} {cpu * 1e3:8.1f} {width * height / wall / 1e6:7.2f}")


if __name__ == "__main__":
    main()
