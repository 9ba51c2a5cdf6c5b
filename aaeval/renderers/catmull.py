"""Methods ``catmull`` and ``catmull-jagged``: Catmull 1978 exact area sampling.

``catmull`` gives every pixel the exact area average of the visible colours over the
pixel square (box filter), hidden surfaces solved inside the pixel by the recursive pixel
integrator. ``catmull-jagged`` is the paper's mode with the integrator switched off: the
nearest piece in the pixel's z-list colours the whole pixel.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from aaeval.renderers._catmull_kernel import BACKGROUND, catmull_fragments
from aaeval.renderers._clip import normalised_orientation
from aaeval.renderers.registry import register_method
from aaeval.scenes import Scene, parse_scene

__all__ = ["Fragments", "visible_fragments", "resolve_flat", "render_catmull", "render_catmull_jagged"]


class Fragments(NamedTuple):
    """Visible pieces of polygons per pixel: one row per (pixel, polygon) pair.

    ``pixel`` is ``row * width + col``; ``polygon`` indexes ``scene.polygons`` (-1 is the
    background); ``area`` is the visible area inside the pixel (the pixel's areas sum to
    1); ``cx, cy`` is that area's centroid (image coordinates).
    """

    pixel: np.ndarray
    polygon: np.ndarray
    area: np.ndarray
    cx: np.ndarray
    cy: np.ndarray


def kernel_inputs(scene: Scene):
    """Flat arrays of the drawable polygons (outlines normalised to positive area).

    Returns ``(start, length, x, y, planes, source, eps_z)`` where ``source[k]`` is the
    index in ``scene.polygons`` of kernel polygon ``k``. Polygons seen edge-on cover no
    area and are left out.
    """
    keep = [p for p in scene.polygons if np.isfinite(p.plane).all()]
    outlines = [normalised_orientation(p.xy) for p in keep]
    lengths = np.array([len(o) for o in outlines], dtype=np.int64)
    starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64) if len(keep) else np.zeros(0, np.int64)
    xy = np.concatenate(outlines) if keep else np.zeros((0, 2))
    planes = np.array([p.plane for p in keep], dtype=np.float64).reshape(-1, 3)
    source = np.array([p.index for p in keep], dtype=np.int64)
    zmax = max((np.abs(p.vertices[:, 2]).max() for p in keep), default=0.0)
    # depth differences below this count as one shared plane (float64 rounding of the
    # plane evaluation is ~1e-16 of the depth magnitude)
    eps_z = 1e-11 * (1.0 + zmax)
    return starts, lengths, np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]), planes, source, eps_z


def visible_fragments(scene: Scene, *, jagged: bool = False, centroids: bool = True) -> Fragments:
    """Run the Catmull scanline algorithm and return every pixel's visible fragments.

    With ``centroids=False`` the cheap paths (a solid piece; one irregular piece over a
    solid one) skip locating the visible pieces' centroids and report pixel centres;
    areas are exact either way.
    """
    starts, lengths, x, y, planes, source, eps_z = kernel_inputs(scene)
    pix, src, area, cx, cy = catmull_fragments(
        scene.width, scene.height, starts, lengths, x, y, planes, eps_z, jagged, centroids
    )
    polygon = np.where(src == BACKGROUND, BACKGROUND, source[np.maximum(src, 0)] if len(source) else src)
    return Fragments(pix, polygon, area, cx, cy)


def resolve_flat(scene: Scene, fragments: Fragments) -> np.ndarray:
    """Area-weighted flat colours of the fragments: the box-filtered image (H, W, 3)."""
    colors = np.vstack([np.array([p.color for p in scene.polygons]).reshape(-1, 3), scene.background])
    rgb = colors[fragments.polygon]  # index -1 is the background row
    n = scene.width * scene.height
    image = np.empty((n, 3))
    for ch in range(3):
        image[:, ch] = np.bincount(fragments.pixel, weights=fragments.area * rgb[:, ch], minlength=n)
    return image.reshape(scene.height, scene.width, 3)


def _warmup() -> None:
    tiny = parse_scene(
        {
            "image": {"width": 4, "height": 3},
            "polygons": [
                {"color": [1, 0, 0], "vertices": [[0.2, 0.3, 1], [3.7, 0.6, 2], [1.5, 2.9, 0]]},
                {"color": [0, 1, 0], "vertices": [[0.1, 2.5, 0], [3.9, 2.2, 3], [2.5, 0.1, 1]]},
                {"color": [0, 0, 1], "vertices": [[-1, -1, 5], [5, -1, 5], [5, 4, 5], [-1, 4, 5]]},
            ],
        },
        source="<warm-up>",
    )
    render_catmull(tiny)
    render_catmull_jagged(tiny)


@register_method(
    "catmull",
    summary="Catmull 1978: exact box filter, hidden surfaces solved inside each pixel",
    exact=True,
    warmup=_warmup,
)
def render_catmull(scene: Scene) -> np.ndarray:
    return resolve_flat(scene, visible_fragments(scene, centroids=False))


@register_method(
    "catmull-jagged",
    summary="Catmull 1978 with the pixel integrator off: nearest piece fills the pixel",
    warmup=_warmup,
)
def render_catmull_jagged(scene: Scene) -> np.ndarray:
    return resolve_flat(scene, visible_fragments(scene, jagged=True, centroids=False))
