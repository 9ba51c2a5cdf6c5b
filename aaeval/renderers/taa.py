"""Method ``taa``: temporal anti-aliasing as engines ship it (Karis 2014, "High Quality Temporal Supersampling").

Each frame takes one sample per pixel, at a sub-pixel jitter that cycles through the
first ``phases`` points of the Halton(2, 3) sequence (indices 1..phases, minus 1/2: the
jitter of Unreal Engine 4 and most engines). The previous output (the *history*) is
reprojected by the scene's exact motion (the animation's translation per frame: pixel
``p`` of frame ``t`` shows what pixel ``p - translate`` showed at ``t - 1``), resampled
bilinearly or with the Catmull-Rom spline (``resample=``); history that comes from
outside the previous image is replaced by the current sample. The reprojected history is
limited to the current frame's 3x3 neighbourhood in YCoCg: clamped to its min/max box
(``clamp=minmax``), or clipped towards the centre of the box ``mean +- gamma * std``
(``clamp=variance``, Salvi 2016), or not at all (``clamp=none``). The output is
``alpha * current + (1 - alpha) * history`` and becomes the next history.

Frame ``k`` of an animation is frame ``warmup + k`` of the sequence: ``warmup`` frames of
the scene held still at its first frame (jitter running) are rendered first, then frames
``0 .. k`` with the motion, so every frame's image is reproducible on its own, whatever
was rendered before. Within one process the last history of each (scene, options) is
kept, so rendering frames in order costs one frame each (when the scene moved back to its
first frame is bit for bit the same from either frame; otherwise the frame is rendered
from the start, so the cache never changes an image).

``[shaded]`` scenes are shaded at each sample. When their objects spin, the history is
reprojected per pixel from the analytic motion: the surface point at each pixel centre
(on the triangle visible there) is carried back to the previous frame by its barycentric
coordinates in the same triangle one frame earlier (spin and translation, exactly), and
the history is resampled there (:func:`motion_sources`, :func:`resample_at`).
"""

from __future__ import annotations

import hashlib
import pickle
import threading
from collections import OrderedDict

import numpy as np

from aaeval.renderers.offsets import OffsetSampler, halton
from aaeval.renderers.cost import PAIR_SECONDS, scene_load
from aaeval.renderers.registry import Option, register_method
from aaeval.renderers.sampling import warmup_scene
from aaeval.scenes import Scene

__all__ = ["render_taa", "jitter_sequence", "rgb_to_ycocg", "ycocg_to_rgb"]

_CACHE: "OrderedDict[tuple, tuple[int, np.ndarray]]" = OrderedDict()
_CACHE_LOCK = threading.Lock()
_CACHE_SIZE = 4
_CACHE_BYTES = 256 << 20  # histories kept in all


def jitter_sequence(phases: int) -> np.ndarray:
    """Offsets from the pixel centre (phases, 2): Halton(2, 3) points 1..phases, minus 1/2."""
    return np.array([[halton(i, 2) - 0.5, halton(i, 3) - 0.5] for i in range(1, phases + 1)])


def rgb_to_ycocg(rgb: np.ndarray) -> np.ndarray:
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return np.stack([0.25 * r + 0.5 * g + 0.25 * b, 0.5 * r - 0.5 * b, -0.25 * r + 0.5 * g - 0.25 * b], axis=-1)


def ycocg_to_rgb(ycc: np.ndarray) -> np.ndarray:
    y, co, cg = ycc[..., 0], ycc[..., 1], ycc[..., 2]
    return np.stack([y + co - cg, y + cg, y - co - cg], axis=-1)


def _weights(t, kind: str) -> tuple[list[int], list]:
    """Tap offsets and weights of the resampling kernel at fraction ``t`` past a texel."""
    if kind == "bilinear":
        return [0, 1], [1 - t, t]
    # Catmull-Rom
    return [-1, 0, 1, 2], [(-t + 2 * t * t - t**3) / 2, (2 - 5 * t * t + 3 * t**3) / 2,
                           (t + 4 * t * t - 3 * t**3) / 2, (-t * t + t**3) / 2]


def _taps(shift: float, n: int, kind: str) -> tuple[list[np.ndarray], list[float], np.ndarray]:
    """Source indices and weights along one axis for sampling at ``i - shift``, and which
    ``i`` fall inside the previous image."""
    pos = np.arange(n) - shift
    base = int(np.floor(-shift))
    offsets, weights = _weights(-shift - base, kind)
    idx = [np.clip(np.arange(n) + base + o, 0, n - 1) for o in offsets]
    inside = (pos >= -0.5) & (pos <= n - 0.5)
    return idx, weights, inside


def reproject(history: np.ndarray, dx: float, dy: float, kind: str) -> tuple[np.ndarray, np.ndarray]:
    """``history`` sampled at ``(col - dx, row - dy)`` of every pixel, and where that lies
    inside the image (H, W bool)."""
    h, w = history.shape[:2]
    xi, xw, xin = _taps(dx, w, kind)
    yi, yw, yin = _taps(dy, h, kind)
    rows = sum(wt * history[:, i] for i, wt in zip(xi, xw))
    out = sum(wt * rows[i] for i, wt in zip(yi, yw))
    return out, yin[:, None] & xin[None, :]


