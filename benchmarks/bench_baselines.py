"""Median milliseconds per frame of every anti-aliasing method on random triangle scenes.

Usage: ``PYTHONPATH=. python3 benchmarks/bench_baselines.py [--repeats N] [--methods SPEC ...]``

Each method is warmed up first (numba JIT), then timed ``--repeats`` times per scene with
:func:`aaeval.renderers.render_timed`; the median is printed. A second table gives each
method's RMSE and largest pixel error against the exact ``catmull`` image of the small
scene. Last, the time of ``abuffer`` on a deep stack of coplanar triangles (the tie rule's
worst case for sorting a pixel's fragments).
"""

from __future__ import annotations

import argparse
import statistics

import numpy as np

from aaeval import registries
from aaeval.renderers import render, render_timed
from aaeval.scenes.generate import coplanar_stack, random_triangles
from smoke import SMOKE, smallest

registries.load()  # a program fills the registries once, before it renders

DEFAULT_METHODS = [
    "catmull",
    "point",
    "supersample:k=2",
    "supersample:k=4",
    "supersample:k=8",
    "jitter:k=4,seed=1",
    "abuffer",
    "skia",
]

SCENES = {
    "512x512, 2000 triangles": dict(width=512, height=512, n=2000, seed=1, size=40.0),
    "256x256, 200 triangles": dict(width=256, height=256, n=200, seed=2, size=40.0),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--methods", nargs="+", default=DEFAULT_METHODS)
    args = smallest(parser.parse_args(), repeats=1)
    sizes = {"96x96, 40 triangles": dict(width=96, height=96, n=40, seed=1, size=20.0)} if SMOKE else SCENES
    scenes = {name: random_triangles(**kw) for name, kw in sizes.items()}
    print(f"median ms per frame over {args.repeats} repeats (after warm-up)")
    print(f"{'method':<22}" + "".join(f"{name:>28}" for name in scenes))
    for spec in args.methods:
        cells = []
        for scene in scenes.values():
            render_timed(scene, spec)  # warm-up, and first-touch costs
            times = render_timed(scene, spec, repeats=args.repeats)[1]
            cells.append(f"{1000 * statistics.median(times):>28.1f}")
        print(f"{spec:<22}" + "".join(cells), flush=True)

    name, scene = list(scenes.items())[-1]
    exact = render(scene, "catmull")
    print(f"\nerror against catmull on the {name} scene")
    print(f"{'method':<22}{'RMSE':>12}{'max abs':>12}")
    for spec in args.methods + [f"supersample:k={k}" for k in (16, 32)]:
        diff = render(scene, spec) - exact
        print(f"{spec:<22}{np.sqrt(np.mean(diff**2)):>12.2e}{np.abs(diff).max():>12.2e}", flush=True)

    stack = coplanar_stack(300 if SMOKE else 3000)
    render_timed(stack, "abuffer")
    times = render_timed(stack, "abuffer", repeats=args.repeats)[1]
    print(f"\nabuffer on {stack.source}, 12 x 12: {1000 * statistics.median(times):.1f} ms (median of {args.repeats})")


if __name__ == "__main__":
    main()
