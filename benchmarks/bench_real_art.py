"""Every method on real art beside random triangles, with time against size.

Usage: ``PYTHONPATH=. python3 benchmarks/bench_real_art.py [--repeats 5] [--methods SPEC ...]
[--sizes 100 339 1000] [--out benchmarks/results]``

Scenes: the shipped illustration, icon set and map (SVG imports, configs/scenes/content/)
enlarged to about 512 px, the page of text (the pangram), tiger-like illustrations at
512 x 512 (:func:`aaeval.scenes.generate.illustration_like`, held-out seeds 1 and 2, at
``--sizes`` layers), and random triangles of the speed table (512 x 512, 2000 of 40 px).
Every method renders every scene, the methods taking turns inside each repeat
(interleaved: load from other processes falls on all alike), render time only after a
warm-up. Printed: median wall ms, the spread (min-max), median CPU ms and the ratio to
catmull. Written to ``--out``: ``bench_real_art.csv`` (every timing) and
``bench_real_art.png`` (median time against the scene's vertex count, log-log).
"""

from __future__ import annotations

import argparse
import csv
import statistics
import time
from pathlib import Path

import numpy as np

from aaeval import registries
from aaeval._toml import read_toml
from aaeval.renderers import render_timed
from aaeval.scenes.document import parse_scene
from aaeval.scenes.format import SceneError
from aaeval.scenes.generate import illustration_like, random_triangles
from smoke import SMOKE, smallest, time_against_size_axes

registries.load()  # a program fills the registries once, before it renders

CONTENT = Path(__file__).resolve().parents[1] / "configs" / "scenes" / "content"
METHODS = ["catmull:threads=1", "weiler-atherton", "skia", "blend2d"]


def enlarged(name: str, side: int = 512):
    """A shipped scene scaled (about the origin) so that its longer side is ``side`` px."""
    document, _ = read_toml(CONTENT / f"{name}.toml", SceneError, "scene file")
    image = document["image"]
    k = side / max(image["width"], image["height"])
    if k <= 1:
        return parse_scene(document, source=name)
    image["width"], image["height"] = round(image["width"] * k), round(image["height"] * k)
    document.pop("svg", None)  # the import's own record: it names the unscaled file
    document.pop("text", None)
    for polygon in document["polygons"]:
        for ring in [polygon["vertices"], *polygon.get("holes", [])]:
            for point in ring:
                point[0], point[1] = point[0] * k, point[1] * k
    return parse_scene(document, source=f"{name} x{k:.3g}")


def scenes(sizes):
    big = 64 if SMOKE else 512
    out = [("illustration", enlarged("illustration", big)), ("icons", enlarged("icons", big)),
           ("map", enlarged("map", big)), ("pangram", enlarged("pangram", 0))]
    side = 64 if SMOKE else 512
    out += [(f"tiger-like seed {s}, {n} layers", illustration_like(s, n=n, size=side)) for s in (1, 2) for n in sizes]
    n = 20 if SMOKE else 2000
    out.append((f"random {side}x{side}, {n}x40", random_triangles(n, side, side, size=40.0, seed=1)))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--methods", nargs="+", default=METHODS)
    parser.add_argument("--sizes", nargs="+", type=int, default=[100, 339, 1000])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results"))
    args = smallest(parser.parse_args(), repeats=1, sizes=[5])
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    print(f"median of {args.repeats} interleaved repeats after warm-up; spread = min-max; ratio to catmull:threads=1")
    for name, scene in scenes(args.sizes):
        vertices = int(scene.arrays.length.sum())
        times = {m: [] for m in args.methods}
        for m in args.methods:
            render_timed(scene, m)  # warm-up
        for _ in range(args.repeats):
            for m in args.methods:
                c0 = time.process_time()
                times[m].append((render_timed(scene, m)[1][0], time.process_time() - c0))
        base = statistics.median(w for w, _ in times[args.methods[0]])
        print(f"\n{name}: {scene.width}x{scene.height}, {len(scene.polygons)} polygons ({len(scene.holed)} with holes), "
              f"{vertices} vertices")
        for m, values in times.items():
            wall = [w for w, _ in values]
            med = statistics.median(wall)
            cpu = statistics.median(c for _, c in values)
            print(f"  {m:>30} {med * 1e3:9.1f} ms  ({min(wall) * 1e3:.1f}-{max(wall) * 1e3:.1f})  cpu {cpu * 1e3:8.1f}"
                  f"  x{med / base:6.2f}")
            for k, (w, c) in enumerate(values):
                rows.append(dict(scene=name, width=scene.width, height=scene.height, polygons=len(scene.polygons),
                                 vertices=vertices, method=m, repeat=k, wall_ms=w * 1e3, cpu_ms=c * 1e3,
                                 median_wall_ms=med * 1e3, ratio_to_catmull=med / base))
    with open(args.out / "bench_real_art.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot(rows, args.out / "bench_real_art.png")
    print(f"\nwrote {args.out / 'bench_real_art.csv'} and {args.out / 'bench_real_art.png'}")


def plot(rows, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5), dpi=150)
    methods = list(dict.fromkeys(r["method"] for r in rows))
    for m in methods:
        points = sorted({(r["vertices"], r["median_wall_ms"], r["scene"]) for r in rows if r["method"] == m})
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        ax.plot(xs, ys, "o", label=m, alpha=0.8)
        tiger = sorted((p[0], p[1]) for p in points if p[2].startswith("tiger-like seed 1"))
        if tiger:
            ax.plot(*zip(*tiger), "-", color=ax.lines[-1].get_color(), alpha=0.5)
    time_against_size_axes(ax, xlabel="scene vertices (tiger-like seed 1 joined by lines)",
                           ylabel="median render time, ms (one core)",
                           title="Real art and random triangles: render time against scene size", legend_size=8)
    fig.tight_layout()
    tmp = path.with_suffix(".tmp.png")
    fig.savefig(tmp)
    plt.close(fig)
    tmp.replace(path)


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