def resample_at(history: np.ndarray, sx: np.ndarray, sy: np.ndarray, kind: str) -> tuple[np.ndarray, np.ndarray]:
    """``history`` sampled at index coordinates ``(sx, sy)`` (H, W each; texel (r, c) is at
    x = c, y = r), edge texels repeated, and where the points lie inside the image."""
    h, w = history.shape[:2]
    inside = (sx >= -0.5) & (sx <= w - 0.5) & (sy >= -0.5) & (sy <= h - 0.5)
    x0, y0 = np.floor(sx), np.floor(sy)
    xo, xw = _weights(sx - x0, kind)
    yo, yw = _weights(sy - y0, kind)
    x0, y0 = x0.astype(np.int64), y0.astype(np.int64)
    out = np.zeros(history.shape)
    for oy, wy in zip(yo, yw):
        yi = np.clip(y0 + oy, 0, h - 1)
        for ox, wx in zip(xo, xw):
            out += (wy * wx)[:, :, None] * history[yi, np.clip(x0 + ox, 0, w - 1)]
    return out, inside


def motion_sources(now: OffsetSampler, before: OffsetSampler, dx: float, dy: float) -> tuple[np.ndarray, np.ndarray]:
    """Where the surface seen at each pixel centre of a frame was one frame earlier, in index
    coordinates: moved back by the translation ``(dx, dy)``, and on shaded triangles (which
    also spin) carried back exactly: the point's barycentric coordinates in its triangle now,
    applied to the same triangle the frame before (a rigid motion keeps them)."""
    h, w = now.height, now.width
    rows, cols = np.mgrid[0:h, 0:w]
    x, y = cols + 0.5, rows + 0.5
    px, py = x - dx, y - dy
    if now.field is not None and len(now.scene.polygons) == len(before.scene.polygons):
        ids = now.ids(0.0, 0.0)
        hit = ids >= 0
        poly = np.full(ids.shape, -1, np.int64)
        poly[hit] = now.source[ids[hit]]
        tri = hit & now.field.shaded[np.maximum(poly, 0)]
        if tri.any():
            p = poly[tri]
            a, b = now.scene.arrays, before.scene.arrays
            vn = a.vertices[a.start[p][:, None] + np.arange(3)]
            vb = b.vertices[b.start[p][:, None] + np.arange(3)]
            X, Y = x[tri], y[tri]
            (x0, y0), (x1, y1), (x2, y2) = vn[:, 0, :2].T, vn[:, 1, :2].T, vn[:, 2, :2].T
            d = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)  # not 0: an edge-on triangle is never seen
            b1 = ((X - x0) * (y2 - y0) - (x2 - x0) * (Y - y0)) / d
            b2 = ((x1 - x0) * (Y - y0) - (X - x0) * (y1 - y0)) / d
            moved = (1 - b1 - b2)[:, None] * vb[:, 0] + b1[:, None] * vb[:, 1] + b2[:, None] * vb[:, 2]
            px[tri], py[tri] = moved[:, 0], moved[:, 1]
    return px - 0.5, py - 0.5


def _spins(scene: Scene) -> bool:
    section = scene.extensions.get("shaded")
    return section is not None and any(obj.spin_degrees != 0.0 for obj in section.objects)


def neighbourhood_box(current: np.ndarray, mode: str, gamma: float) -> tuple[np.ndarray, np.ndarray] | None:
    """The YCoCg box the history is limited to, from the current frame's 3x3 neighbourhoods
    (edge pixels repeated): ``(lo, hi)``, or None for ``mode="none"``."""
    if mode == "none":
        return None
    ycc = rgb_to_ycocg(current)
    h, w = ycc.shape[:2]
    pad = np.pad(ycc, ((1, 1), (1, 1), (0, 0)), mode="edge")
    views = [pad[1 + dy : 1 + dy + h, 1 + dx : 1 + dx + w] for dy in (-1, 0, 1) for dx in (-1, 0, 1)]
    if mode == "minmax":
        lo, hi = views[0].copy(), views[0].copy()
        for v in views[1:]:
            np.minimum(lo, v, out=lo)
            np.maximum(hi, v, out=hi)
        return lo, hi
    mean = sum(views) / 9.0
    std = np.sqrt(np.maximum(sum(v * v for v in views) / 9.0 - mean**2, 0.0))
    return mean - gamma * std, mean + gamma * std


def _limit(history: np.ndarray, box, mode: str) -> np.ndarray:
    if box is None:
        return history
    hist = rgb_to_ycocg(history)
    lo, hi = box
    if mode == "minmax":
        limited = np.clip(hist, lo, hi)
    else:  # clip towards the box centre (keeps the history's hue direction)
        centre = 0.5 * (lo + hi)
        extent = np.maximum(0.5 * (hi - lo), 1e-12)
        v = hist - centre
        ratio = np.max(np.abs(v) / extent, axis=-1, keepdims=True)
        limited = np.where(ratio > 1.0, centre + v / np.maximum(ratio, 1.0), hist)
    # history inside the box is kept as it is (no round trip through YCoCg)
    moved = np.any(limited != hist, axis=-1, keepdims=True)
    return np.where(moved, ycocg_to_rgb(limited), history)


