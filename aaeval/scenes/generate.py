"""Every generated scene: the builders and the one registry of generators.

- Builders (:func:`fan`, :func:`slivers`, :func:`picket_fence`, :func:`random_triangles`,
  :func:`random_polygons`) build a scene as the dictionary a TOML file would parse to and
  hand it to :func:`~aaeval.scenes.document.parse_scene`, so what they return has passed
  the same validation as a file.
- Generators (:data:`GENERATORS`, :func:`register_generator`, :func:`generate_scene`):
  scenes built from one *difficulty* value, which sweeps (``generator = "fan"`` in an
  experiment config) raise to find where each method starts to fail. Every generator
  declares the range of its difficulty and each parameter's type, default (given once,
  here) and range; :func:`generate_scene` checks them all, and the size of what would be
  built (:data:`MAX_POLYGONS`, :data:`MAX_PIXEL_FRAMES`), before building anything, and
  refuses bad input with a one-line :class:`GeneratorError` naming the generator, the
  parameter and the rule.
- :func:`~aaeval.scenes.write.write_scene` (beside the reader, in :mod:`aaeval.scenes.write`)
  writes a scene back as TOML; it is re-exported here.
"""

from __future__ import annotations

import colorsys
import math
from dataclasses import dataclass
from typing import Any, Callable, Mapping

import numpy as np

from aaeval.options import Option, Registry
from aaeval.scenes.document import parse_scene
from aaeval.scenes.format import Scene, SceneError
from aaeval.scenes.write import scene_to_dict, write_scene

__all__ = [
    "GENERATORS",
    "Generator",
    "GeneratorError",
    "coplanar_stack",
    "MAX_POLYGONS",
    "MAX_PIXEL_FRAMES",
    "register_generator",
    "generate_scene",
    "fan",
    "illustration_like",
    "picket_fence",
    "random_polygons",
    "random_triangles",
    "scene_to_dict",
    "slivers",
    "write_scene",
]


# --- generators ---------------------------------------------------------------------


def random_triangles(
    n: int,
    width: int = 512,
    height: int = 512,
    *,
    size: float = 40.0,
    depth_range: tuple[float, float] = (0.0, 100.0),
    seed: int = 0,
) -> Scene:
    """``n`` random triangles with independent random vertex depths, so they interpenetrate.

    Each triangle has a centre uniform over the image and vertices uniform in a
    ``size`` x ``size`` box around it (so some reach beyond the image); every vertex has
    its own depth uniform in ``depth_range``, which tilts the triangles and makes their
    depth planes cross. Colours are uniform in [0, 1)^3. The Catmull benchmark uses
    ``random_triangles(2000, 512, 512)``.
    """
    _check_count(n, "n")
    rng = np.random.default_rng(seed)
    centres = rng.uniform((0.0, 0.0), (width, height), size=(n, 1, 2))
    xy = centres + rng.uniform(-size / 2, size / 2, size=(n, 3, 2))
    z = rng.uniform(*depth_range, size=(n, 3, 1))
    colors = rng.uniform(0.0, 1.0, size=(n, 3))
    polygons = [_polygon(v, c) for v, c in zip(np.concatenate([xy, z], axis=2), colors)]
    return _scene(width, height, polygons, source=f"random_triangles(n={n}, seed={seed})")


