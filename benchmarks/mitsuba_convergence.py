"""How close the Mitsuba ground truth gets to the exact ``catmull`` image, and at what cost.

For each scene and each spp: RMSE and max |error| against ``catmull`` (median over
``--repeats`` seeds) and the median wall and process CPU time of a render (kernels
compiled first, no cache; CPU time counts all of Dr.Jit's threads, so it stays honest on a
shared machine where wall time does not). Issue target: stratified 4096 spp within RMSE 2e-4 of ``catmull`` on the shipped
scenes.

    PYTHONPATH=. python benchmarks/mitsuba_convergence.py                 # generated 256x256 + configs/scenes/*.toml
    PYTHONPATH=. python benchmarks/mitsuba_convergence.py a.toml --spp 64,4096 --repeats 5
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from aaeval import registries
from aaeval.groundtruth.flat import SAMPLERS, render_mitsuba
from aaeval.mitsuba_variant import import_mitsuba
from aaeval.renderers import METHODS, render
from aaeval.scenes import Scene, load_scene, parse_scene
from smoke import smallest

registries.load()  # a program fills the registries once, before it renders

TARGET_RMSE = 2e-4


def generated_scene(size: int = 256, count: int = 12, seed: int = 1) -> Scene:
    """A shipped-like scene: triangles, quads and concave outlines on random tilted
    planes (so they interpenetrate), some reaching outside the image."""
    rng = np.random.default_rng(seed)
    polygons = []
    for i in range(count):
        centre = rng.uniform(-0.1, 1.1, 2) * size
        n = (3, 4, 6)[i % 3]
        angles = (np.arange(n) + rng.uniform(0, 0.8, n)) * (2 * np.pi / n)  # star-shaped: simple
        radii = rng.uniform(0.15, 0.45, n) * size
        if n == 6:
            radii[::2] *= 0.35  # alternate radii: a concave star-like outline
        xy = centre + np.column_stack([np.cos(angles), np.sin(angles)]) * radii[:, None]
        a, b = rng.uniform(-0.5, 0.5, 2)
        c = rng.uniform(0, size)
        z = a * xy[:, 0] + b * xy[:, 1] + c
        polygons.append({"color": rng.uniform(0, 1, 3).tolist(), "vertices": np.column_stack([xy, z]).tolist()})
    return parse_scene(
        {"image": {"width": size, "height": size, "background": [0.05, 0.05, 0.1]}, "polygons": polygons},
        source=f"generated-{size}x{size}-{count}",
    )


def measure(scene: Scene, spp_list, sampler: str, repeats: int):
    reference = render(scene, "catmull")
    rows = []
    for spp in spp_list:
        errors, worst, times, cpu = [], [], [], []
        for seed in range(repeats):
            start, start_cpu = time.perf_counter(), time.process_time()
            image = render_mitsuba(scene, spp=spp, sampler=sampler, seed=seed)
            times.append(time.perf_counter() - start)
            cpu.append(time.process_time() - start_cpu)
            errors.append(np.sqrt(np.mean((image - reference) ** 2)))
            worst.append(np.abs(image - reference).max())
        rows.append((spp, *(float(np.median(v)) for v in (errors, worst, times, cpu))))
    return rows


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", type=Path, help="scene files (default: configs/scenes/*.toml)")
    parser.add_argument("--spp", default="64,256,1024,4096", help="comma-separated spp values")
    parser.add_argument("--sampler", default="stratified", choices=SAMPLERS)
    parser.add_argument("--repeats", type=int, default=3, help="renders (seeds) per cell; medians are printed")
    parser.add_argument("--no-generated", action="store_true", help="skip the generated 256x256 scene")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    args = smallest(parser.parse_args(argv), spp="4,16", repeats=1, no_generated=True, quiet=True,
                    scenes=[Path("configs/scenes/fan.toml")])

    from rich.progress import track  # rich: a dependency already (tqdm is not)

    spp_list = [int(s) for s in args.spp.split(",")]
    paths = args.scenes or sorted(Path("configs/scenes").glob("*.toml"))
    scenes = ([] if args.no_generated else [generated_scene()]) + [load_scene(p) for p in paths]

    mi = import_mitsuba("auto")
    METHODS["catmull"].warmup()
    METHODS["mitsuba"].warmup()
    print(f"Mitsuba {mi.__version__}, variant {mi.variant()}, sampler {args.sampler}, median of {args.repeats} seeds")
    header = f"{'scene':<28} {'size':>9} {'polys':>5} {'spp':>6} {'RMSE':>9} {'max|err|':>9} {'wall s':>8} {'cpu s':>8}"
    lines, failures = [header, "-" * len(header)], []
    for scene in (scenes if args.quiet else track(scenes, description="scenes")):
        name = Path(scene.source).stem if scene.source.endswith(".toml") else scene.source
        for spp, rmse, worst, seconds, cpu in measure(scene, spp_list, args.sampler, args.repeats):
            size = f"{scene.width}x{scene.height}"
            lines.append(f"{name:<28} {size:>9} {len(scene.polygons):>5} {spp:>6} {rmse:9.2e} {worst:9.2e} {seconds:8.3f} {cpu:8.3f}")
            if spp == 4096 and rmse > TARGET_RMSE:
                failures.append(name)
    print("\n".join(lines))
    if 4096 in spp_list:
        print(f"4096 spp above RMSE {TARGET_RMSE:g}: {', '.join(failures) or 'none'}")


if __name__ == "__main__":
    main()
