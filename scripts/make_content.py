"""Rebuild the shipped real-content scenes in configs/scenes/content/.

    PYTHONPATH=$PWD python3 scripts/make_content.py

Writes map.svg (a seeded tiling) and imports every scene with ``aaeval import``: the
pangram at 9, 12 and 16 px, the icon set, the map and the illustration, each animated by
1/8 px steps (the scrolling case). The SVGs icons.svg and illustration.svg are
hand-written for aaeval (CC0 1.0, stated in each file).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from aaeval.cli import main

CONTENT = Path(__file__).resolve().parents[1] / "configs" / "scenes" / "content"
PANGRAM = "The quick brown fox jumps over the lazy dog"
FRAMES = 8


def map_svg(seed: int = 14, cols: int = 12, rows: int = 8, cell: float = 8.0, origin=(2.3, 2.6)) -> str:
    """A map-like tiling: jittered quadrilateral cells sharing every edge and vertex,
    coloured by the nearest of a few region seeds (neighbours of one colour still abut)."""
    rng = np.random.default_rng(seed)
    gx, gy = np.meshgrid(np.arange(cols + 1) * cell, np.arange(rows + 1) * cell)
    jitter = rng.uniform(-0.3, 0.3, (2, rows + 1, cols + 1)) * cell
    jitter[:, [0, -1], :] = 0.0  # straight outer border
    jitter[:, :, [0, -1]] = 0.0
    x, y = gx + jitter[0] + origin[0], gy + jitter[1] + origin[1]
    seeds = rng.uniform([0, 0], [cols * cell, rows * cell], (7, 2)) + origin
    palette = ["#e5c494", "#b3cde3", "#ccebc5", "#decbe4", "#fed9a6", "#f4cae4", "#d9d9a0"]
    lines = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{cols * cell + 5:g}" height="{rows * cell + 5:g}">',
             "  <!-- A map-like tiling of quadrilaterals sharing edges, made for aaeval by",
             f"       scripts/make_content.py (seed {seed}); licence: CC0 1.0 (public domain dedication). -->"]
    for r in range(rows):
        for c in range(cols):
            corners = [(x[r, c], y[r, c]), (x[r, c + 1], y[r, c + 1]), (x[r + 1, c + 1], y[r + 1, c + 1]), (x[r + 1, c], y[r + 1, c])]
            centre = np.mean(corners, axis=0)
            region = int(np.argmin(np.hypot(*(seeds - centre).T)))
            d = "M " + " L ".join(f"{px:.4f} {py:.4f}" for px, py in corners) + " Z"
            lines.append(f'  <path id="cell-{r}-{c}" fill="{palette[region]}" d="{d}"/>')
    lines.append("</svg>")
    return "\n".join(lines) + "\n"


def run(*args: str) -> None:
    code = main(list(args))
    if code:
        sys.exit(code)


if __name__ == "__main__":
    (CONTENT / "map.svg").write_text(map_svg())
    anim = ["--frames", str(FRAMES)]
    run("import", "text", PANGRAM, "--size", "9", "12", "16", "-o", str(CONTENT / "pangram.toml"),
        *anim, "--translate", "0", "0.125")
    for name in ("icons", "map", "illustration"):
        run("import", "svg", str(CONTENT / f"{name}.svg"), "-o", str(CONTENT / f"{name}.toml"), "--strict",
            *anim, "--translate", "0.125", "0.0625")