def random_polygons(
    n: int,
    width: int = 128,
    height: int = 128,
    *,
    size: float = 30.0,
    vertices: tuple[int, int] = (5, 12),
    depth_range: tuple[float, float] = (0.0, 100.0),
    seed: int = 0,
) -> Scene:
    """``n`` random concave simple polygons: star-shaped outlines on tilted planes.

    Each polygon has a random number of vertices in ``vertices`` (inclusive) at jittered,
    strictly increasing angles around its centre (every angular gap below pi) and random
    radii between ``size / 8`` and ``size / 2``: such an outline is star-shaped from its
    centre, hence always simple, and usually concave. Its depth is a random plane whose
    depth over the polygon stays roughly within ``depth_range``, so polygons interpenetrate.
    """
    _check_count(n, "n")
    lo, hi = vertices
    if not 3 <= lo <= hi:
        raise ValueError(f"vertices must be (lo, hi) with 3 <= lo <= hi, got {vertices}")
    rng = np.random.default_rng(seed)
    z0, z1 = depth_range
    polygons = []
    for _ in range(n):
        k = int(rng.integers(lo, hi + 1))
        step = 2 * math.pi / k
        # jitter below half a step keeps consecutive angles increasing with gaps < pi
        angles = step * np.arange(k) + rng.uniform(-0.45, 0.45, k) * step + rng.uniform(0, 2 * math.pi)
        radii = rng.uniform(size / 8, size / 2, k)
        centre = rng.uniform((0.0, 0.0), (width, height))
        xy = centre + radii[:, None] * np.column_stack([np.cos(angles), np.sin(angles)])
        slope = rng.uniform(-1, 1, 2) * (z1 - z0) / (2 * size)
        depth = rng.uniform(z0, z1) + (xy - centre) @ slope
        polygons.append(_polygon(np.column_stack([xy, depth]), rng.uniform(0.0, 1.0, 3)))
    return _scene(width, height, polygons, source=f"random_polygons(n={n}, seed={seed})")


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
    _check_count(n, "n")
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
    return _scene(width, height, polygons, source=f"fan(n={n})")


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
    _check_count(n, "n")
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
    return _scene(image_width, image_height, polygons, source=f"slivers(width={width})")


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
    _check_count(bars, "bars")
    _check_count(frames, "frames")
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
    return _scene(
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
    _check_count(n, "n")
    polygons = [{"color": [i / n, 0.5, 0.25], "vertices": [[-1, -1, 2.0], [2.5 * size, -1, 2.0], [-1, 2.5 * size, 2.0]]}
                for i in range(n)]
    return _scene(size, size, polygons, source=f"coplanar_stack(n={n})")


def _blob(rng, centre, radius, k, wobble):
    t = np.sort(rng.uniform(0, 2 * math.pi, 1)) + 2 * math.pi * np.arange(k) / k
    r = np.ones(k)
    for m in range(2, 6):
        r += wobble / m * np.sin(m * t + rng.uniform(0, 2 * math.pi))
    r *= radius
    return centre + np.column_stack([r * np.cos(t), r * np.sin(t)]), r.min()


def _stroke(rng, size, k):
    start = rng.uniform(0, size, 2)
    heading = rng.uniform(0, 2 * math.pi)
    turn = rng.uniform(-0.02, 0.02)
    step = rng.uniform(1.5, 4.0)
    width = rng.uniform(0.6, 3.0)
    angles = heading + turn * np.arange(k)  # radius of curvature step/|turn| >= 75 px > width
    centre = start + np.cumsum(step * np.column_stack([np.cos(angles), np.sin(angles)]), axis=0)
    normal = np.column_stack([-np.sin(angles), np.cos(angles)])
    taper = width * np.sin(np.linspace(0.05, math.pi - 0.05, k))
    return np.concatenate([centre + taper[:, None] * normal, (centre - taper[:, None] * normal)[::-1]])


def illustration_like(seed: int = 0, n: int = 339, size: int = 512, stroke_share: float = 0.3) -> Scene:
    """A full-size illustration like the Ghostscript tiger, from a seed (the tiger itself
    is not shipped): a white background and ``n`` flat layers painted back to front, most
    of them smooth blobs of 24-160 vertices (curves flattened as an SVG import would), a
    fifth of those with a hole, and ``stroke_share`` of them thin tapered curved strokes
    of 40-120 vertices like the tiger's whiskers. A blob is star-shaped about its centre
    and a stroke is a centre line offset by less than its radius of curvature, so every
    outline is simple; a hole is a smaller star-shaped ring within half the blob's inner
    radius. Seed 0 is the scene profiled while making Weiler-Atherton's indexed loop;
    seeds 1 and 2 are held out (``benchmarks/bench_real_art.py``).
    """
    rng = np.random.default_rng(seed)
    polygons = [{"color": [1.0, 1.0, 1.0],
                 "vertices": [[0, 0, n + 1], [size, 0, n + 1], [size, size, n + 1], [0, size, n + 1]]}]
    for i in range(n):
        z = float(n - i)  # later layers nearer: smaller depth
        color = rng.uniform(0, 1, 3).tolist()
        if rng.uniform() < stroke_share:
            xy = _stroke(rng, size, int(rng.integers(20, 60)))
            polygons.append({"color": color, "vertices": np.column_stack([xy, np.full(len(xy), z)]).tolist()})
            continue
        radius = size * rng.uniform(0.02, 0.18) * (1.0 - 0.6 * i / n)  # big shapes behind, details in front
        k = int(rng.integers(24, 161))
        centre = rng.uniform(0, size, 2)
        xy, rmin = _blob(rng, centre, radius, k, rng.uniform(0.05, 0.35))
        poly = {"color": color, "vertices": np.column_stack([xy, np.full(k, z)]).tolist()}
        if rng.uniform() < 0.2:  # a hole about the blob's own centre, inside half its inner radius
            hole, _ = _blob(rng, centre, 0.5 * rmin, int(rng.integers(12, 61)), 0.2)
            poly["holes"] = [np.column_stack([hole, np.full(len(hole), z)]).tolist()]
        polygons.append(poly)
    return _scene(size, size, polygons, source=f"illustration_like(seed={seed}, n={n})")


# --- helpers ------------------------------------------------------------------------


def _scene(width, height, polygons, *, animation=None, source) -> Scene:
    document: dict[str, Any] = {"image": {"width": int(width), "height": int(height)}, "polygons": polygons}
    if animation:
        document["animation"] = animation
    return parse_scene(document, source=source)


def _polygon(vertices: np.ndarray, color: np.ndarray) -> dict[str, Any]:
    return {"color": np.asarray(color, dtype=float).tolist(), "vertices": np.asarray(vertices, dtype=float).tolist()}


def _hue(h: float) -> list[float]:
    return list(colorsys.hsv_to_rgb(h, 1.0, 1.0))


def _check_count(n: Any, name: str) -> None:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"{name} must be a positive integer, got {n!r}")


