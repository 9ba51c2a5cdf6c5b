"""Benchmark: the exact Catmull renderer against the other methods, same scenes, one run.

Scenes are random interpenetrating triangles (:func:`aaeval.scenes.generate.random_triangles`)
in four groups: ``table`` (the rows of benchmarks/results/bench_methods.md's table), ``count`` (polygon count 500 to
32000 at 512x512), ``size`` (image side 256 to 2048, triangles scaled with it) and ``depth``
(depth complexity: triangle size 10 to 80 at 512x512). Every method renders every scene;
the methods take turns inside each repeat (interleaved, so a machine shared with other work
disturbs them alike). Render time only: each method is warmed up first (JIT compilation
excluded). Single-core rows use ``threads=1``; ``catmull:threads=0`` (all cores) is timed
too, for the thread speed-up.

Printed per scene and method: median wall milliseconds, the spread (interquartile range),
median process CPU milliseconds, and the ratio of the median to Skia's. A method whose
first render takes longer than ``--slow`` seconds is timed once on that scene, and
``weiler-atherton`` (object-space, far slower) is left out above ``--wa-max`` polygons. Written to
``--out``: ``bench_methods.csv`` (every timing) and ``bench_methods.png``, cost against work
(log-log; work = pixels + the pixel area of every polygon, i.e. pixels x (1 + depth
complexity)) with the machine's fill-rate line (the time to write that many RGB float64
pixels once, measured here). The header also gives the machine's own parallel ceiling: how
much faster a loop of pure arithmetic (no memory traffic, no shared state) runs split over
every core than on one, median of interleaved repeats; the thread speed-up of
``catmull:threads=0`` on each scene is printed next to it.

    PYTHONPATH=. python3 benchmarks/bench_methods.py [--groups table count size depth]
        [--repeats 5] [--methods SPEC ...] [--out benchmarks/results]
"""

from __future__ import annotations

import argparse
import csv
import os
import time
from pathlib import Path

import numpy as np

from aaeval import registries
from aaeval.renderers import render_timed
from aaeval.catmull import available_cores
from aaeval.scenes.generate import random_triangles
from smoke import SMOKE, smallest, time_against_size_axes

registries.load()  # a program fills the registries once, before it renders

METHODS = [
    "catmull:threads=1",
    "catmull-jagged:threads=1",
    "weiler-atherton",
    "skia",
    "blend2d",
    "supersample:k=4",
    "supersample:k=16",
    "catmull:threads=0",
]

# (width = height, triangles, triangle extent in pixels)
GROUPS = {
    "table": [(512, 2000, 40.0), (512, 500, 20.0), (512, 32000, 20.0), (1024, 2000, 80.0), (2048, 2000, 160.0)],
    "count": [(512, 500, 20.0), (512, 2000, 20.0), (512, 8000, 20.0), (512, 32000, 20.0)],
    "size": [(256, 2000, 20.0), (512, 2000, 40.0), (1024, 2000, 80.0), (2048, 2000, 160.0)],
    "depth": [(512, 2000, 10.0), (512, 2000, 20.0), (512, 2000, 40.0), (512, 2000, 80.0)],
}
SMOKE_GROUP = [(96, 40, 20.0)]  # AAEVAL_BENCH_SMOKE=1 (benchmarks/smoke.py)


def covered_area(scene) -> float:
    """Sum of the triangles' areas in pixels (clipped to nothing: an upper bound near edges)."""
    tri = scene.arrays.vertices[:, :2].reshape(-1, 3, 2)
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    return float(np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum() / 2)


