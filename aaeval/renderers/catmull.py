"""Methods ``catmull`` and ``catmull-jagged``: Catmull 1978 exact area sampling.

``catmull`` gives every pixel the exact area average of the visible colours over the
pixel square (box filter), hidden surfaces solved inside the pixel by the recursive pixel
integrator. ``catmull-jagged`` is the paper's mode with the integrator switched off: the
nearest piece in the pixel's z-list colours the whole pixel.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from aaeval.filters.registry import DEFAULT_FILTER, FILTERS
from aaeval.renderers._catmull_kernel import BACKGROUND, BAND_ROWS, band_colors, band_fragments, sort_polygons
from aaeval.renderers.registry import Option, register_method
from aaeval.scenes import Scene, parse_scene
from aaeval.scenes.depth import depth_tolerance
from aaeval.specular.methods import PARAMETERS as SPECULAR_PARAMETERS
from aaeval.weiler_atherton.near_ties import resolve_flat_arrays

__all__ = ["Fragments", "visible_fragments", "resolve_flat", "render_flat", "render_catmull", "render_catmull_jagged"]


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
    """Flat arrays of the drawable polygons, outlines normalised to positive area.

    Returns ``(start, length, x, y, planes, source, eps_z)`` where ``source[k]`` is the
    index in ``scene.polygons`` of kernel polygon ``k``. Polygons seen edge-on cover no
    area and are left out. Vectorised: no Python loop over polygons.
    """
    arr = scene.arrays
    source = np.flatnonzero(np.isfinite(arr.planes).all(axis=1))
    length = arr.length[source]
    start = np.zeros(len(source), dtype=np.int64)
    start[1:] = np.cumsum(length)[:-1]
    # gather each kept polygon's vertices; reverse the ones wound the other way
    owner = np.repeat(np.arange(len(source)), length)
    local = np.arange(length.sum()) - start[owner]
    xy = arr.vertices[arr.start[source][owner] + local, :2]
    area2 = np.add.reduceat(xy[:, 0] * _next_in_polygon(xy[:, 1], start, length, owner, local)
                            - _next_in_polygon(xy[:, 0], start, length, owner, local) * xy[:, 1],
                            start) if len(source) else np.zeros(0)
    flip = area2[owner] < 0 if len(source) else np.zeros(0, bool)
    local = np.where(flip, length[owner] - 1 - local, local)
    xy = arr.vertices[arr.start[source][owner] + local, :2]
    # depth differences below this count as one shared plane (the scene format's tie rule)
    eps_z = depth_tolerance(arr.vertices[:, 2])
    # stacks of nearly coplanar polygons are resolved by the rule before the pairwise sort
    start, length, x, y, planes, source = resolve_flat_arrays(
        start, length, np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]),
        np.ascontiguousarray(arr.planes[source]), source, eps_z)
    return start, length, x, y, planes, source, eps_z


def _next_in_polygon(values, start, length, owner, local):
    """``values`` shifted by one vertex within each polygon (cyclically)."""
    return values[start[owner] + (local + 1) % length[owner]]


def available_cores() -> int:
    """Cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


@lru_cache(maxsize=None)
def _pool(threads: int) -> ThreadPoolExecutor:
    return ThreadPoolExecutor(max_workers=threads, thread_name_prefix="catmull")


# a forked child inherits the pools without their threads: a band handed to one would
# wait forever, so the child starts with none (multiprocessing forks by default on Linux)
if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_pool.cache_clear)


def run_bands(height: int, threads: int, band):
    """``band(row0, row1)`` for every band of rows, on ``threads`` threads (0: all cores);
    results in band order. The kernel releases the GIL, and the bands do not depend on
    the thread count, so neither does the result."""
    bands = [(r, min(r + BAND_ROWS, height)) for r in range(0, height, BAND_ROWS)]
    threads = min(threads or available_cores(), len(bands))
    if threads <= 1:
        return [band(r0, r1) for r0, r1 in bands]
    order = far_apart(len(bands), threads)
    results = [None] * len(bands)
    for i, result in zip(order, _pool(threads).map(lambda i: band(*bands[i]), order)):
        results[i] = result
    return results