# --- the generator registry ----------------------------------------------------------

# A generated scene holds at most this many polygons: validating 100k triangles takes
# about 30 s and 0.5 GB on one core, and every method renders each of them per frame.
MAX_POLYGONS = 100_000
# ... and at most this many pixels over all its frames (the scene format's pixel limit).
MAX_PIXEL_FRAMES = 1 << 28


class GeneratorError(SceneError):
    """A generator name, difficulty or parameter that is unknown, of the wrong type or
    out of range, or a scene too large to build; the message is one line."""


@dataclass(frozen=True)
class Generator:
    """A registered generator: ``make(difficulty, **params) -> scene document``.

    ``difficulty`` is what the difficulty value measures (for axis labels);
    ``difficulty_param`` its type and range; ``params`` the other parameters;
    ``size(difficulty, params) -> (polygons, pixels x frames)`` what the scene would hold,
    checked against the limits before ``make`` runs.
    """

    name: str
    make: Callable[..., dict]
    difficulty: str
    difficulty_param: Option
    params: Mapping[str, Option]
    size: Callable[[float, Mapping[str, Any]], tuple[int, int]]


GENERATORS: Registry = Registry("scene generator", GeneratorError)


def register_generator(
    name: str,
    make: Callable[..., dict] | None = None,
    *,
    difficulty: str,
    difficulty_param: Option,
    params: Mapping[str, Option],
    size: Callable[[float, Mapping[str, Any]], tuple[int, int]],
):
    """Register ``make(difficulty, **params) -> scene document`` under ``name``:
    ``register_generator(name, make, ...)`` or ``@register_generator(name, ...)``."""

    def decorate(func):
        GENERATORS.add(name, Generator(name, func, difficulty, difficulty_param, dict(params), size))
        return func

    return decorate if make is None else decorate(make)


