"""Scene generators for experiments: scenes built from a difficulty value.

A generator is a plain function ``generate(difficulty, **params) -> dict`` returning a
scene document (the parsed-TOML form of the scene format), registered with
:func:`register_generator` under a name, with the label of its difficulty axis. The
stability experiment sweeps a generator over increasing difficulty to find where each
method starts to fail.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

__all__ = ["GENERATORS", "Generator", "register_generator", "generate_scene"]


@dataclass(frozen=True)
class Generator:
    name: str
    make: Callable[..., dict]
    difficulty: str  # what the difficulty value measures, for axis labels
    params: tuple[str, ...]


GENERATORS: dict[str, Generator] = {}


def register_generator(name: str, *, difficulty: str, params: tuple[str, ...] = ()):
    """Decorator registering ``make(difficulty, **params) -> scene document``."""

    def decorate(func):
        if name in GENERATORS:
            raise ValueError(f"generator {name!r} is registered twice")
        GENERATORS[name] = Generator(name, func, difficulty, tuple(params))
        return func

    return decorate


def generate_scene(name: str, difficulty: float, **params: Any) -> dict:
    """The scene document generator ``name`` builds at ``difficulty``."""
    if name not in GENERATORS:
        raise ValueError(f"unknown scene generator {name!r}; available: {', '.join(sorted(GENERATORS))}")
    gen = GENERATORS[name]
    unknown = sorted(set(params) - set(gen.params))
    if unknown:
        raise ValueError(f"generator {name!r}: unknown parameter(s) {unknown}; parameters: {list(gen.params)}")
    return gen.make(difficulty, **params)


def _palette(i: int) -> list[float]:
    # distinct, fully saturated-ish colours so every polygon's share of a pixel shows
    colours = [[0.9, 0.1, 0.1], [0.1, 0.8, 0.2], [0.15, 0.25, 0.95], [0.95, 0.85, 0.1],
               [0.8, 0.2, 0.9], [0.1, 0.85, 0.85], [0.95, 0.5, 0.1], [0.5, 0.5, 0.5]]
    return colours[i % len(colours)]


def _animation(frames: int, step: float) -> dict:
    # an irrational-looking direction so edges cross sample positions at many phases
    return {"frames": int(frames), "translate": [step, step * 0.61803398875]}


@register_generator("fan", difficulty="polygons meeting in one pixel", params=("size", "frames", "step"))
def fan(difficulty: float, *, size: int = 9, frames: int = 1, step: float = 0.125) -> dict:
    """``N = difficulty`` triangles meeting at one point inside the centre pixel.

    The centre pixel holds all N polygons (plus their shared vertex), the case the
    two-polygons-per-pixel implementation in the seeds could not handle.
    """
    n = int(round(difficulty))
    if n < 3:
        raise ValueError(f"fan: difficulty (number of triangles) must be >= 3, got {difficulty}")
    cx = cy = size / 2 + 0.137  # off the pixel centre, so point samples do not hit the apex
    radius = size  # reaches past the image on every side
    polygons = []
    for i in range(n):
        a0 = 2 * math.pi * i / n + 0.3
        a1 = 2 * math.pi * (i + 1) / n + 0.3
        tri = [[cx, cy, 1.0],
               [cx + radius * math.cos(a0), cy + radius * math.sin(a0), 1.0],
               [cx + radius * math.cos(a1), cy + radius * math.sin(a1), 1.0]]
        polygons.append({"color": _palette(i), "vertices": tri})
    return {"image": {"width": size, "height": size, "background": [0.0, 0.0, 0.0]},
            "animation": _animation(frames, step), "polygons": polygons}


@register_generator("sliver", difficulty="1 / sliver width (1/px)", params=("size", "frames", "step", "count"))
def sliver(difficulty: float, *, size: int = 16, frames: int = 1, step: float = 0.125, count: int = 3) -> dict:
    """``count`` long slivers of width ``1 / difficulty`` pixels, slightly tilted.

    Thinner than a pixel, a sliver falls between point samples on some rows and frames
    and is hit on others; its exact coverage is its width times its length.
    """
    if difficulty <= 0:
        raise ValueError(f"sliver: difficulty (1 / width) must be > 0, got {difficulty}")
    width = 1.0 / difficulty
    polygons = []
    for i in range(count):
        # inside the frame with room for the animation's drift, so the true sum is constant
        x0 = size * (0.15 + 0.5 * i / max(count - 1, 1)) + 0.21 * i
        tilt = 0.9  # pixels of horizontal drift from top to bottom
        top, bottom = 1.0, size - 1.5
        quad = [[x0, top, 1.0], [x0 + width, top, 1.0], [x0 + width + tilt, bottom, 1.0], [x0 + tilt, bottom, 1.0]]
        polygons.append({"color": [1.0, 1.0, 1.0], "vertices": quad})
    return {"image": {"width": size, "height": size, "background": [0.05, 0.05, 0.1]},
            "animation": _animation(frames, step), "polygons": polygons}


@register_generator("edges", difficulty="edge slope (rise per pixel run)", params=("size", "frames", "step"))
def edges(difficulty: float, *, size: int = 24, frames: int = 8, step: float = 0.125) -> dict:
    """Nearly axis-aligned edges (slope ``difficulty``, at most about 0.2 so the scene
    stays inside the frame) moving by sub-pixel steps.

    Small slopes make the long staircases and crawling edges of point sampling; the
    occluding quad in front exercises hidden-surface removal inside pixels.
    """
    s = float(difficulty)
    lo, hi = 0.12 * size, 0.8 * size  # room for the drift of the animation inside the frame
    back = [[lo + 0.3, 0.2 * size, 2.0], [hi, 0.2 * size + s * (hi - lo), 2.0],
            [hi - 0.2, 0.7 * size + s * (hi - lo), 2.0], [lo + 0.1, 0.7 * size, 2.0]]
    front = [[0.3 * size + 0.07, 0.1 * size + 0.4, 1.0], [0.62 * size, 0.1 * size + 0.77, 1.0],
             [0.62 * size - s * 0.6 * size, 0.85 * size, 1.0]]
    return {"image": {"width": size, "height": size, "background": [0.02, 0.02, 0.02]},
            "animation": _animation(frames, step),
            "polygons": [{"color": [0.95, 0.9, 0.3], "vertices": back},
                         {"color": [0.2, 0.45, 0.95], "vertices": front}]}
