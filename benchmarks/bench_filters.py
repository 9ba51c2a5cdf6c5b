"""Render time of every pixel filter against the box, exact and sampled, interleaved.

Usage: ``PYTHONPATH=. python3 benchmarks/bench_filters.py [--repeats N] [--scenes NAME ...]``

For each scene, every spec is warmed up (first-touch costs), then the specs are timed in
turns (box, tent, ..., box, tent, ...) ``--repeats`` times, so load from other processes
falls on all of them alike; the median wall time per spec, its ratio to the box of the same
method and (``cpu x``) the ratio of the median process CPU times are printed. ``catmull``
runs on one thread (``threads=1``). ``catmull:filter=F`` (F != box) includes finding the
visible pieces (the Catmull kernel run on the half-pixel-shifted knot grid) and
integrating them. The ``512x512, 2000 triangles`` scene is the filter table's row
(bench_methods' 512² scene of 2000 triangles of 40 px, seed 1).
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

from aaeval import registries
from aaeval.filters import FILTERS
from aaeval.renderers import render_timed
from aaeval.scenes import load_scene
from aaeval.scenes.generate import random_triangles

registries.load()  # a program fills the registries once, before it renders

ROOT = Path(__file__).resolve().parents[1]
SCENES = {
    "interpenetrating 32x32": lambda: load_scene(ROOT / "configs" / "scenes" / "interpenetrating.toml"),
    "picket_fence_moire 32x8": lambda: load_scene(ROOT / "configs" / "scenes" / "picket_fence_moire.toml"),
    "random 128x128, 150 triangles": lambda: random_triangles(width=128, height=128, n=150, seed=2, size=30.0),
    "random 512x512, 2000 triangles": lambda: random_triangles(2000, 512, 512, size=40.0, depth_range=(0.0, 100.0),
                                                               seed=1),
}
METHODS = ["catmull:threads=1", "supersample:k=4", "jitter:k=4,seed=1"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=list(SCENES))
    parser.add_argument("--methods", nargs="+", default=METHODS)
    args = parser.parse_args()
    print(f"median ms per frame over {args.repeats} interleaved repeats (after warm-up); x = ratio to the box")
    for scene_name in args.scenes:
        scene = SCENES[scene_name]()
        print(f"\n{scene_name}")
        methods = args.methods
        print(f"{'filter':<12}" + "".join(f"{m:>40}" for m in methods))
        specs = {(m, f): f"{m}{',' if ':' in m else ':'}filter={f}" for m in methods for f in FILTERS}
        for spec in specs.values():
            render_timed(scene, spec)  # warm-up, first-touch costs
        times = {key: [] for key in specs}
        cpu = {key: [] for key in specs}
        for _ in range(args.repeats):
            for key, spec in specs.items():
                start = time.process_time()
                times[key].append(render_timed(scene, spec)[1][0])
                cpu[key].append(time.process_time() - start)
        median = {key: statistics.median(t) for key, t in times.items()}
        cpu_median = {key: statistics.median(t) for key, t in cpu.items()}
        for f in FILTERS:
            cells = [f"{1000 * median[(m, f)]:>18.2f} ms {median[(m, f)] / median[(m, 'box')]:>5.2f}x "
                     f"cpu {cpu_median[(m, f)] / cpu_median[(m, 'box')]:>5.2f}x" for m in methods]
            print(f"{f:<12}" + "".join(cells), flush=True)


if __name__ == "__main__":
    main()