def generate_scene(name: str, difficulty: float, **params: Any) -> dict:
    """The scene document generator ``name`` builds at ``difficulty``.

    Every parameter not given takes its declared default. Raises :class:`GeneratorError`
    (one line) for an unknown generator or parameter, a value of the wrong type or out of
    range, or a scene over :data:`MAX_POLYGONS` polygons or :data:`MAX_PIXEL_FRAMES`
    pixels x frames (with the estimate), before building anything.
    """
    gen = GENERATORS.get_entry(name)
    unknown = sorted(set(params) - set(gen.params))
    if unknown:
        raise GeneratorError(f"generator {name!r}: unknown parameter(s) {unknown}; parameters: {sorted(gen.params)}")
    d = gen.difficulty_param.convert(difficulty, f"generator {name!r}: difficulty ({gen.difficulty_param.doc})",
                                    GeneratorError)
    values = {key: p.default for key, p in gen.params.items()}
    for key, value in params.items():
        values[key] = gen.params[key].convert(value, f"generator {name!r}: parameter {key}", GeneratorError)
    polygons, pixel_frames = gen.size(d, values)
    if polygons > MAX_POLYGONS:
        raise GeneratorError(f"generator {name!r} at difficulty {d:g} would build {polygons} polygons; "
                             f"the limit is {MAX_POLYGONS}")
    if pixel_frames > MAX_PIXEL_FRAMES:
        raise GeneratorError(f"generator {name!r} would render {pixel_frames} pixels over all frames; "
                             f"the limit is {MAX_PIXEL_FRAMES}")
    try:
        return gen.make(d, **values)
    except GeneratorError:
        raise
    except (SceneError, ValueError) as exc:  # a combination the builder cannot lay out
        raise GeneratorError(f"generator {name!r} at difficulty {d:g}: {exc}") from None


def _animation(frames: int, step: float) -> dict:
    # an irrational-looking direction so edges cross sample positions at many phases
    return {"frames": int(frames), "translate": [step, step * 0.61803398875]}


def _animated(scene: Scene, frames: int, step: float) -> dict:
    document = scene_to_dict(scene)
    if frames > 1:
        document["animation"] = _animation(frames, step)
    return document


# Parameters shared by several generators (declared once)
MAX_SIDE = 16384  # the scene format's largest image side
_FRAMES = Option(int, 1, "frames of the animation (1 = a still scene)", minimum=1, maximum=100_000)
_STEP = Option(float, 0.125, "sub-pixel translation per frame (px)", minimum=-64.0, maximum=64.0)


def _size(default: int, doc: str = "image width and height (px)") -> Option:
    return Option(int, default, doc, minimum=4, maximum=MAX_SIDE)


def _square(size_key: str = "size", polygons: Callable[[float, Mapping[str, Any]], int] = lambda d, p: 0):
    def size(d: float, p: Mapping[str, Any]) -> tuple[int, int]:
        return polygons(d, p), p[size_key] ** 2 * p["frames"]

    return size


@register_generator(
    "fan",
    difficulty="polygons meeting in one pixel",
    difficulty_param=Option(float, None, "number of wedges, rounded", minimum=3),
    params={"size": _size(9), "frames": _FRAMES, "step": _STEP},
    size=_square(polygons=lambda d, p: int(round(d))),
)
def _fan(difficulty: float, *, size: int, frames: int, step: float) -> dict:
    """:func:`fan`: ``N = difficulty`` wedges meeting inside one pixel."""
    return _animated(fan(int(round(difficulty)), size, size), frames, step)


