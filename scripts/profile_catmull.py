"""Where catmull's box render spends its time, sorted by what the work is for.

The kernel (``render_flat``, one thread) renders a random-triangle scene in a loop under
``perf record``; each sampled address is named by its chain of inlined functions
(``addr2line -i``) and counted in one of three parts:

- **clip arithmetic of the visibility resolution**: ``common/geometry.hpp`` (side tests,
  half-plane clips, areas) reached from the pixel integrator, the two-layer case, the front
  piece or ``clip_to_column``: the operations whose roundings are the image's bits (some
  of them only feed the integrator's decisions: parts later found hidden);
- **the integrator's control**: its lists, side ranges, depth relations and records;
- **the front end**: strips, z-lists, the sweep and the sink.

The kernel and ``catmull-jagged`` (the same front end with the visibility resolution
switched off: the nearest piece takes the whole pixel) are also timed, interleaved, and with
``--blend2d`` the ``blend2d`` method on the same scene. The floor printed is the jagged time
plus the visibility's clip arithmetic: what catmull would take if its integrator's control
cost nothing.

Needs ``perf`` and ``addr2line``, and the catmull module built with symbols and lines into
the source tree::

    bash scripts/build_native_dev.sh catmull -DAAEVAL_KEEP_SYMBOLS=ON -DCMAKE_CXX_FLAGS=-g
    python3 scripts/profile_catmull.py --scene 512 32000 20 --blend2d
"""

from __future__ import annotations

import argparse
import collections
import importlib.util
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
MODULE = next((ROOT / "aaeval" / "native").glob("catmull.*.so"), None)
VISIBILITY = ("integrate", "two_layer", "emit_front_piece", "clip_to_column", "pixel_polygons")
PARTS = ("clip arithmetic of the visibility resolution", "integrator control", "front end")