def _scene_key(first: Scene) -> str:
    digest = hashlib.sha256()
    for part in (first.arrays.vertices, first.arrays.colors, first.arrays.start, np.asarray(first.background),
                 np.asarray(first.translate), np.array([first.width, first.height, first.frames])):
        digest.update(np.ascontiguousarray(part).tobytes())
    digest.update(pickle.dumps(dict(first.extensions), protocol=4))
    return digest.hexdigest()


@register_method(
    "taa",
    summary="TAA: Halton(2,3) jitter, history reprojected by the exact motion, YCoCg clamp, exponential blend",
    options={
        "phases": Option(int, 8, "jitter phases (Halton(2,3) points per cycle)", choices=(8, 16)),
        "alpha": Option(float, 0.1, "weight of the current frame in the exponential blend", minimum=1e-3,
                        maximum=1.0),
        "warmup": Option(int, 64, "frames of the still first frame rendered before frame 0", minimum=0,
                         maximum=4096),
        "resample": Option(str, "catmull-rom", "history resampling: catmull-rom or bilinear",
                           choices=("catmull-rom", "bilinear")),
        "clamp": Option(str, "minmax", "history limit in YCoCg: minmax (3x3 box), variance (mean +- gamma std, "
                        "clipped), none", choices=("minmax", "variance", "none")),
        "gamma": Option(float, 1.0, "variance clipping: box half-width in standard deviations", minimum=0.0,
                        maximum=10.0),
    },
    warmup=lambda: render_taa(warmup_scene(), warmup=2),
    samples=lambda o: o["warmup"] + 1,
    memory=lambda scene, o: 40 * 8 * scene.width * scene.height,
    seconds=lambda scene, o: _seconds(scene, o),
)
def render_taa(scene: Scene, phases: int = 8, alpha: float = 0.1, warmup: int = 64, resample: str = "catmull-rom",
               clamp: str = "minmax", gamma: float = 1.0) -> np.ndarray:
    # every frame is drawn from one base, the scene moved back to its first frame: a cached
    # history is used only when its base is bit for bit this one (moving a scene to frame k
    # and back can differ in the last bit), so a frame is the same alone or after the others
    base = scene.at_frame(0)
    key = (_scene_key(base), phases, alpha, warmup, resample, clamp, gamma)
    target = scene.frame
    with _CACHE_LOCK:
        cached = _CACHE.get(key)
    jitter = jitter_sequence(phases)
    dx, dy = (float(v) for v in scene.translate)
    if cached is not None and cached[0] <= target:
        frame, history = cached[0], cached[1].copy()
        start = frame + 1
    else:
        history = None
        sampler = OffsetSampler(base)
        # the still first frame: its images and neighbourhood boxes repeat with the jitter
        still = [sampler.sample(*jitter[i]) for i in range(min(warmup, phases))]
        boxes = [neighbourhood_box(image, clamp, gamma) for image in still]
        for t in range(warmup):
            history = _step(history, still[t % phases], boxes[t % phases], 0.0, 0.0, alpha, resample, clamp)
        start = 0
    spinning = _spins(base)
    before = None
    for j in range(start, target + 1):
        t = warmup + j
        now = OffsetSampler(base.at_frame(j))
        current = now.sample(*jitter[t % phases])
        box = neighbourhood_box(current, clamp, gamma)
        if j > 0 and spinning and history is not None:
            before = before if before is not None else OffsetSampler(base.at_frame(j - 1))
            sx, sy = motion_sources(now, before, dx, dy)
            history, inside = resample_at(history, sx, sy, resample)
            history = np.where(inside[:, :, None], history, current)
            history = _step(history, current, box, 0.0, 0.0, alpha, resample, clamp)
        else:
            moved = j > 0
            history = _step(history, current, box, dx if moved else 0.0, dy if moved else 0.0, alpha, resample, clamp)
        before = now
    with _CACHE_LOCK:
        _CACHE[key] = (target, history.copy())
        _CACHE.move_to_end(key)
        while len(_CACHE) > _CACHE_SIZE or sum(h.nbytes for _, h in _CACHE.values()) > _CACHE_BYTES:
            _CACHE.popitem(last=False)
    return history


def _seconds(scene: Scene, o) -> float:
    # frame k draws frames 0..k, each with its own near-tie pass (the registry counts one),
    # and blends warmup + k + 1 images (~0.2 us a pixel each, measured on 256 x 256)
    frames = scene.frame + 1
    blends = scene.width * scene.height * (o["warmup"] + 2 * frames + o["phases"])
    return PAIR_SECONDS * scene_load(scene).pairs * frames + 2e-7 * blends


def _step(history, current, box, dx, dy, alpha, resample, clamp):
    if history is None:
        return current
    if dx or dy:
        history, inside = reproject(history, dx, dy, resample)
        history = np.where(inside[:, :, None], history, current)
    history = _limit(history, box, clamp)
    return history + alpha * (current - history)
