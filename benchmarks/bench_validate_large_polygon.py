"""Time and memory to load and validate one polygon of many vertices.

Usage: ``PYTHONPATH=. /usr/bin/time -v python3 benchmarks/bench_validate_large_polygon.py [--vertices N]``

Writes a scene file holding one simple polygon, a tight double spiral of N vertices (the
kind of outline where edges of neighbouring turns run close together), then times
``load_scene`` on it: TOML parsing, every per-vertex check and the O(n log n) self-crossing
sweep (C++, ``aaeval.native.samplers``: nothing to compile first). ``/usr/bin/time -v`` reports the peak resident memory ("Maximum resident set size").
The pairwise check this replaced needed 37 GiB at 100000 vertices.
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

import numpy as np


def spiral_scene(n: int) -> str:
    t = np.linspace(0.0, 40 * math.pi, n // 2, endpoint=False)
    outer = np.c_[(1 + t) * np.cos(t), (1 + t) * np.sin(t)]
    inner = np.c_[(1.5 + t) * np.cos(t), (1.5 + t) * np.sin(t)]
    ring = np.concatenate([outer, inner[::-1]]) * 2 + 300
    vertices = ",".join(f"[{float(x)!r},{float(y)!r},0.0]" for x, y in ring)
    return f"[image]\nwidth = 600\nheight = 600\n\n[[polygons]]\ncolor = [1.0, 1.0, 1.0]\nvertices = [{vertices}]\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vertices", type=int, default=100_000)
    args = parser.parse_args()
    from aaeval.scenes import load_scene

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "spiral.toml"
        path.write_text(spiral_scene(args.vertices))
        start = time.perf_counter()
        scene = load_scene(path)
        print(f"{len(scene.polygons[0].vertices)} vertices: load_scene {time.perf_counter() - start:.2f} s")


if __name__ == "__main__":
    main()