def far_apart(n: int, threads: int) -> list[int]:
    """The order threads take n bands in: the image cut into ``threads`` runs of bands,
    one band from each in turn, so that threads write far-apart memory. (Neighbouring
    bands share the kernel's 2 MB pages of a new image: two threads touching one first at
    the same time both zero it. Measured on the 2048² row, two threads: 1.73-1.78x one
    thread in band order, 1.80-1.82x in this order.)"""
    run = -(-n // threads)
    return [k * run + i for i in range(run) for k in range(threads) if k * run + i < n]


def visible_fragments(scene: Scene, *, jagged: bool = False, centroids: bool = True, threads: int = 0) -> Fragments:
    """Run the Catmull scanline algorithm and return every pixel's visible fragments.

    With ``centroids=False`` the cheap paths (a solid piece; one irregular piece over a
    solid one) skip locating the visible pieces' centroids and report pixel centres;
    areas are exact either way. ``threads``: bands of rows run in parallel (0: all
    cores); the result does not depend on it.
    """
    starts, lengths, x, y, planes, source, eps_z = kernel_inputs(scene)
    polys = sort_polygons(starts, lengths, x, y, planes)
    parts = run_bands(scene.height, threads,
                       lambda r0, r1: band_fragments(polys, scene.width, r0, r1, eps_z, jagged, centroids))
    pix, src, area, cx, cy = (np.concatenate([p[i] for p in parts]) if parts else np.zeros(0) for i in range(5))
    pix = pix.astype(np.int64)
    src = src.astype(np.int64)
    polygon = np.where(src == BACKGROUND, BACKGROUND, source[np.maximum(src, 0)] if len(source) else src)
    return Fragments(pix, polygon, area, cx, cy)


def resolve_flat(scene: Scene, fragments: Fragments) -> np.ndarray:
    """Area-weighted flat colours of the fragments: the box-filtered image (H, W, 3)."""
    colors = np.vstack([scene.arrays.colors, scene.background])
    rgb = colors[fragments.polygon]  # index -1 is the background row
    n = scene.width * scene.height
    image = np.empty((n, 3))
    for ch in range(3):
        image[:, ch] = np.bincount(fragments.pixel, weights=fragments.area * rgb[:, ch], minlength=n)
    return image.reshape(scene.height, scene.width, 3)


def render_flat(scene: Scene, *, jagged: bool = False, threads: int = 0) -> np.ndarray:
    """The box-filtered flat-colour image (H, W, 3), written by the kernel straight into
    the image (no fragment list): the same bits as ``resolve_flat(visible_fragments())``."""
    starts, lengths, x, y, planes, source, eps_z = kernel_inputs(scene)
    polys = sort_polygons(starts, lengths, x, y, planes)
    colors = np.ascontiguousarray(np.vstack([scene.arrays.colors[source], scene.background]), dtype=float)
    image = np.empty((scene.width * scene.height, 3))
    run_bands(scene.height, threads,
               lambda r0, r1: band_colors(polys, scene.width, r0, r1, eps_z, jagged, colors, image))
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


# Options for scenes with [shaded] objects, declared once by the specular registry
# (flat scenes ignore them). Its method list is a live view: a clamp registered there
# later is accepted by catmull:specular=NAME.
SPECULAR_OPTIONS = {
    name: Option(p.type, p.default, p.doc, choices=p.choices, minimum=p.minimum)
    for name, p in SPECULAR_PARAMETERS.items()
}


FILTER_OPTION = {
    "filter": Option(
        str,
        DEFAULT_FILTER,
        "pixel filter, as Mitsuba 3 defines it and normalises its film (aaeval.filters, docs/filters.md)",
        choices=tuple(FILTERS),
    ),
}

# methods whose coverage is per pixel by construction (masks, analytic coverage) accept
# only the box, and say so when asked for another
BOX_ONLY = {"filter": Option(str, DEFAULT_FILTER, "pixel filter: box only (coverage is computed per pixel)",
                             choices=(DEFAULT_FILTER,))}


THREADS = Option(int, 0, "bands of rows rendered in parallel on this many threads (0: all cores); "
                 "the image does not depend on it", minimum=0)


@register_method(
    "catmull",
    summary="Catmull 1978: exact box filter (or another filter=), hidden surfaces solved inside each pixel",
    options={**SPECULAR_OPTIONS, **FILTER_OPTION, "threads": THREADS},
    exact=True,
    warmup=_warmup,
)
def render_catmull(scene: Scene, filter: str = DEFAULT_FILTER, threads: int = 0, **specular_options) -> np.ndarray:
    from aaeval.scenes.shaded import has_shaded

    if filter != DEFAULT_FILTER:
        from aaeval.filters.exact import filtered_image

        if has_shaded(scene):
            raise ValueError(f"catmull: filter={filter} supports flat-coloured scenes only, not [shaded] objects")
        return filtered_image(scene, FILTERS[filter])
    if has_shaded(scene):
        # at call time: the specular renderer uses this module's visible_fragments
        from aaeval.specular.render import render_shaded

        return render_shaded(scene, **specular_options)
    return render_flat(scene, threads=threads)


@register_method(
    "catmull-jagged",
    summary="Catmull 1978 with the pixel integrator off: nearest piece fills the pixel",
    options={"threads": THREADS},
    warmup=_warmup,
)
def render_catmull_jagged(scene: Scene, threads: int = 0) -> np.ndarray:
    return render_flat(scene, jagged=True, threads=threads)
