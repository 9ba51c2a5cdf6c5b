"""A test-only exact reference for box-filtered polygon scenes, built on GEOS (shapely).

It shares nothing with the renderers: each polygon's visible region is the polygon minus
every other polygon restricted to the half-plane where that one is nearer (for
interpenetrating polygons the boundary is the line where the depth planes cross; on one
shared plane the later polygon is in front; a polygon with holes is one GEOS polygon with
interior rings, never the pieces the scene cuts it into), and a pixel's colour is the sum of the
visible regions' areas over the pixel square times their colours.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import shapely
from shapely.geometry import Polygon as ShapelyPolygon
from shapely.geometry import box

from aaeval.scenes import Scene

# depth-plane differences below this are one shared plane (same as the renderer's scale)
COPLANAR = 1e-9


def _nearer_region(p, q, bounds) -> shapely.Geometry:
    """Where polygon q is in front of polygon p, as a region of the plane."""
    da, db, dc = q.plane - p.plane  # z_q - z_p = da x + db y + dc
    if abs(da) < COPLANAR and abs(db) < COPLANAR and abs(dc) < COPLANAR:
        return box(*bounds) if q.index > p.index else shapely.Polygon()
    if abs(da) < 1e-15 and abs(db) < 1e-15:
        return box(*bounds) if dc < 0 else shapely.Polygon()
    # half-plane da x + db y + dc < 0, as a polygon covering the bounds
    x0, y0, x1, y1 = bounds
    corners = np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])
    big = ShapelyPolygon(corners)
    line_pt = -dc * np.array([da, db]) / (da * da + db * db)
    direction = np.array([-db, da]) / np.hypot(da, db)
    normal = -np.array([da, db]) / np.hypot(da, db)  # towards decreasing z_q - z_p
    span = 4 * max(x1 - x0, y1 - y0) + np.linalg.norm(line_pt) + 10
    half = ShapelyPolygon(
        [
            line_pt - span * direction,
            line_pt + span * direction,
            line_pt + span * direction + span * normal,
            line_pt - span * direction + span * normal,
        ]
    )
    return big.intersection(half)


class _Whole(NamedTuple):
    """A polygon as the file gave it, holes included (the oracle never uses the pieces)."""

    xy: np.ndarray
    holes: list
    plane: np.ndarray
    color: np.ndarray
    index: int  # file order, for ties on a shared plane


def whole_polygons(scene: Scene) -> list[_Whole]:
    """The scene's polygons with their holes as GEOS shapes take them, in file order."""
    holed = {h.first: h for h in scene.holed}
    pieces = {i for h in scene.holed for i in h.pieces}
    wholes = []
    for i, p in enumerate(scene.polygons):
        if i in holed:
            h = holed[i]
            wholes.append(_Whole(h.rings[0][:, :2], [r[:, :2] for r in h.rings[1:]], h.plane, h.color, i))
        elif i not in pieces:
            wholes.append(_Whole(p.xy, [], p.plane, p.color, i))
    return wholes


def document_polygons(document: dict, frame: int = 0) -> list[_Whole]:
    """The polygons of a raw scene document (the dict a TOML file parses to), holes and
    the animation's translation at ``frame`` included, without aaeval's parser: each
    plane is the least-squares plane through the outer ring's vertices."""
    shift = np.asarray(document.get("animation", {}).get("translate", [0.0, 0.0]), dtype=float) * frame
    wholes = []
    for i, p in enumerate(document.get("polygons", [])):
        ring = np.asarray(p["vertices"], dtype=float)
        xy = ring[:, :2] + shift
        fit = np.linalg.lstsq(np.column_stack([xy, np.ones(len(xy))]), ring[:, 2], rcond=None)[0]
        holes = [np.asarray(h, dtype=float)[:, :2] + shift for h in p.get("holes", [])]
        wholes.append(_Whole(xy, holes, fit, np.asarray(p["color"], dtype=float), i))
    return wholes


def document_oracle_image(document: dict, frame: int = 0) -> np.ndarray:
    """:func:`oracle_image` of a raw scene document (see :func:`document_polygons`): the
    reference then owes nothing to how aaeval parses holes or planes."""
    image = document["image"]
    return _overlay(document_polygons(document, frame), image["width"], image["height"],
                    np.asarray(image.get("background", [0.0, 0.0, 0.0]), dtype=float))


def document_visible_areas(document: dict, frame: int = 0) -> np.ndarray:
    """Per pixel, the area each polygon of a raw scene document shows in it, and last the
    background's: shape (H, W, polygons + 1), by GEOS on the document alone."""
    image = document["image"]
    width, height = image["width"], image["height"]
    polygons = document_polygons(document, frame)
    rows, cols = np.mgrid[0:height, 0:width]
    pixels = shapely.box(cols.ravel(), rows.ravel(), cols.ravel() + 1.0, rows.ravel() + 1.0)
    areas = np.zeros((height * width, len(polygons) + 1))
    for i, region in enumerate(_visible(polygons, width, height)):
        if not region.is_empty:
            areas[:, i] = shapely.area(shapely.intersection(pixels, region))
    areas[:, -1] = 1.0 - areas[:, :-1].sum(axis=1)
    return areas.reshape(height, width, -1)


def visible_regions(scene: Scene) -> list[shapely.Geometry]:
    """The exactly visible region of every polygon of the scene (GEOS), holes included."""
    return _visible(whole_polygons(scene), scene.width, scene.height)


def _visible(polygons: list[_Whole], width: int, height: int) -> list[shapely.Geometry]:
    shapes = [ShapelyPolygon(p.xy, p.holes) for p in polygons]
    allpts = np.vstack([p.xy for p in polygons] + [np.array([[0, 0], [width, height]])])
    bounds = (*(allpts.min(axis=0) - 10), *(allpts.max(axis=0) + 10))
    regions = []
    for i, p in enumerate(polygons):
        if not np.isfinite(p.plane).all():
            regions.append(shapely.Polygon())
            continue
        region = shapes[i]
        for j, q in enumerate(polygons):
            if j == i or not np.isfinite(q.plane).all() or not region.intersects(shapes[j]):
                continue
            region = region.difference(shapes[j].intersection(_nearer_region(p, q, bounds)))
        regions.append(region)
    return regions


def oracle_image(scene: Scene) -> np.ndarray:
    """Exact box-filtered image of a flat-coloured scene, by GEOS polygon overlay."""
    return _overlay(whole_polygons(scene), scene.width, scene.height, scene.background)


def _overlay(polygons: list[_Whole], width: int, height: int, background: np.ndarray) -> np.ndarray:
    rows, cols = np.mgrid[0:height, 0:width]
    pixels = shapely.box(cols.ravel(), rows.ravel(), cols.ravel() + 1.0, rows.ravel() + 1.0)
    image = np.zeros((height * width, 3))
    covered = np.zeros(height * width)
    for p, region in zip(polygons, _visible(polygons, width, height)):
        if region.is_empty:
            continue
        area = shapely.area(shapely.intersection(pixels, region))
        image += area[:, None] * p.color
        covered += area
    image += (1.0 - covered)[:, None] * background
    return image.reshape(height, width, 3)