def fill_seconds_per_pixel(side: int = 1024, repeats: int = 9) -> float:
    """The machine's fill rate: the best time (the limit, least disturbed by other work) to
    write one RGB float64 pixel of a new image."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        image = np.empty((side, side, 3))
        image[...] = 0.5
        times.append(time.perf_counter() - start)
    return float(min(times)) / (side * side)


def _arithmetic(n):
    s = 0.0
    for i in range(n):
        s += (i % 7) * 0.5
    return s


def parallel_ceiling(cores: int, repeats: int = 7, n: int = 5_000_000) -> float:
    """Median time of a pure-arithmetic loop in one process over its median split across
    ``cores`` processes started beforehand (interleaved): the speed-up this machine gives
    work that shares nothing."""
    from concurrent.futures import ProcessPoolExecutor

    one, many = [], []
    with ProcessPoolExecutor(cores) as pool:
        list(pool.map(_arithmetic, [10] * cores))  # the workers start before the clock
        for _ in range(repeats):
            start = time.perf_counter()
            _arithmetic(n)
            one.append(time.perf_counter() - start)
            start = time.perf_counter()
            list(pool.map(_arithmetic, [n // cores] * cores))
            many.append(time.perf_counter() - start)
    return float(np.median(one) / np.median(many))


def time_scene(scene, methods, repeats, slow):
    """Interleaved timings: ``{method: [(wall, cpu), ...]}``."""
    timings = {m: [] for m in methods}
    once = set()
    for r in range(repeats):
        order = methods[r % len(methods):] + methods[:r % len(methods)]
        for spec in order:
            if spec in once:
                continue
            cpu = time.process_time()
            _, (wall,) = render_timed(scene, spec)
            timings[spec].append((wall, time.process_time() - cpu))
            if r == 0 and wall > slow:
                once.add(spec)
    return timings


def summary(values):
    v = np.asarray(values)
    return float(np.median(v)), float(np.percentile(v, 75) - np.percentile(v, 25))


def plot(rows, fill, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 5))
    for spec in dict.fromkeys(r["method"] for r in rows):
        pts = sorted({(float(r["work"]), float(r["median_wall_ms"])) for r in rows if r["method"] == spec})
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o", ms=5, alpha=0.8, label=spec)
    work = np.array(sorted({float(r["work"]) for r in rows}))
    ax.plot(work, work * fill * 1e3, "k--", lw=1.5, label="fill rate (write each unit of work once)")
    time_against_size_axes(ax, xlabel="work: pixels x (1 + depth complexity)", ylabel="median wall ms per frame",
                           title="Render time against work (random interpenetrating triangles)", legend_size=7)
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # 3x10^5 4x10^5 ... collide
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--groups", nargs="+", default=list(GROUPS), choices=list(GROUPS))
    parser.add_argument("--methods", nargs="+", default=METHODS)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--slow", type=float, default=3.0, help="seconds above which a method is timed once")
    parser.add_argument("--wa-max", type=int, default=2000, help="most polygons weiler-atherton is timed on")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--plot-only", action="store_true", help="redraw the plot from --out's CSV")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results"))
    args = smallest(parser.parse_args(), groups=["smoke"], repeats=1)
    args.out.mkdir(parents=True, exist_ok=True)
    fill = fill_seconds_per_pixel()
    if args.plot_only:
        with open(args.out / "bench_methods.csv") as fh:
            plot(list(csv.DictReader(fh)), fill, args.out / "bench_methods.png")
        return
    cores = available_cores()
    # smoke: one short repeat (the full measurement is 7 x 5e6 iterations, about 10 s)
    smoke = {"repeats": 1, "n": 200_000} if SMOKE else {}
    ceiling = parallel_ceiling(cores, **smoke) if cores > 1 else 1.0
    print(f"{os.cpu_count()} cores; fill rate {fill * 1e9:.2f} ns per RGB float64 pixel; "
          f"median of {args.repeats} interleaved repeats after warm-up")
    print(f"parallel ceiling: pure arithmetic runs {ceiling:.2f}x faster on {cores} threads than on one")
    scenes = list(dict.fromkeys(s for g in args.groups for s in {**GROUPS, "smoke": SMOKE_GROUP}[g]))
    rows = []
    for side, n, size in scenes:
        scene = random_triangles(n, side, side, size=size, depth_range=(0.0, 100.0), seed=args.seed)
        pixels = side * side
        depth = covered_area(scene) / pixels
        work = pixels * (1 + depth)
        methods = [m for m in args.methods if not (m.startswith("weiler-atherton") and n > args.wa_max)]
        timings = time_scene(scene, methods, args.repeats, args.slow)
        skia = summary([w for w, _ in timings["skia"]])[0] if "skia" in timings else float("nan")
        print(f"\n{side}x{side}, {n} triangles of {size:g} px, depth complexity {depth:.2f}")
        print(f"{'method':>26} {'wall ms':>9} {'IQR':>7} {'cpu ms':>9} {'/ skia':>7} {'ns/px':>7} {'n':>2}")
        for spec, values in timings.items():
            wall, spread = summary([w for w, _ in values])
            cpu, _ = summary([c for _, c in values])
            print(f"{spec:>26} {wall * 1e3:9.1f} {spread * 1e3:7.1f} {cpu * 1e3:9.1f} {wall / skia:7.2f} "
                  f"{wall / pixels * 1e9:7.0f} {len(values):2d}")
            for k, (w, c) in enumerate(values):
                rows.append(dict(side=side, triangles=n, size=size, depth=round(depth, 3), work=work, method=spec,
                                 repeat=k, wall_ms=w * 1e3, cpu_ms=c * 1e3, median_wall_ms=wall * 1e3,
                                 median_ratio_to_skia=wall / skia))
        if "catmull:threads=1" in timings and "catmull:threads=0" in timings:
            one, every = (summary([w for w, _ in timings[m]])[0] for m in ("catmull:threads=1", "catmull:threads=0"))
            print(f"{'':>26} threads=0 is {one / every:.2f}x threads=1 ({cores} cores; ceiling {ceiling:.2f}x)")
    with open(args.out / "bench_methods.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot(rows, fill, args.out / "bench_methods.png")
    print(f"\nwrote {args.out / 'bench_methods.csv'} and {args.out / 'bench_methods.png'}")


if __name__ == "__main__":
    main()
