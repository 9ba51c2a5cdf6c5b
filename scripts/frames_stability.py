"""How many frames the default experiment's moving groups need: each regular sampler's
spread (flicker of the error; the intensity sum's variation) at 8, 16, 32 and 64 frames of
seeded random sub-pixel offsets, against the exact box-filtered truth (Catmull).

    python scripts/frames_stability.py        # a Markdown table (docs/sweeps.md quotes it)

A spread is stable at N frames when it is close to its value at 64. The flicker (an RMS over
frames) settles fast; a sum variation (max - min) is an extreme and grows while rare phases
are still being met.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np

from aaeval import registries
from aaeval.catmull import render_flat
from aaeval.metrics import flicker, relative_variation
from aaeval.renderers import MethodSpec, render
from aaeval.scenes import parse_scene
from aaeval.scenes.generate import generate_scene

registries.load()  # a program fills the registries once, before it renders

ROOT = Path(__file__).resolve().parents[1]
COUNTS = (8, 16, 32, 64)
METHODS = ("point", "supersample:k=4", "abuffer", "msaa")
MOTION = {"frames": max(COUNTS), "phases": "random", "seed": 1}  # the default experiment's motion


def scenes() -> dict:
    out = {}
    for difficulty in (0.05, 0.2):
        document = dict(generate_scene("edges", difficulty, size=24))
        out[f"edges@{difficulty}"] = parse_scene({**document, "animation": MOTION})
    for name in ("khan_triangles_a", "abutting", "picket_fence", "picket_fence_moire_21"):
        document = tomllib.loads((ROOT / "configs" / "scenes" / f"{name}.toml").read_text())
        out[name] = parse_scene({**document, "animation": MOTION}, source=name)
    return out


def main() -> None:
    print("| scene | method | " + " | ".join(f"flicker, {n} frames" for n in COUNTS) + " | "
          + " | ".join(f"sum var, {n}" for n in COUNTS) + " |")
    print("|" + "---|" * (2 + 2 * len(COUNTS)))
    for name, scene in scenes().items():
        truth = np.stack([render_flat(scene.at_frame(k)) for k in range(scene.frames)])
        for method in METHODS:
            spec = MethodSpec.parse(method)
            test = np.stack([render(scene, spec, frame=k) for k in range(scene.frames)])
            sums = test.sum(axis=(1, 2, 3))
            fl = [f"{flicker(truth[:n], test[:n]):.3e}" for n in COUNTS]
            sv = [f"{relative_variation(sums[:n]):.3e}" for n in COUNTS]
            print(f"| {name} | {method} | " + " | ".join(fl + sv) + " |")


if __name__ == "__main__":
    main()
