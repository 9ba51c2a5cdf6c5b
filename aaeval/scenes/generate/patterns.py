"""Builders of regular stress scenes: thin features meeting, crossing or moving at
sub-pixel scale (:func:`fan`, :func:`slivers`, :func:`picket_fence`) and a stack of
coplanar triangles (:func:`coplanar_stack`)."""

from __future__ import annotations

import colorsys
import math

import numpy as np

from aaeval.scenes.format import Scene
from aaeval.scenes.generate.build import built_scene, check_count

__all__ = ["coplanar_stack", "fan", "picket_fence", "slivers"]


def fan(
    n: int = 24,
    width: int = 32,
    height: int = 32,
    *,
    apex: tuple[float, float] | None = None,
    radius: float | None = None,
    gap: float = 0.0,
) -> Scene:
    """``n`` thin triangles (wedges) sharing one apex inside a pixel, in distinct colours.

    The wedges go round the full circle; ``gap`` (a fraction of each wedge's angle, in
    [0, 1)) leaves background between neighbours, ``gap=0`` makes them abut along shared
    edges. Colours are evenly spaced hues; depths are distinct (wedge ``i`` at depth
    ``i``). The apex defaults to an off-centre point of the middle pixel.
    """
    check_count(n, "n")
    if not 0.0 <= gap < 1.0:
        raise ValueError(f"gap must be in [0, 1), got {gap}")
    ax, ay = apex if apex is not None else (width // 2 + 0.3125, height // 2 + 0.5625)
    r = radius if radius is not None else 0.45 * min(width, height)
    step = 2 * math.pi / n

    def rim(angle: float) -> list[float]:
        return [ax + r * math.cos(angle), ay + r * math.sin(angle)]

    starts = [rim(i * step) for i in range(n)]
    # with no gap a wedge ends on the very point where the next begins: exactly shared edges
    ends = starts[1:] + starts[:1] if gap == 0.0 else [rim((i + 1 - gap) * step) for i in range(n)]
    polygons = []
    for i in range(n):
        z = float(i)
        v = [[ax, ay, z], [*starts[i], z], [*ends[i], z]]
        polygons.append({"color": _hue(i / n), "vertices": v})
    return built_scene(width, height, polygons, source=f"fan(n={n})")


def slivers(
    width: float = 0.1,
    image_width: int = 32,
    image_height: int = 32,
    *,
    n: int = 8,
    length: float | None = None,
) -> Scene:
    """``n`` long rectangles ``width`` pixels wide (sub-pixel), at evenly spread angles.

    They all pass through the image centre at depths ``0..n-1`` (a star of thin bars,
    crossing each other in the middle pixel), white over black: the case where a point
    sampler shows dotted lines and area sampling a faint, unbroken (if jagged) one.
    """
    check_count(n, "n")
    if not width > 0:
        raise ValueError(f"width must be > 0, got {width}")
    cx, cy = image_width / 2 + 0.25, image_height / 2 + 0.125
    half = (length if length is not None else 0.9 * min(image_width, image_height)) / 2
    polygons = []
    for i in range(n):
        angle = math.pi * (i + 0.5) / n
        d = np.array([math.cos(angle), math.sin(angle)])
        w = np.array([-d[1], d[0]]) * width / 2
        c = np.array([cx, cy])
        corners = [c - half * d - w, c + half * d - w, c + half * d + w, c - half * d + w]
        polygons.append({"color": [1.0, 1.0, 1.0], "vertices": [[*p, float(i)] for p in corners]})
    return built_scene(image_width, image_height, polygons, source=f"slivers(width={width})")


def picket_fence(
    bar_width: float = 0.3,
    period: float = 1.0,
    *,
    bars: int = 20,
    width: int = 32,
    height: int = 8,
    frames: int = 16,
    color: tuple[float, float, float] = (1.0, 1.0, 1.0),
) -> Scene:
    """Vertical bars thinner than a pixel, moving right by ``period / frames`` per frame.

    Over the ``frames`` frames the fence moves by one period less one step, staying
    wholly inside the image (one pixel of margin at the top and bottom, at least one at
    the sides), so its exact area average has the same intensity sum in every frame while
    a point sampler's sum swings (Catmull 1978: "for a fine picket fence the picture can
    be all white in one picture and all black in the next").
    """
    check_count(bars, "bars")
    check_count(frames, "frames")
    if not 0 < bar_width < period:
        raise ValueError(f"need 0 < bar_width < period, got {bar_width}, {period}")
    step = period / frames
    span = (bars - 1) * period + bar_width + (frames - 1) * step
    x0 = (width - span) / 2
    if x0 < 1.0:
        raise ValueError(f"{bars} bars of period {period} moving {frames} frames do not fit in width {width}")
    top, bottom = 1.0, height - 1.0
    polygons = []
    for i in range(bars):
        left = x0 + i * period
        right = left + bar_width
        v = [[left, top, 0.0], [right, top, 0.0], [right, bottom, 0.0], [left, bottom, 0.0]]
        polygons.append({"color": list(map(float, color)), "vertices": v})
    return built_scene(
        width,
        height,
        polygons,
        animation={"frames": frames, "translate": [step, 0.0]},
        source=f"picket_fence(bar_width={bar_width}, period={period})",
    )


def coplanar_stack(n: int = 3000, *, size: int = 12) -> Scene:
    """``n`` triangles on one plane, each covering the whole ``size`` x ``size`` image, in
    file order: the depth-tie rule's stress case (the latest is seen everywhere; a sampler
    that sorted a pixel's fragments by insertion would move them n^2 / 2 times)."""
    check_count(n, "n")
    polygons = [{"color": [i / n, 0.5, 0.25], "vertices": [[-1, -1, 2.0], [2.5 * size, -1, 2.0], [-1, 2.5 * size, 2.0]]}
                for i in range(n)]
    return built_scene(size, size, polygons, source=f"coplanar_stack(n={n})")


def _hue(h: float) -> list[float]:
    return list(colorsys.hsv_to_rgb(h, 1.0, 1.0))
