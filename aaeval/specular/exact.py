"""Exact Phong shading: the shade integrated over every visible piece of every pixel.

``catmull:shading=exact``. Catmull's kernel finds the visible pieces (the same sweep and
pixel integrator as ``catmull``); the native sink ``src/shading/`` integrates the
documented Phong model (docs/shaded_scenes.md) over each piece by a collapsed
Gauss-Legendre rule on its fan triangles, bisecting a triangle where the rule and its two
halves disagree by more than ``tol`` per unit area (that disagreement, summed, is the
pixel's error bound) or where its normals spread wider than the highlight lobe near the
lobe's peak. The specular method's clamp sets each visible polygon's exponent and ks per
pixel (:func:`aaeval.specular.render.fragment_parameters`), and that material is then
integrated exactly. ``crow`` has no clamp: its K x K samples are a quadrature of the
unclamped shade, which this integral replaces, so ``crow`` here equals ``none``.
"""

from __future__ import annotations

import hashlib
import pickle
import threading
from dataclasses import fields
from typing import NamedTuple

import numpy as np

from aaeval.catmull import BACKGROUND, Fragments, kernel_inputs, native_arrays, thread_count
from aaeval.native import catmull as _catmull
from aaeval.native import shading as _shading
from aaeval.scenes import Scene
from aaeval.scenes.shaded import expand_shaded
from aaeval.specular.methods import specular_options
from aaeval.specular.render import shaded_pieces, fragment_parameters

__all__ = ["ExactShading", "DEFAULT_TOL", "exact_shading", "error_bound", "render_exact"]

# error per unit area each fan triangle is refined to: a pixel's bound stays near 1e-12
DEFAULT_TOL = 1e-12


class ExactShading(NamedTuple):
    """An exactly shaded image and what it cost.

    ``image`` (H, W, 3) and ``specular`` (H, W): the box-filtered Phong image and its
    specular term; ``bound`` (H, W): each pixel's estimated error (the refinement's
    disagreements, in the image's units, largest channel); ``evals`` (H, W): shade
    evaluations per pixel.
    """

    image: np.ndarray
    specular: np.ndarray
    bound: np.ndarray
    evals: np.ndarray

    @property
    def max_bound(self) -> float:
        return float(self.bound.max(initial=0.0))


def exact_shading(scene: Scene, *, tol: float = DEFAULT_TOL, threads: int = 0, **options) -> ExactShading:
    """Render a scene with ``[shaded]`` objects with the shade integrated exactly.

    Every call integrates (a render is timed for real); its error bound is kept for
    :func:`error_bound`.

    Parameters
    ----------
    scene : Scene
    tol : float
        Error per unit area each fan triangle is refined to.
    threads : int
        Bands of rows on this many threads (0: all cores); the image does not depend on it.
    **options
        The specular method and its parameters (:data:`aaeval.specular.methods.PARAMETERS`).
    """
    options = specular_options(**options)
    if not tol > 0:
        raise ValueError(f"tol must be > 0, got {tol!r}")
    result = _integrate(scene, tol, threads, options)
    with _LAST_LOCK:
        _LAST_BOUND[:] = [_content_key(scene, tol, options), result.bound.copy()]
    return result


def error_bound(scene: Scene, *, tol: float = DEFAULT_TOL, **options) -> np.ndarray:
    """The per-pixel error bound of :func:`exact_shading` (``bound``), taken from the last
    integration in this process when it was of the same scene, ``tol`` and options (a
    sweep's reference renders the frame, then asks for its bound), else integrated now."""
    checked = specular_options(**options)
    key = _content_key(scene, tol, checked)
    with _LAST_LOCK:
        if _LAST_BOUND and _LAST_BOUND[0] == key:
            return _LAST_BOUND[1].copy()
    return exact_shading(scene, tol=tol, **options).bound


#: ``[key, bound]`` of the last integration in this process (one frame's bound)
_LAST_BOUND: list = []
_LAST_LOCK = threading.Lock()


def _content_key(scene: Scene, tol: float, options: dict) -> bytes:
    """A digest of everything the integration reads: the scene's fields (not the caches an
    object gathers as it is used), ``tol`` and the options. Two scenes that pickle alike
    render alike; any difference only misses the cache."""
    content = (tuple(getattr(scene, f.name) for f in fields(scene)), tol, sorted(options.items()))
    return hashlib.blake2b(pickle.dumps(content, protocol=5)).digest()


def _integrate(scene: Scene, tol: float, threads: int, options: dict) -> ExactShading:
    expanded = expand_shaded(scene)
    field = expanded.field
    start, length, x, y, planes, source, eps_z = kernel_inputs(expanded.scene)
    arrays = native_arrays(start, length, x, y, planes)
    threads = thread_count(threads)
    pix, src, area, cx, cy = _catmull.fragments(*arrays, float(eps_z), scene.width, scene.height, False, True, threads)
    polygon = np.where(src == BACKGROUND, BACKGROUND, source[np.maximum(src, 0)] if len(source) else src)
    fragments = Fragments(pix, polygon.astype(np.int64), area, cx, cy)
    frag_n, frag_ks = _fragment_materials(field, fragments, scene.width, options)
    size = scene.width * scene.height
    offset = np.searchsorted(pix, np.arange(size + 1)).astype(np.int64)
    light = field.light
    colors = np.vstack([field.color[source], np.asarray(expanded.scene.background, dtype=np.float64)])
    shaded = field.shaded[source].astype(np.uint8)
    G = np.where(shaded[:, None, None].astype(bool), field.G[source], 0.0).reshape(-1, 9)
    rgb, spec, bound, evals = _shading.render_exact(
        *arrays, float(eps_z), scene.width, scene.height, np.ascontiguousarray(G), np.ascontiguousarray(colors),
        np.ascontiguousarray(field.ka[source]), np.ascontiguousarray(field.kd[source]), np.ascontiguousarray(shaded),
        light is not None and light.kind == "point",
        np.ascontiguousarray(light.vector if light is not None else np.zeros(3), dtype=np.float64),
        offset, np.ascontiguousarray(src, dtype=np.int64), frag_n, frag_ks, float(tol), threads)
    return ExactShading(rgb, spec, bound, evals)


def _fragment_materials(field, fragments: Fragments, width: int, options) -> tuple[np.ndarray, np.ndarray]:
    """Exponent and ks per fragment row: the specular method's clamp on shaded rows, 0 elsewhere."""
    pieces = shaded_pieces(field, fragments, width)
    n_new, ks_new, _ = fragment_parameters(field, pieces, **options)
    frag_n = np.zeros(len(fragments.pixel))
    frag_ks = np.zeros(len(fragments.pixel))
    frag_n[pieces.rows] = n_new
    frag_ks[pieces.rows] = ks_new
    return frag_n, frag_ks


def render_exact(scene: Scene, *, return_specular: bool = False, **options):
    """:func:`exact_shading`'s image (and its specular term if ``return_specular``)."""
    result = exact_shading(scene, **options)
    if return_specular:
        return result.image, result.specular
    return result.image
