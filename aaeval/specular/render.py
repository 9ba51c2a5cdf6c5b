"""Phong-shaded Catmull rendering: exact edges, one shade per visible piece per pixel.

Every visible piece of a polygon in a pixel (one row of
:func:`aaeval.catmull.visible_fragments`, all of that polygon's visible area in
the pixel) is shaded once, at its area centroid, with the parameters the chosen specular
method gives it (Amanatides' "one shade per polygon per pixel"). ``crow`` instead shades
flagged pieces (or all, ``region="all"``) on a K x K sub-pixel grid: the scene is scaled
by K and rendered again with exact visibility, each sub-pixel piece shaded at its own
centroid, and its area / K^2 added to its parent piece. That makes ``crow`` with large K
everywhere converge to the exact box-filtered Phong image.
"""

from __future__ import annotations

from dataclasses import replace
from typing import NamedTuple

import numpy as np

from aaeval.catmull import Fragments, visible_fragments
from aaeval.scenes import Scene
from aaeval.scenes.shaded import ShadedScene, ShadingField, expand_shaded
from aaeval.specular.methods import SPECULAR_METHODS, specular_options
from aaeval.specular.shading import amanatides_rate, corner_offsets, min_corner_dot, phong, rescale_ks
from aaeval.specular.tables import min_dot

__all__ = [
    "SPECULAR_METHODS",
    "AliasingMap",
    "render_shaded",
    "specular_aliasing_map",
    "fragment_parameters",
    "scaled_scene",
]

class AliasingMap(NamedTuple):
    """Amanatides' detection per pixel.

    ``flag`` (H, W) bool: some visible shaded piece has its corner-normal dot below
    MinDot[n]; ``rate`` (H, W): the largest oversampling rate ``delta_alpha_N /
    delta_alpha_n`` of the pixel's shaded pieces (0 where none; > 1 exactly where flagged);
    ``dot`` (H, W): the smallest corner-normal dot product (1 where no shaded piece).
    """

    flag: np.ndarray
    rate: np.ndarray
    dot: np.ndarray


class _Pieces(NamedTuple):
    """The shaded visible pieces: fragment rows, their polygons and corner normals."""

    rows: np.ndarray
    polygon: np.ndarray
    corners: np.ndarray  # (k, 4, 3)
    dot: np.ndarray  # (k,)


