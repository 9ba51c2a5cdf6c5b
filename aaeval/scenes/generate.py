"""Scene generators and a writer for the core keys of the scene format.

Every generator builds the scene as the dictionary a TOML file would parse to and hands
it to :func:`~aaeval.scenes.format.parse_scene`, so what it returns has passed the same
validation as a file. :func:`write_scene` writes a scene back as TOML in the core keys
only; reading the file again gives the same numbers bit for bit (floats are written with
``repr``, which round-trips).
"""

from __future__ import annotations

import colorsys
import math
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from aaeval.imageio import atomic_write
from aaeval.scenes.format import Scene, SceneError, parse_scene

__all__ = [
    "fan",
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


# --- writing ------------------------------------------------------------------------


def scene_to_dict(scene: Scene) -> dict[str, Any]:
    """The core-key dictionary of a scene at frame 0 (what its TOML file parses to).

    A scene at a later frame is first moved back to frame 0, which may change the last
    bit of its coordinates (``x + k t - k t``); a scene at frame 0 is written exactly.

    Raises
    ------
    ValueError
        The scene carries extension tables, which the core format cannot hold.
    """
    if scene.extensions:
        raise ValueError(
            f"{scene.source}: scene has extension tables {sorted(scene.extensions)}; "
            "only the core keys can be written"
        )
    scene = scene.at_frame(0)
    document: dict[str, Any] = {
        "image": {
            "width": scene.width,
            "height": scene.height,
            "background": scene.background.tolist(),
        }
    }
    if scene.frames != 1 or scene.translate.any():
        document["animation"] = {"frames": scene.frames, "translate": scene.translate.tolist()}
    document["polygons"] = [
        {"color": p.color.tolist(), "vertices": p.vertices.tolist()} for p in scene.polygons
    ]
    return document


def write_scene(scene: Scene | Mapping[str, Any], path: str | Path, *, comment: str | None = None) -> Path:
    """Write a scene (or a scene dictionary) as TOML in the core keys, atomically.

    A dictionary is validated with :func:`parse_scene` first, so nothing invalid is
    written. ``comment`` becomes a ``#`` header. Returns the path.
    """
    path = Path(path)
    if not isinstance(scene, Scene):
        scene = parse_scene(scene, source=str(path))
    text = _header(comment) + _toml(scene_to_dict(scene))
    atomic_write(path, lambda tmp: Path(tmp).write_text(text))
    return path


def _header(comment: str | None) -> str:
    if not comment:
        return ""
    return "".join(f"# {line}".rstrip() + "\n" for line in comment.strip("\n").splitlines()) + "\n"


def _toml(document: Mapping[str, Any]) -> str:
    lines = ["[image]"]
    lines += [f"{k} = {_value(v)}" for k, v in document["image"].items()]
    if "animation" in document:
        lines += ["", "[animation]"]
        lines += [f"{k} = {_value(v)}" for k, v in document["animation"].items()]
    for p in document["polygons"]:
        lines += ["", "[[polygons]]", f"color = {_value(p['color'])}", "vertices = ["]
        lines += [f"  {_value(v)}," for v in p["vertices"]]
        lines.append("]")
    return "\n".join(lines) + "\n"


def _value(v: Any) -> str:
    if isinstance(v, bool):
        raise SceneError(f"booleans have no place in the core scene format, got {v!r}")
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise SceneError(f"non-finite number {v!r} cannot be written")
        return repr(v)  # shortest string that reads back as the same float; valid TOML
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} in a scene file")


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
