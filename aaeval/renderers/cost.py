"""What a render costs: counts read from a scene's polygon boxes, and the estimated time
of one render.

Memory and time are estimated from the scene in one pass over its polygons' bounding boxes
(:func:`scene_load`): ``pairs``, the polygon pairs whose boxes overlap (every method that
draws polygons first resolves near depth ties between such pairs, and Weiler-Atherton
clips them against each other), and ``depth_squares``, the sum over pixels of the squared
number of boxes over the pixel (a per-pixel sort of fragments, as the A-buffer's, costs
that). A method declares what it costs per unit once, in its ``register_method`` call
(``memory=``, ``seconds=``); the pass over the boxes costs O(polygons + pixels / cell).
:mod:`aaeval.renderers.budget` holds these estimates against the limits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from aaeval.renderers.registry import Method
from aaeval.scenes import Scene

__all__ = ["PAIR_BYTES", "PAIR_SECONDS", "SceneLoad", "render_seconds", "scene_load"]

# Every method that draws the polygons first groups near depth ties among polygons whose
# boxes overlap (aaeval.weiler_atherton.near_ties through catmull.kernel_inputs): per such
# pair, bytes held and seconds taken. Measured on 2000 and 4000 identical triangles in a
# 16x16 image (every pair overlapping): about 210 bytes and 1 microsecond per pair (and
# Weiler-Atherton on 1e4 of them: 11 GB, 44 s, i.e. 226 bytes and 0.9 us per pair in all).
PAIR_BYTES = 200
PAIR_SECONDS = 0.8e-6


@dataclass(frozen=True)
class SceneLoad:
    """What a scene costs to draw, from its polygons' bounding boxes (:func:`scene_load`)."""

    polygons: int
    vertices: int
    # polygon pairs whose boxes overlap (inside the image); estimated from a sample when large
    pairs: float
    # sum over pixels of (boxes over the pixel)^2, and of boxes over the pixel
    depth_squares: float
    fragments: float


# exact pair counts up to this many polygons; beyond, a sample of polygons against all
_EXACT_PAIRS = 2048
_PAIR_WORK = 1 << 22  # box comparisons the pair estimate may make (tens of milliseconds)
_GRID_CELLS = 1 << 18  # cells of the depth grid


def scene_load(scene: Scene) -> SceneLoad:
    """Counts of :class:`SceneLoad` for ``scene`` (boxes clipped to the image), computed
    once per scene object."""
    cached = scene.__dict__.get("_aaeval_scene_load")
    if cached is None:
        cached = _scene_load(scene)
        scene.__dict__["_aaeval_scene_load"] = cached  # a frozen dataclass: its cache, as cached_property's
    return cached


def _scene_load(scene: Scene) -> SceneLoad:
    polys = scene.polygons
    n = len(polys)
    if n == 0:
        return SceneLoad(0, 0, 0.0, 0.0, 0.0)
    arr = scene.arrays
    xy = arr.vertices[:, :2]
    lo = np.minimum.reduceat(xy, arr.start, axis=0)
    hi = np.maximum.reduceat(xy, arr.start, axis=0)
    extent = np.array([scene.width, scene.height], dtype=np.float64)
    keep = np.all((lo < extent) & (hi > 0), axis=1)  # boxes reaching into the image
    lo, hi = np.clip(lo, 0.0, extent), np.clip(hi, 0.0, extent)
    lo, hi = lo[keep], hi[keep]
    m = len(lo)
    # pairs: every pair when few, else each sampled box against all, scaled
    if m <= _EXACT_PAIRS:
        sample = np.arange(m)
    else:
        size = int(min(m, max(64, _PAIR_WORK // m)))
        sample = np.random.default_rng(0).choice(m, size=size, replace=False)
    hits = 0
    step = max(1, (1 << 22) // (4 * max(m, 1)))
    for a in range(0, len(sample), step):
        s = sample[a : a + step]
        over = ((lo[s, None, 0] <= hi[None, :, 0]) & (lo[None, :, 0] <= hi[s, None, 0])
                & (lo[s, None, 1] <= hi[None, :, 1]) & (lo[None, :, 1] <= hi[s, None, 1]))
        hits += int(over.sum()) - len(s)  # not with itself
    pairs = hits / 2 * (m / max(len(sample), 1))
    # depth per grid cell: boxes over it (a cell of c x c pixels counts a box touching it)
    c = max(1, math.ceil(math.sqrt(scene.width * scene.height / _GRID_CELLS)))
    gw, gh = -(-scene.width // c), -(-scene.height // c)
    x0 = np.clip(np.floor(lo[:, 0] / c).astype(np.int64), 0, gw - 1)
    y0 = np.clip(np.floor(lo[:, 1] / c).astype(np.int64), 0, gh - 1)
    x1 = np.clip(np.ceil(hi[:, 0] / c).astype(np.int64), x0 + 1, gw)
    y1 = np.clip(np.ceil(hi[:, 1] / c).astype(np.int64), y0 + 1, gh)
    diff = np.zeros((gh + 1, gw + 1), np.int64)
    np.add.at(diff, (y0, x0), 1)
    np.add.at(diff, (y0, x1), -1)
    np.add.at(diff, (y1, x0), -1)
    np.add.at(diff, (y1, x1), 1)
    depth = np.cumsum(np.cumsum(diff, axis=0), axis=1)[:gh, :gw].astype(np.float64)
    return SceneLoad(n, len(arr.vertices), float(pairs), float((depth**2).sum() * c * c),
                     float(depth.sum() * c * c))


# The least one render costs whatever the scene: Python's call, the budget check, the image
# (seconds per render and per pixel; measured 0.5-0.8 ms of CPU per frame for point, abuffer
# and catmull on a 25x1 scene); a run of many frames is budgeted with at least this.
RENDER_SECONDS = 1e-3
PIXEL_SECONDS = 1e-8



def render_seconds(scene: Scene, method: Method, options: Mapping[str, Any]) -> float:
    """The estimated seconds of one render (the near-tie pass, the method's own estimate,
    and the least any render costs)."""
    seconds = RENDER_SECONDS + PIXEL_SECONDS * scene.width * scene.height
    if method.runs_near_ties:
        seconds += PAIR_SECONDS * scene_load(scene).pairs
    if method.seconds is not None:
        seconds += float(method.seconds(scene, options))
    return seconds

