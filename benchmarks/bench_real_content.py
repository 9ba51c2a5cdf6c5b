"""Catmull's exact renderer against the rasterizers shipped for real content, per scene.

Usage: ``PYTHONPATH=. python3 benchmarks/bench_real_content.py [--repeats N]``

For each shipped real-content scene (configs/scenes/content/: the pangram at 9/12/16 px,
the icon set, the map tiling, the illustration) it times ``catmull`` against ``skia`` and
the scene's own peer (``freetype`` for text, ``resvg`` for SVG), interleaved round by
round so that load from other processes falls on every method alike, and prints the
median milliseconds per frame (JIT compiled before the clock starts; each round renders
a different frame of the scene's 1/8-px animation) with the ratio to ``catmull``, and
each method's RMSE against the exact image with its intensity-sum variation and flicker
over the animation (the same definitions as the sweep's temporal metrics).
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

import numpy as np

from aaeval import registries
from aaeval.metrics.temporal import flicker, intensity_sum, relative_variation
from aaeval.renderers import render, render_timed
from aaeval.scenes import load_scene

registries.load()  # a program fills the registries once, before it renders

CONTENT = Path(__file__).resolve().parents[1] / "configs" / "scenes" / "content"
SCENES = ["pangram", "icons", "map", "illustration"]


def peers(scene) -> list[str]:
    own = ["freetype"] if "text" in scene.extensions else ["resvg"] if "svg" in scene.extensions else []
    return ["catmull", "skia", *own]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=9, help="rounds per scene (default 9)")
    args = parser.parse_args()
    print(f"median ms per frame over {args.repeats} interleaved rounds (after warm-up); ratio = method / catmull")
    print(f"{'scene':<14}{'size':>10}{'polygons':>10}  {'method':<10}{'ms':>9}{'ratio':>8}"
          f"{'RMSE':>10}{'sum var':>10}{'flicker':>10}")
    for name in SCENES:
        scene = load_scene(CONTENT / f"{name}.toml")
        specs = peers(scene)
        times = {spec: [] for spec in specs}
        for spec in specs:
            render_timed(scene, spec)  # warm-up
        for r in range(args.repeats):
            for spec in specs:
                times[spec].append(render_timed(scene, spec, frame=r % scene.frames)[1][0])
        exact = np.stack([render(scene, "catmull", frame=k) for k in range(scene.frames)])
        base = statistics.median(times["catmull"])
        for spec in specs:
            frames = exact if spec == "catmull" else np.stack([render(scene, spec, frame=k) for k in range(scene.frames)])
            rmse = float(np.sqrt(np.mean((frames - exact) ** 2)))
            ms = 1000 * statistics.median(times[spec])
            size = f"{scene.width}x{scene.height}"
            print(f"{name:<14}{size:>10}{len(scene.polygons):>10}  {spec:<10}{ms:>9.2f}{ms / 1000 / base:>8.2f}"
                  f"{rmse:>10.4f}{relative_variation([intensity_sum(f) for f in frames]):>10.2e}"
                  f"{flicker(exact, frames):>10.2e}", flush=True)


if __name__ == "__main__":
    main()
