"""catmull:shading=exact against shading=piece on configs/scenes/shaded/cylinders.toml, one core.

Prints the median and spread of each over repeats after a warm-up, their ratio, the
evaluations per highlight pixel (specular > 1e-3), the largest error bound and the
energy error of the per-piece highlight against the exact one.
Run: PYTHONPATH=. python benchmarks/bench_shading.py [repeats]
"""

import os
import statistics
import sys
import time
from pathlib import Path

from aaeval.scenes import load_scene
from aaeval.specular.exact import exact_shading
from aaeval.specular.render import render_shaded

SCENE = Path(__file__).resolve().parents[1] / "configs/scenes/shaded/cylinders.toml"


def timed(fn, repeats):
    fn()  # warm-up
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), min(times), max(times)


def one_core() -> int:
    """Pin this process to one core: the per-piece path has no thread option (its visibility
    runs on every core it may use), so only the affinity makes the comparison one core each."""
    core = min(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {core})
    return core


def main(repeats: int = 3) -> None:
    print(f"pinned to core {one_core()}")
    scene = load_scene(SCENE)
    piece = timed(lambda: render_shaded(scene), repeats)
    exact = timed(lambda: exact_shading(scene, threads=1), repeats)
    for name, (med, lo, hi) in (("piece", piece), ("exact", exact)):
        print(f"{name}: median {med:.3f} s (range {lo:.3f}-{hi:.3f}) over {repeats}")
    print(f"exact / piece: {exact[0] / piece[0]:.2f}")
    result = exact_shading(scene, threads=1)
    _, spec_piece = render_shaded(scene, return_specular=True)
    highlight = result.specular > 1e-3
    print(f"highlight pixels {int(highlight.sum())}, evaluations per highlight pixel "
          f"{result.evals[highlight].mean():.0f} (max {result.evals.max():.0f}), max bound {result.max_bound:.2e}")
    print(f"highlight energy, piece vs exact: {spec_piece.sum() / result.specular.sum() - 1:+.4%}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 3)
