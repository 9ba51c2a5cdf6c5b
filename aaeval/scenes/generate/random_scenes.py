"""Builders of random scenes from a seed: interpenetrating triangles
(:func:`random_triangles`), concave polygons on tilted planes (:func:`random_polygons`)
and a layered illustration like the Ghostscript tiger (:func:`illustration_like`)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from aaeval.scenes.format import Scene
from aaeval.scenes.generate.build import built_scene, check_count

__all__ = ["illustration_like", "random_polygons", "random_triangles"]


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
    check_count(n, "n")
    rng = np.random.default_rng(seed)
    centres = rng.uniform((0.0, 0.0), (width, height), size=(n, 1, 2))
    xy = centres + rng.uniform(-size / 2, size / 2, size=(n, 3, 2))
    z = rng.uniform(*depth_range, size=(n, 3, 1))
    colors = rng.uniform(0.0, 1.0, size=(n, 3))
    polygons = [_polygon(v, c) for v, c in zip(np.concatenate([xy, z], axis=2), colors)]
    return built_scene(width, height, polygons, source=f"random_triangles(n={n}, seed={seed})")


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
    check_count(n, "n")
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
    return built_scene(width, height, polygons, source=f"random_polygons(n={n}, seed={seed})")


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
    return built_scene(size, size, polygons, source=f"illustration_like(seed={seed}, n={n})")


def _polygon(vertices: np.ndarray, color: np.ndarray) -> dict[str, Any]:
    return {"color": np.asarray(color, dtype=float).tolist(), "vertices": np.asarray(vertices, dtype=float).tolist()}
