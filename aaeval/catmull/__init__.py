"""Catmull 1978 exact area sampling: the scanline kernel's Python face.

The kernel is native (``aaeval.native.catmull``, C++ under ``src/catmull/``), laid out by the
paper's stages: ``strips.hpp`` (I./III.A/III.C: polygons in order of their first scanline,
the active list, each scanline's strip pieces with their exact coverage of every pixel
column), ``buckets.hpp`` (III.C.4: the x-bucket), ``sweep.hpp`` (III.D/E: the row sweep and
its cheap cases), ``integrator.hpp`` (III.E.b: the pixel integrator, recursive clipping
along the front polygon's edges and where depth planes cross; :mod:`.reference` is the same
in plain Python) and ``sink.hpp`` (the sink protocol every result leaves through: colours,
fragments or, in ``moments.hpp``, a filter's moments). ``src/common/geometry.hpp`` holds the
half-plane clip, shoelace area and centroid.

Here: :func:`kernel_inputs` (the scene as the kernel's flat arrays),
:func:`visible_fragments` (every pixel's visible polygons with area and centroid),
:func:`render_flat` (the box-filtered flat-colour image) and :func:`resolve_flat`. Bands of
``BAND_ROWS`` rows run on C++ threads without the GIL; the result does not depend on the
thread count. The exact filters' path is :mod:`aaeval.catmull.filtered`; the methods
``catmull`` and ``catmull-jagged`` are registered by :mod:`aaeval.renderers.catmull`.
"""

from __future__ import annotations

import os
from typing import NamedTuple

import numpy as np

from aaeval.native import catmull as _catmull
from aaeval.scenes import Scene
from aaeval.scenes.depth import depth_tolerance
from aaeval.weiler_atherton.near_ties import resolve_flat_arrays

__all__ = ["BACKGROUND", "BAND_ROWS", "MAX_THREADS", "Fragments", "kernel_inputs", "available_cores", "far_apart",
           "visible_fragments", "resolve_flat", "render_flat"]

BACKGROUND = _catmull.BACKGROUND  # the source of the background's fragments
BAND_ROWS = _catmull.BAND_ROWS  # rows per band (bands run independently)


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
    x, y = _outlines_wound_positive(arr.vertices, arr.start[source], length, start)
    # depth differences below this count as one shared plane (the scene format's tie rule)
    eps_z = depth_tolerance(arr.vertices[:, 2])
    # stacks of nearly coplanar polygons are resolved by the rule before the pairwise sort
    start, length, x, y, planes, source = resolve_flat_arrays(
        start, length, x, y, np.ascontiguousarray(arr.planes[source]), source, eps_z)
    return start, length, x, y, planes, source, eps_z


def _outlines_wound_positive(vertices, first, length, start):
    """The x and y ``(sum(length),)`` (contiguous) of each polygon's outline (polygon k:
    ``length[k]`` vertices from ``first[k]``, written from ``start[k]``), reversed where
    its shoelace area is negative. Polygons of one size up to 8 (all triangles, say) take
    a 2D path, a column of corners at a time, that adds the area's terms as
    ``np.add.reduceat`` does on the general path (the first plus the sum of the rest, left
    to right), so a polygon of nearly zero area turns the same way on either path."""
    n = len(length)
    if n and length.min() == length.max() and 3 <= length[0] <= 8:
        size = int(length[0])
        if (first == np.arange(n) * size).all() and len(vertices) >= n * size:
            corners = vertices[:n * size].reshape(n, size, -1)  # stored in order: no gather
        else:
            corners = vertices[first[:, None] + np.arange(size)]
        x, y = np.ascontiguousarray(corners[..., 0]), np.ascontiguousarray(corners[..., 1])

        def term(j):
            k = (j + 1) % size
            return x[:, j] * y[:, k] - x[:, k] * y[:, j]

        rest = term(1)
        for j in range(2, size):
            rest = rest + term(j)
        flip = (term(0) + rest < 0)[:, None]
        return np.where(flip, x[:, ::-1], x).ravel(), np.where(flip, y[:, ::-1], y).ravel()
    owner = np.repeat(np.arange(n), length)
    local = np.arange(length.sum()) - start[owner]
    index = first[owner] + local
    if n:
        following = first[owner] + (local + 1) % length[owner]
        area2 = np.add.reduceat(vertices[index, 0] * vertices[following, 1]
                                - vertices[following, 0] * vertices[index, 1], start)
        flip = area2[owner] < 0
        index = np.where(flip, first[owner] + length[owner] - 1 - local, index)
    return vertices[index, 0], vertices[index, 1]


def native_arrays(start, length, x, y, planes):
    """The kernel inputs as the native module takes them (C order, int64 / float64)."""
    return (np.ascontiguousarray(start, dtype=np.int64), np.ascontiguousarray(length, dtype=np.int64),
            np.ascontiguousarray(x, dtype=np.float64), np.ascontiguousarray(y, dtype=np.float64),
            np.ascontiguousarray(np.reshape(planes, (-1, 3)), dtype=np.float64))


def available_cores() -> int:
    """Cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


#: The most threads the native kernels take (src/catmull/module.cpp, src/shading/module.cpp).
MAX_THREADS = 4096


def thread_count(threads: int) -> int:
    """``threads`` (0: all cores) as the kernel's thread count."""
    if not 0 <= threads <= MAX_THREADS:
        raise ValueError(f"threads must be in [0, {MAX_THREADS}] (0: all cores), got {threads}")
    return min(int(threads) or available_cores(), MAX_THREADS)


def far_apart(n: int, threads: int) -> list[int]:
    """The order the kernel's threads take n bands in: the image cut into ``threads`` runs
    of bands, one band from each in turn, so that threads write far-apart memory
    (neighbouring bands share the 2 MB pages of a new image: two threads first touching one
    at the same time both zero it)."""
    return list(_catmull.far_apart(n, threads))


def visible_fragments(scene: Scene, *, jagged: bool = False, centroids: bool = True, threads: int = 0) -> Fragments:
    """Run the Catmull scanline algorithm and return every pixel's visible fragments.

    With ``centroids=False`` the cheap paths (a solid piece; one irregular piece over a
    solid one) skip locating the visible pieces' centroids and report pixel centres;
    areas are exact either way. ``threads``: bands of rows run in parallel (0: all
    cores); the result does not depend on it.
    """
    starts, lengths, x, y, planes, source, eps_z = kernel_inputs(scene)
    pix, src, area, cx, cy = _catmull.fragments(*native_arrays(starts, lengths, x, y, planes), float(eps_z),
                                                scene.width, scene.height, bool(jagged), bool(centroids),
                                                thread_count(threads))
    polygon = np.where(src == BACKGROUND, BACKGROUND, source[np.maximum(src, 0)] if len(source) else src)
    return Fragments(pix, polygon.astype(np.int64), area, cx, cy)


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
    colors = np.ascontiguousarray(np.vstack([scene.arrays.colors[source], scene.background]), dtype=np.float64)
    return _catmull.render_flat(*native_arrays(starts, lengths, x, y, planes), colors.reshape(-1, 3), float(eps_z),
                                scene.width, scene.height, bool(jagged), thread_count(threads))
