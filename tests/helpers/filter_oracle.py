"""A test-only reference for filtered images: GEOS visible regions and area quadrature.

Independent of :mod:`aaeval.filters` except for the filter's *name*: the profiles are
written out here from Mitsuba 3's sources (``src/rfilters/*.cpp``), the visible regions
come from :func:`oracle.visible_regions` (GEOS), each region is cut into knot cells and
triangulated (GEOS constrained Delaunay), and every triangle is integrated with a
collapsed-square (Duffy) tensor Gauss-Legendre rule: exact for the polynomial filters at
the order used, converged below 1e-13 for the Gaussian (the test checks two orders).
"""

from __future__ import annotations

import numpy as np
import shapely

from tests.helpers.oracle import visible_regions, whole_polygons

# --- the filters, as Mitsuba 3 writes them -----------------------------------------


def _mitchell(b, c):
    def k(t):
        x = np.abs(t)
        inner = ((12 - 9 * b - 6 * c) * x**3 + (-18 + 12 * b + 6 * c) * x**2 + (6 - 2 * b)) / 6
        outer = ((-b - 6 * c) * x**3 + (6 * b + 30 * c) * x**2 + (-12 * b - 48 * c) * x + (8 * b + 24 * c)) / 6
        return np.where(x < 1, inner, np.where(x < 2, outer, 0.0))

    return k


def _gaussian(t, stddev=0.5):
    alpha = -1.0 / (2 * stddev * stddev)
    radius = 4 * stddev
    return np.maximum(0.0, np.exp(alpha * t * t) - np.exp(alpha * radius * radius))


PROFILES = {
    "box": (0.5, lambda t: np.where(np.abs(t) <= 0.5, 1.0, 0.0)),
    "tent": (1.0, lambda t: np.maximum(0.0, 1.0 - np.abs(t))),
    "bspline": (2.0, _mitchell(1.0, 0.0)),
    "mitchell": (2.0, _mitchell(1 / 3, 1 / 3)),
    "catmullrom": (2.0, _mitchell(0.0, 0.5)),
    "gaussian": (2.0, _gaussian),
}


# --- quadrature on triangles ---------------------------------------------------------


def triangle_rule(order: int):
    """Points (barycentric-free: (s, t) in the unit triangle) and weights of a Duffy rule."""
    g, w = np.polynomial.legendre.leggauss(order)
    g = 0.5 * (g + 1)
    w = 0.5 * w
    a, b = np.meshgrid(g, g, indexing="ij")
    wa, wb = np.meshgrid(w, w, indexing="ij")
    # (a, b) in the unit square -> (s, t) = (a, b (1 - a)), Jacobian (1 - a)
    s = a.ravel()
    t = (b * (1 - a)).ravel()
    weight = (wa * wb * (1 - a)).ravel()
    return s, t, weight


def _region_points(region, cells, rule):
    """Quadrature points and weights of ``region`` cut into the knot cells."""
    s, t, weight = rule
    xs, ys, ws = [], [], []
    for cell in cells:
        part = shapely.intersection(region, cell)
        if part.is_empty or part.area == 0:
            continue
        tris = shapely.constrained_delaunay_triangles(part)
        for tri in getattr(tris, "geoms", [tris]):
            if tri.is_empty:
                continue
            p = np.asarray(tri.exterior.coords)[:3]
            e1 = p[1] - p[0]
            e2 = p[2] - p[0]
            jac = abs(e1[0] * e2[1] - e1[1] * e2[0])
            xs.append(p[0, 0] + s * e1[0] + t * e2[0])
            ys.append(p[0, 1] + s * e1[1] + t * e2[1])
            ws.append(weight * jac)
    if not xs:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    return np.concatenate(xs), np.concatenate(ys), np.concatenate(ws)


def _knot_cells(width, height, box_filter):
    """Cells on which every pixel's filter is smooth, clipped to the image."""
    if box_filter:  # knots on the integer grid
        xs = np.arange(width + 1.0)
        ys = np.arange(height + 1.0)
    else:  # pixel centres at i + 1/2 and integer knot spacing: half-integer lines
        xs = np.concatenate([[0.0], np.arange(0.5, width, 1.0), [float(width)]])
        ys = np.concatenate([[0.0], np.arange(0.5, height, 1.0), [float(height)]])
    return [shapely.box(x0, y0, x1, y1) for x0, x1 in zip(xs[:-1], xs[1:]) for y0, y1 in zip(ys[:-1], ys[1:])]


def _reached(p, count, radius, profile):
    """The pixels (along one axis) whose centres a point's filter reaches, and their weights.

    A filter of this radius reaches the centres j + 1/2 with |p - j - 1/2| <= radius: at most
    floor(2 radius) + 1 of them, from ceil(p - 1/2 - radius). Returns the indices (points, K),
    clipped into the image, and the profile there (points, K), zero past the image's edge: every
    other centre's weight is 0 exactly (each profile is 0 beyond its radius).
    """
    k = int(np.floor(2 * radius)) + 1
    j = np.ceil(p - 0.5 - radius).astype(np.int64)[:, None] + np.arange(k)[None, :]
    inside = (j >= 0) & (j < count)
    return np.clip(j, 0, count - 1), np.where(inside, profile(p[:, None] - (j + 0.5)), 0.0)


def filtered_oracle(scene, name: str, order: int = 6) -> np.ndarray:
    """The image ``(H, W, 3)`` filtered by ``name`` and normalised as Mitsuba's film does."""
    radius, profile = PROFILES[name]
    width, height = scene.width, scene.height
    cells = _knot_cells(width, height, name == "box")
    rule = triangle_rule(order)
    image_box = shapely.box(0, 0, width, height)
    regions = [r.intersection(image_box) for r in visible_regions(scene)]
    colors = [p.color for p in whole_polygons(scene)]  # holed polygons whole, as the regions are

    def weights(region):
        """sum_p w_p wy[p, j] wx[p, i] over the region's points: each point adds only to the
        pixels its filter reaches (a dense (points, W) profile was most of the oracle's time)."""
        x, y, w = _region_points(region, cells, rule)
        total = np.zeros(height * width)
        for part in range(0, len(x), 100_000):  # (points, K, K) at a time, a few tens of MB
            cut = slice(part, part + 100_000)
            ix, wx = _reached(x[cut], width, radius, profile)
            iy, wy = _reached(y[cut], height, radius, profile)
            index = iy[:, :, None] * width + ix[:, None, :]
            value = w[cut, None, None] * wy[:, :, None] * wx[:, None, :]
            total += np.bincount(index.ravel(), value.ravel(), minlength=height * width)
        return total.reshape(height, width)

    # the film's denominator: the filter over the whole image; the background gets what
    # the visible regions leave of it (a GEOS difference of their union is not robust
    # enough: it lost whole pixels on a scene with holes)
    den = weights(image_box)
    num = np.zeros((height, width, 3))
    covered = np.zeros((height, width))
    for region, color in zip(regions, colors):
        if region.is_empty:
            continue
        weight = weights(region)
        num += weight[..., None] * np.asarray(color)
        covered += weight
    num += (den - covered)[..., None] * np.asarray(scene.background)
    return num / den[..., None]
