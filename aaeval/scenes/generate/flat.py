"""The generators of flat scenes: wedges meeting in one pixel (``fan``), sub-pixel bars
(``sliver``), a moving picket fence (``picket``), random triangles (``random``) and
nearly axis-aligned edges (``edges``)."""

from __future__ import annotations

from aaeval.options import Option
from aaeval.scenes.generate.params import FRAMES, STEP, animated, animation_table, image_side, square_image
from aaeval.scenes.generate.patterns import fan, picket_fence, slivers
from aaeval.scenes.generate.random_scenes import random_triangles
from aaeval.scenes.generate.registry import MAX_POLYGONS, GeneratorError, register_generator
from aaeval.scenes.write import scene_to_dict


@register_generator(
    "fan",
    difficulty="polygons meeting in one pixel",
    difficulty_param=Option(float, None, "number of wedges, rounded", minimum=3),
    params={"size": image_side(9), "frames": FRAMES, "step": STEP},
    size=square_image(polygons=lambda d, p: int(round(d))),
)
def _fan(difficulty: float, *, size: int, frames: int, step: float) -> dict:
    """:func:`fan`: ``N = difficulty`` wedges meeting inside one pixel."""
    return animated(fan(int(round(difficulty)), size, size), frames, step)


@register_generator(
    "sliver",
    difficulty="1 / sliver width (1/px)",
    difficulty_param=Option(float, None, "1 / width of each bar, 1/px", minimum=0, maximum=1e6, low_open=True),
    params={"size": image_side(16), "frames": FRAMES, "step": STEP,
            "count": Option(int, 4, "number of bars", minimum=1, maximum=MAX_POLYGONS)},
    size=square_image(polygons=lambda d, p: p["count"]),
)
def _sliver(difficulty: float, *, size: int, frames: int, step: float, count: int) -> dict:
    """:func:`slivers`: ``count`` bars ``1 / difficulty`` pixels wide.

    Thinner than a pixel, a sliver falls between point samples on some rows and frames
    and is hit on others; its exact coverage is its width times its length.
    """
    # shorter than the image by the animation's drift, so the true sum stays constant
    length = 0.9 * size - 2 * frames * abs(step)
    if length <= 0:
        raise GeneratorError(f"generator 'sliver': {frames} frames of step {step} drift further than the "
                             f"image of size {size} is wide")
    return animated(slivers(1.0 / difficulty, size, size, n=count, length=length), frames, step)


@register_generator(
    "picket",
    difficulty="bars per pixel",
    difficulty_param=Option(float, None, "bars per pixel, 1 / period", minimum=0, maximum=1e6, low_open=True),
    params={"bar_width": Option(float, 0.3, "bar width as a fraction of the period", minimum=0, maximum=1, low_open=True),
            "bars": Option(int, 12, "number of bars", minimum=1, maximum=MAX_POLYGONS),
            "width": image_side(24, "image width (px)"), "height": image_side(6, "image height (px)"),
            "frames": Option(int, 8, "frames (the fence moves one period over all of them)", minimum=1, maximum=100_000)},
    size=lambda d, p: (p["bars"], p["width"] * p["height"] * p["frames"]),
)
def _picket(difficulty: float, *, bar_width: float, bars: int, width: int, height: int, frames: int) -> dict:
    """:func:`picket_fence` with period ``1 / difficulty`` pixels."""
    if bar_width >= 1:
        raise GeneratorError(f"generator 'picket': parameter bar_width must be < 1 (a fraction of the period), "
                             f"got {bar_width!r}")
    period = 1.0 / difficulty
    return scene_to_dict(picket_fence(bar_width * period, period, bars=bars, width=width, height=height,
                                      frames=frames))


@register_generator(
    "random",
    difficulty="number of random triangles",
    difficulty_param=Option(float, None, "number of triangles, rounded", minimum=1),
    params={"size": image_side(128), "frames": FRAMES, "step": STEP,
            "seed": Option(int, 0, "seed of the random scene", minimum=0, maximum=2**63 - 1)},
    size=square_image(polygons=lambda d, p: int(round(d))),
)
def _random(difficulty: float, *, size: int, frames: int, step: float, seed: int) -> dict:
    """:func:`random_triangles`: interpenetrating triangles, for timing."""
    n = int(round(difficulty))
    return animated(random_triangles(n, size, size, size=max(4.0, size / 8), seed=seed), frames, step)


@register_generator(
    "edges",
    difficulty="edge slope (rise per pixel run)",
    difficulty_param=Option(float, None, "slope of the near-horizontal edges", minimum=0, maximum=0.3),
    params={"size": image_side(24), "frames": Option(int, 8, FRAMES.doc, minimum=1, maximum=100_000), "step": STEP},
    size=square_image(polygons=lambda d, p: 2),
)
def _edges(difficulty: float, *, size: int, frames: int, step: float) -> dict:
    """Nearly axis-aligned edges (slope ``difficulty``, at most 0.3 so the scene stays
    inside the frame) moving by sub-pixel steps.

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
            "animation": animation_table(frames, step),
            "polygons": [{"color": [0.95, 0.9, 0.3], "vertices": back},
                         {"color": [0.2, 0.45, 0.95], "vertices": front}]}
