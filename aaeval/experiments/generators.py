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


def _animation(frames: int, step: float) -> dict:
    # an irrational-looking direction so edges cross sample positions at many phases
    return {"frames": int(frames), "translate": [step, step * 0.61803398875]}


def _animated(scene, frames: int, step: float) -> dict:
    from aaeval.scenes.generate import scene_to_dict

    document = scene_to_dict(scene)
    if frames > 1:
        document["animation"] = _animation(frames, step)
    return document


@register_generator("fan", difficulty="polygons meeting in one pixel", params=("size", "frames", "step"))
def fan(difficulty: float, *, size: int = 9, frames: int = 1, step: float = 0.125) -> dict:
    """``aaeval.scenes.generate.fan``: ``N = difficulty`` wedges meeting inside one pixel."""
    from aaeval.scenes.generate import fan as make_fan

    n = int(round(difficulty))
    if n < 3:
        raise ValueError(f"fan: difficulty (number of wedges) must be >= 3, got {difficulty}")
    return _animated(make_fan(n, size, size), frames, step)


@register_generator("sliver", difficulty="1 / sliver width (1/px)", params=("size", "frames", "step", "count"))
def sliver(difficulty: float, *, size: int = 16, frames: int = 1, step: float = 0.125, count: int = 4) -> dict:
    """``aaeval.scenes.generate.slivers``: ``count`` bars ``1 / difficulty`` pixels wide.

    Thinner than a pixel, a sliver falls between point samples on some rows and frames
    and is hit on others; its exact coverage is its width times its length.
    """
    from aaeval.scenes.generate import slivers

    if difficulty <= 0:
        raise ValueError(f"sliver: difficulty (1 / width) must be > 0, got {difficulty}")
    # shorter than the image by the animation's drift, so the true sum stays constant
    length = 0.9 * size - 2 * frames * step
    return _animated(slivers(1.0 / difficulty, size, size, n=count, length=length), frames, step)


@register_generator("picket", difficulty="bars per pixel", params=("bar_width", "bars", "width", "height", "frames"))
def picket(difficulty: float, *, bar_width: float = 0.3, bars: int = 12, width: int = 24, height: int = 6,
           frames: int = 8) -> dict:
    """``aaeval.scenes.generate.picket_fence`` with period ``1 / difficulty`` pixels."""
    from aaeval.scenes.generate import picket_fence, scene_to_dict

    period = 1.0 / difficulty
    return scene_to_dict(picket_fence(bar_width * period, period, bars=bars, width=width, height=height,
                                      frames=frames))


@register_generator("random", difficulty="number of random triangles", params=("size", "frames", "step", "seed"))
def random(difficulty: float, *, size: int = 128, frames: int = 1, step: float = 0.125, seed: int = 0) -> dict:
    """``aaeval.scenes.generate.random_triangles``: interpenetrating triangles, for timing."""
    from aaeval.scenes.generate import random_triangles

    n = int(round(difficulty))
    return _animated(random_triangles(n, size, size, size=max(4.0, size / 8), seed=seed), frames, step)


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


def _shiny_cylinder(size: int, radius: float, n: float, frames: int, step: float, segments: int) -> dict:
    # one cylinder of the [shaded] extension (docs/shaded_scenes.md), lit from behind the
    # viewer, so the highlight runs along the axis where the normal faces the viewer
    c = size / 2
    return {
        "image": {"width": size, "height": size, "background": [0.02, 0.02, 0.03]},
        "animation": _animation(frames, step),
        "shaded": {
            "light": {"type": "directional", "direction": [0.3, 0.0, -1.0]},
            "cylinders": [{
                "centre": [c + 0.173, c + 0.291, 200.0], "axis": [0.12, 1.0, 0.0], "radius": float(radius),
                "length": 0.8 * size, "segments": int(segments),
                "spin": {"axis": [0.0, 0.0, 1.0], "degrees": 0.2},
                "material": {"color": [0.75, 0.12, 0.10], "ka": 0.15, "kd": 0.55, "ks": 0.8, "n": float(n)},
            }],
        },
    }


@register_generator("shininess", difficulty="Phong exponent n", params=("size", "radius", "frames", "step", "segments"))
def shininess(difficulty: float, *, size: int = 32, radius: float = 9.0, frames: int = 1, step: float = 0.125,
              segments: int = 48) -> dict:
    """A shiny cylinder whose Phong exponent is ``difficulty``: the highlight narrows as it grows."""
    if difficulty < 1:
        raise ValueError(f"shininess: difficulty (Phong exponent) must be >= 1, got {difficulty}")
    return _shiny_cylinder(size, radius, difficulty, frames, step, segments)


@register_generator("curvature", difficulty="curvature 1 / radius (1/px)", params=("size", "n", "frames", "step", "segments"))
def curvature(difficulty: float, *, size: int = 32, n: float = 200.0, frames: int = 1, step: float = 0.125,
              segments: int = 48) -> dict:
    """A shiny cylinder of radius ``1 / difficulty``: the normal turns faster across a pixel as it grows."""
    if not 0 < difficulty <= 2:
        raise ValueError(f"curvature: difficulty (1 / radius) must be in (0, 2], got {difficulty}")
    return _shiny_cylinder(size, min(1.0 / difficulty, 0.4 * size), n, frames, step, segments)