def load_module(path: Path):
    """The catmull module at ``path`` (the dev build, not the installed one)."""
    spec = importlib.util.spec_from_file_location("catmull", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def make_scene(scene: list[float], tiger: int | None):
    """Random triangles (bench_methods' scenes: side, count, size) or a tiger-like
    illustration of 339 layers at 512 x 512 (bench_real_art's)."""
    from aaeval.scenes.generate import illustration_like, random_triangles

    if tiger is not None:
        return illustration_like(tiger, n=339, size=512)
    side, triangles, size = int(scene[0]), int(scene[1]), scene[2]
    return random_triangles(triangles, side, side, size=size, depth_range=(0.0, 100.0), seed=1)


def kernel_call(scene):
    """A function rendering ``scene`` with the dev module: ``call(jagged)``."""
    import aaeval.catmull as C

    module = load_module(MODULE)
    starts, lengths, x, y, planes, source, eps_z = C.kernel_inputs(scene)
    colors = np.vstack([scene.arrays.colors[source], scene.background]).astype(np.float64)
    args = C.native_arrays(starts, lengths, x, y, planes)
    return lambda jagged: module.render_flat(*args, colors, float(eps_z), scene.width, scene.height, jagged, 1)


def loop(scene, repeats: int) -> None:
    """The worker perf records: the exact kernel only, after one warm-up render."""
    call = kernel_call(scene)
    for _ in range(repeats + 1):
        call(False)


def median_ms(seconds: list[float]) -> float:
    return 1e3 * float(np.median(seconds))


def timings(scene, repeats: int, blend2d: bool) -> dict[str, float]:
    """Median ms of the kernel, the jagged kernel and (optionally) blend2d, interleaved."""
    call = kernel_call(scene)
    runs = {"catmull": lambda: call(False), "catmull-jagged": lambda: call(True)}
    if blend2d:
        from aaeval import registries
        from aaeval.renderers import render

        registries.load()
        runs["blend2d"] = lambda: render(scene, "blend2d")
    seconds = {name: [] for name in runs}
    for repeat in range(repeats + 1):
        for name, run in runs.items():
            start = time.perf_counter()
            run()
            if repeat:  # the first round warms up
                seconds[name].append(time.perf_counter() - start)
    return {name: median_ms(s) for name, s in seconds.items()}


def mapped_base(data: Path) -> tuple[int, int, int]:
    """(address, length, file offset) of the dev module's code in the recorded process."""
    events = subprocess.run(["perf", "script", "-i", data, "--show-mmap-events"], capture_output=True, text=True,
                            check=True).stdout
    for line in events.splitlines():
        if "MMAP" in line and str(MODULE) in line and "r-xp" in line:
            found = re.search(r"\[(0x[0-9a-f]+)\((0x[0-9a-f]+)\) @ (0x[0-9a-f]+)", line)
            return tuple(int(g, 16) for g in found.groups())
    raise SystemExit(f"profile_catmull: {MODULE.name} was not mapped in the recorded run")


def sampled_offsets(data: Path) -> collections.Counter:
    """Samples per address inside the dev module (as file offsets, for addr2line)."""
    start, length, offset = mapped_base(data)
    ips = subprocess.run(["perf", "script", "-i", data, "-F", "ip"], capture_output=True, text=True,
                         check=True).stdout.split()
    counts = collections.Counter()
    for ip in map(lambda s: int(s, 16), ips):
        if start <= ip < start + length:
            counts[ip - start + offset] += 1
    return counts


def inline_chains(addresses: list[int]) -> list[list[tuple[str, str]]]:
    """Each address's (function, file:line) from the innermost inlined call outwards."""
    text = subprocess.run(["addr2line", "-e", MODULE, "-f", "-C", "-i", "-a"],
                          input="\n".join(map(hex, addresses)), capture_output=True, text=True, check=True).stdout
    chains: list[list[str]] = []
    for line in text.splitlines():
        if line.startswith("0x"):
            chains.append([])
        else:
            chains[-1].append(line)
    return [list(zip(c[0::2], c[1::2])) for c in chains]


def part_of(chain: list[tuple[str, str]]) -> str:
    """Which of PARTS an address's work belongs to."""
    names = " ".join(name for name, _ in chain)
    visibility = any(key in names for key in VISIBILITY)
    if "geometry.hpp" in chain[0][1] and visibility:
        return PARTS[0]
    return PARTS[1] if visibility else PARTS[2]


def shares(data: Path) -> dict[str, float]:
    """Fraction of the module's samples in each part."""
    counts = sampled_offsets(data)
    addresses = list(counts)
    per_part = collections.Counter()
    for address, chain in zip(addresses, inline_chains(addresses)):
        per_part[part_of(chain) if chain else PARTS[2]] += counts[address]
    total = sum(per_part.values())
    return {part: per_part[part] / total for part in PARTS}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", nargs=3, type=float, default=[512, 32000, 20], metavar=("SIDE", "TRIANGLES", "SIZE"))
    parser.add_argument("--tiger", type=int, metavar="SEED", help="a tiger-like illustration instead (held out: 1, 2)")
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--blend2d", action="store_true", help="time the blend2d method on the same scene too")
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if MODULE is None:
        raise SystemExit("profile_catmull: no aaeval/native/catmull.*.so: build it first (see this script's doc)")
    scene = make_scene(args.scene, args.tiger)
    if args.worker:
        loop(scene, args.repeats)
        return
    ms = timings(scene, args.repeats, args.blend2d)
    with tempfile.TemporaryDirectory() as tmp:
        data = Path(tmp) / "perf.data"
        worker = [sys.executable, __file__, "--worker", "--scene", *map(str, args.scene), "--repeats", str(args.repeats)]
        worker += ["--tiger", str(args.tiger)] if args.tiger is not None else []
        subprocess.run(["perf", "record", "-q", "-F", "2000", "-o", data, *worker], check=True)
        part = shares(data)
    print(f"{scene.source}: {scene.width}x{scene.height}, {len(scene.arrays.start)} polygons; "
          f"medians of {args.repeats} interleaved renders")
    for name, value in ms.items():
        print(f"  {name:16s} {value:8.1f} ms")
    for name in PARTS:
        print(f"  {part[name]:6.1%}  {part[name] * ms['catmull']:7.1f} ms  {name}")
    floor = ms["catmull-jagged"] + part[PARTS[0]] * ms["catmull"]
    line = f"  floor (jagged + visibility clip arithmetic) {floor:.1f} ms"
    if "blend2d" in ms:
        line += f" = {floor / ms['blend2d']:.2f}x blend2d; catmull {ms['catmull'] / ms['blend2d']:.2f}x blend2d"
    print(line)


if __name__ == "__main__":
    main()
