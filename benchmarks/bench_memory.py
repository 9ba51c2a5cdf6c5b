"""Memory of a catmull render on the issue-11 stress scenes; run it under ``/usr/bin/time -v``.

``vertices``: one simple star-shaped polygon with 100000 vertices (radii 60-250 px) on
512x512, checked exactly: its box-filtered image sums to its area. ``polygons``: 100000
random interpenetrating triangles of 10 px on 512x512. The goal is under 2 GB resident
("Maximum resident set size" in time's report; that includes Python, numpy and numba).

    PYTHONPATH=. /usr/bin/time -v python3 benchmarks/bench_memory.py vertices [--threads 0]
    PYTHONPATH=. /usr/bin/time -v python3 benchmarks/bench_memory.py polygons [--threads 0]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from aaeval import registries
from aaeval.renderers import render
from aaeval.scenes import parse_scene
from aaeval.scenes.generate import random_triangles

registries.load()  # a program fills the registries once, before it renders


def star_scene(n: int = 100_000, seed: int = 1):
    """One white star-shaped polygon with ``n`` vertices on black, and its exact area."""
    rng = np.random.default_rng(seed)
    angles = 2 * np.pi * (np.arange(n) + rng.uniform(0, 0.9, n)) / n  # gaps below pi: simple
    radii = rng.uniform(60, 250, n)
    xy = np.column_stack([256 + radii * np.cos(angles), 256 + radii * np.sin(angles)])
    z = 0.01 * xy[:, 0] + 0.02 * xy[:, 1] + 5
    scene = parse_scene({"image": {"width": 512, "height": 512},
                         "polygons": [{"color": [1, 1, 1], "vertices": np.column_stack([xy, z]).tolist()}]})
    x, y = xy[:, 0], xy[:, 1]
    return scene, 0.5 * abs(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", choices=["vertices", "polygons"])
    parser.add_argument("--threads", type=int, default=0)
    args = parser.parse_args()
    start = time.perf_counter()
    if args.scene == "vertices":
        scene, area = star_scene()
    else:
        scene, area = random_triangles(100_000, 512, 512, size=10.0, seed=3), None
    built = time.perf_counter()
    image = render(scene, f"catmull:threads={args.threads}")
    done = time.perf_counter()
    print(f"{args.scene}: scene built in {built - start:.1f} s, rendered in {done - built:.1f} s "
          f"(threads={args.threads}, JIT included if the cache is cold)")
    if area is not None:
        print(f"image sum / 3 = {image.sum() / 3:.6f}, polygon area = {area:.6f}, "
              f"relative difference {image.sum() / 3 / area - 1:.2e}")


if __name__ == "__main__":
    main()