def shaded_pieces(field: ShadingField, fragments: Fragments, width: int) -> _Pieces:
    poly = fragments.polygon
    rows = np.flatnonzero((poly >= 0) & field.shaded[np.maximum(poly, 0)] if len(field.shaded) else np.zeros(len(poly), bool))
    polygon = poly[rows]
    col = (fragments.pixel[rows] % width).astype(np.float64)
    row = (fragments.pixel[rows] // width).astype(np.float64)
    corners = np.stack(
        [field.normals(polygon, col + dx, row + dy) for dx, dy in corner_offsets], axis=1
    )
    return _Pieces(rows, polygon, corners, min_corner_dot(corners))


def specular_aliasing_map(scene: Scene, *, power: float = 1.0) -> AliasingMap:
    """Where Amanatides' test detects specular aliasing, and the oversampling rate it implies.

    Parameters
    ----------
    scene : Scene
        A scene at some frame; its ``[shaded]`` objects are tested, flat polygons never
        alias.
    power : float, optional
        1 (default) for the conservative MinDot[n] = cos(pi / 2n); below 1, the aggressive
        table built from the frequency holding that fraction of the power of cos^n.
    """
    expanded = expand_shaded(scene)
    fragments = visible_fragments(expanded.scene)
    pieces = shaded_pieces(expanded.field, fragments, scene.width)
    n = expanded.field.n[pieces.polygon]
    rate = amanatides_rate(pieces.dot, n, power)
    flagged = pieces.dot < min_dot(n, power)
    size = scene.width * scene.height
    pixel = fragments.pixel[pieces.rows]
    rate_img = np.zeros(size)
    np.maximum.at(rate_img, pixel, rate)
    dot_img = np.ones(size)
    np.minimum.at(dot_img, pixel, pieces.dot)
    flag_img = np.zeros(size, bool)
    flag_img[pixel[flagged]] = True
    shape = (scene.height, scene.width)
    return AliasingMap(flag_img.reshape(shape), rate_img.reshape(shape), dot_img.reshape(shape))


def fragment_parameters(field: ShadingField, pieces: _Pieces, **options) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per shaded piece: ``(n', ks', flagged)`` for the specular method ``options`` name.

    ``flagged`` is Amanatides' detection (conservative, or at ``power``). A method with a
    clamp (:mod:`aaeval.specular.methods`) gets ``n' = min(clamp(corners, n), n)`` and, with
    ``energy="amanatides"``, ``ks' = ks Maximum[n] / Maximum[n']``; the others keep n and
    ks (crow acts on flagged pieces by supersampling).
    """
    options = specular_options(**options)
    n = field.n[pieces.polygon]
    ks = field.ks[pieces.polygon]
    flagged = pieces.dot < min_dot(n, options["power"])
    clamp = SPECULAR_METHODS[options["specular"]].clamp
    if clamp is None:
        return n, ks, flagged
    n_new = np.minimum(clamp(pieces.corners, n, **{k: v for k, v in options.items() if k != "specular"}), n)
    ks_new = rescale_ks(ks, n, n_new) if options["energy"] == "amanatides" else ks
    return n_new, ks_new, flagged


def render_shaded(scene: Scene, *, return_specular: bool = False, **options):
    """Render a scene with ``[shaded]`` objects by Catmull's exact visibility.

    Parameters
    ----------
    scene : Scene
    return_specular : bool
        Also return the specular term alone (H, W), box filtered.
    **options
        ``specular`` (the method), ``power``, ``k``, ``region``, ``energy``: the
        parameters of :data:`aaeval.specular.methods.PARAMETERS`, which documents them and
        gives their defaults.

    Returns
    -------
    ndarray (H, W, 3), and the specular image if ``return_specular``.
    """
    options = specular_options(**options)
    expanded = expand_shaded(scene)
    fragments = visible_fragments(expanded.scene)
    field = expanded.field
    pieces = shaded_pieces(field, fragments, scene.width)
    n_new, ks_new, flagged = fragment_parameters(field, pieces, **options)

    size = scene.width * scene.height
    weights = fragments.area.copy()
    rgb = _flat_colours(expanded, fragments)
    spec = np.zeros(len(fragments.area))
    shaded_rgb, shaded_spec = _shade(field, pieces.polygon, fragments.cx[pieces.rows], fragments.cy[pieces.rows], n_new, ks_new)
    rgb[pieces.rows] = shaded_rgb
    spec[pieces.rows] = shaded_spec

    image = _accumulate(fragments.pixel, weights, rgb, spec, size)
    if SPECULAR_METHODS[options["specular"]].supersample:
        chosen = flagged if options["region"] == "flagged" else np.ones(len(pieces.rows), bool)
        if chosen.any():
            rows = pieces.rows[chosen]
            # remove the single shade of each supersampled piece, add its K x K shades
            image -= _accumulate(fragments.pixel[rows], weights[rows], rgb[rows], spec[rows], size)
            image += _supersampled(expanded, fragments, rows, options["k"], size)
    rgb_img = image[:, :3].reshape(scene.height, scene.width, 3)
    if return_specular:
        return rgb_img, image[:, 3].reshape(scene.height, scene.width)
    return rgb_img


def _flat_colours(expanded: ShadedScene, fragments: Fragments) -> np.ndarray:
    polys = expanded.scene.polygons
    colors = np.vstack([np.array([p.color for p in polys]).reshape(-1, 3), expanded.scene.background])
    return colors[fragments.polygon].copy()


def _shade(field: ShadingField, polygon, x, y, n, ks):
    N = field.normals(polygon, x, y)
    L = field.light_directions(polygon, x, y)
    return phong(N, L, field.color[polygon], field.ka[polygon], field.kd[polygon], ks, n)


def _accumulate(pixel, weights, rgb, spec, size) -> np.ndarray:
    """Area-weighted sums per pixel of rgb and the specular term: (size, 4)."""
    out = np.empty((size, 4))
    for ch in range(3):
        out[:, ch] = np.bincount(pixel, weights=weights * rgb[:, ch], minlength=size)
    out[:, 3] = np.bincount(pixel, weights=weights * spec, minlength=size)
    return out


def _supersampled(expanded: ShadedScene, fragments: Fragments, rows: np.ndarray, k: int, size: int) -> np.ndarray:
    """K x K-shaded contribution of the chosen pieces, from the scene scaled by K."""
    scene = expanded.scene
    field = expanded.field
    fine = visible_fragments(scaled_scene(scene, k))
    fine_col = fine.pixel % (scene.width * k)
    fine_row = fine.pixel // (scene.width * k)
    parent = (fine_row // k) * scene.width + fine_col // k
    n_poly = len(scene.polygons) + 1
    wanted = fragments.pixel[rows].astype(np.int64) * n_poly + fragments.polygon[rows]
    key = parent.astype(np.int64) * n_poly + fine.polygon
    keep = np.isin(key, wanted) & (fine.polygon >= 0)
    polygon = fine.polygon[keep]
    x, y = fine.cx[keep] / k, fine.cy[keep] / k
    rgb, spec = _shade(field, polygon, x, y, field.n[polygon], field.ks[polygon])
    return _accumulate(parent[keep], fine.area[keep] / (k * k), rgb, spec, size)


def scaled_scene(scene: Scene, k: int) -> Scene:
    """The scene magnified k times in x and y (depth planes rescaled to match)."""
    scale = np.array([k, k, 1.0])
    polygons = tuple(
        replace(p, vertices=p.vertices * scale, plane=p.plane * np.array([1.0 / k, 1.0 / k, 1.0]))
        for p in scene.polygons
    )
    return replace(scene, width=scene.width * k, height=scene.height * k, polygons=polygons)
