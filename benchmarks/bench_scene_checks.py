"""Time outside the render for large scenes: reading and checking.

Usage: ``PYTHONPATH=. python3 benchmarks/bench_scene_checks.py [--triangles 100000] [--holes 2000]``

Writes a scene file of ``--triangles`` random triangles (512 x 512, 10 px), then runs
``aaeval render`` on it (catmull, one thread) ``--repeats`` times and prints each run's
wall time, the render alone (as render prints it) and the rest: start-up, imports,
reading the TOML, every check of the format, writing the image. Then it validates one
polygon with ``--holes`` square holes apart (accepted) and with one more overlapping the
first (refused), timing ``parse_scene`` on each.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from aaeval.scenes.document import parse_scene
from aaeval.scenes.format import SceneError
from aaeval.scenes.generate import random_triangles
from aaeval.scenes.write import write_scene
from smoke import smallest

#: the render time in render's closing line: 'wrote OUT (WxH, METHOD, frame F, 1234.5 ms)'
RENDER_MS = re.compile(r", ([0-9.]+) ms\)\s*$")


def holed(n: int, overlap: bool) -> dict:
    side = int(n**0.5) + 1
    holes = [[[2 + 3 * (k // side) + dx, 2 + 3 * (k % side) + dy, 0.0] for dx, dy in ((0, 0), (1, 0), (1, 1), (0, 1))]
             for k in range(n)]
    if overlap:
        holes.append([[2.5, 2.5, 0.0], [3.5, 2.5, 0.0], [3.5, 3.5, 0.0], [2.5, 3.5, 0.0]])
    size = 3 * side + 4
    outer = [[0, 0, 0.0], [size, 0, 0.0], [size, size, 0.0], [0, size, 0.0]]
    return {"image": {"width": 64, "height": 64}, "polygons": [{"color": [1, 1, 1], "vertices": outer, "holes": holes}]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--triangles", type=int, default=100_000)
    parser.add_argument("--holes", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=3)
    args = smallest(parser.parse_args(), triangles=500, holes=50, repeats=1)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "triangles.toml"
        write_scene(random_triangles(args.triangles, 512, 512, size=10.0, seed=1), path)
        print(f"{args.triangles} triangles: {path.stat().st_size / 1e6:.1f} MB of TOML")
        for _ in range(args.repeats):
            # no --stats: with it, render warms the spec up on the scene itself first (a second
            # whole render, which is render time, not reading or checking)
            t = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "aaeval", "render", str(path), "-m", "catmull:threads=1",
                                   "-o", str(Path(tmp) / "out.npy")], check=True, capture_output=True, text=True)
            wall = time.perf_counter() - t
            render = float(RENDER_MS.search(done.stdout).group(1)) / 1e3  # the render's own time, as render prints it
            print(f"  aaeval render: wall {wall:.2f} s, render {render:.2f} s, outside the render {wall - render:.2f} s")
    for overlap in (False, True):
        document = holed(args.holes, overlap)
        t = time.perf_counter()
        try:
            parse_scene(document, source="holes")
            verdict = "accepted"
        except SceneError as exc:
            verdict = f"refused ({exc})"
        print(f"{args.holes + overlap} holes: {time.perf_counter() - t:.2f} s, {verdict}")


if __name__ == "__main__":
    main()