@register_generator(
    "sliver",
    difficulty="1 / sliver width (1/px)",
    difficulty_param=Option(float, None, "1 / width of each bar, 1/px", minimum=0, maximum=1e6, low_open=True),
    params={"size": _size(16), "frames": _FRAMES, "step": _STEP,
            "count": Option(int, 4, "number of bars", minimum=1, maximum=MAX_POLYGONS)},
    size=_square(polygons=lambda d, p: p["count"]),
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
    return _animated(slivers(1.0 / difficulty, size, size, n=count, length=length), frames, step)


@register_generator(
    "picket",
    difficulty="bars per pixel",
    difficulty_param=Option(float, None, "bars per pixel, 1 / period", minimum=0, maximum=1e6, low_open=True),
    params={"bar_width": Option(float, 0.3, "bar width as a fraction of the period", minimum=0, maximum=1, low_open=True),
            "bars": Option(int, 12, "number of bars", minimum=1, maximum=MAX_POLYGONS),
            "width": _size(24, "image width (px)"), "height": _size(6, "image height (px)"),
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
    params={"size": _size(128), "frames": _FRAMES, "step": _STEP,
            "seed": Option(int, 0, "seed of the random scene", minimum=0, maximum=2**63 - 1)},
    size=_square(polygons=lambda d, p: int(round(d))),
)
def _random(difficulty: float, *, size: int, frames: int, step: float, seed: int) -> dict:
    """:func:`random_triangles`: interpenetrating triangles, for timing."""
    n = int(round(difficulty))
    return _animated(random_triangles(n, size, size, size=max(4.0, size / 8), seed=seed), frames, step)


@register_generator(
    "edges",
    difficulty="edge slope (rise per pixel run)",
    difficulty_param=Option(float, None, "slope of the near-horizontal edges", minimum=0, maximum=0.3),
    params={"size": _size(24), "frames": Option(int, 8, _FRAMES.doc, minimum=1, maximum=100_000), "step": _STEP},
    size=_square(polygons=lambda d, p: 2),
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


_SEGMENTS = Option(int, 48, "facets around the cylinder", minimum=3, maximum=MAX_POLYGONS // 4)


def _cylinder_polygons(d: float, p: Mapping[str, Any]) -> int:
    return 4 * p["segments"]  # two side triangles and two cap triangles per facet


@register_generator(
    "shininess",
    difficulty="Phong exponent n",
    difficulty_param=Option(float, None, "Phong exponent of the cylinder", minimum=1, maximum=1e6),
    params={"size": _size(32), "radius": Option(float, 9.0, "cylinder radius (px)", minimum=0, maximum=1e6, low_open=True),
            "frames": _FRAMES, "step": _STEP, "segments": _SEGMENTS},
    size=_square(polygons=_cylinder_polygons),
)
def _shininess(difficulty: float, *, size: int, radius: float, frames: int, step: float, segments: int) -> dict:
    """A shiny cylinder whose Phong exponent is ``difficulty``: the highlight narrows as it grows."""
    return _shiny_cylinder(size, radius, difficulty, frames, step, segments)


@register_generator(
    "curvature",
    difficulty="curvature 1 / radius (1/px)",
    difficulty_param=Option(float, None, "1 / cylinder radius, 1/px", minimum=0, maximum=2, low_open=True),
    params={"size": _size(32), "n": Option(float, 200.0, "Phong exponent of the cylinder", minimum=1, maximum=1e6),
            "frames": _FRAMES, "step": _STEP, "segments": _SEGMENTS},
    size=_square(polygons=_cylinder_polygons),
)
def _curvature(difficulty: float, *, size: int, n: float, frames: int, step: float, segments: int) -> dict:
    """A shiny cylinder of radius ``1 / difficulty``: the normal turns faster across a pixel as it grows."""
    return _shiny_cylinder(size, min(1.0 / difficulty, 0.4 * size), n, frames, step, segments)
