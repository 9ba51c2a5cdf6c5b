"""Imported shapes to a scene file: layers in depth order, polygons with holes, TOML.

Each imported layer (an SVG element's fill or stroke, a glyph) lies on its own depth
plane, later layers nearer (``z = layers - k``), so document order is depth order for
every method, the A-buffer's z ranges included, and no two layers ever tie.
"""

from __future__ import annotations

from typing import Any, Mapping, NamedTuple

import numpy as np

from aaeval.importers.shapes import Region
from aaeval.scenes import SceneError, parse_scene

__all__ = ["Layer", "ImportResult", "scene_document", "region_polygons"]


class Layer(NamedTuple):
    """What one source element paints: a linear RGB colour over some regions."""

    color: np.ndarray
    regions: list[Region]
    name: str  # for messages: the element's id or the glyph


class ImportResult(NamedTuple):
    """An imported scene: the document (validated), what was ignored, and counts."""

    document: dict
    ignored: list[str]
    cut: int  # regions written as triangles because their rings touch (see region_polygons)


def region_polygons(region: Region, color, z: float) -> tuple[list[dict], bool]:
    """The scene polygons of one region: itself with its holes when the format takes it,
    else its earcut triangles (rings that touch at a vertex, which the format refuses,
    still triangulate into pieces that abut exactly). Returns (polygons, cut)."""
    lift = lambda ring: np.column_stack([ring, np.full(len(ring), z)]).tolist()  # noqa: E731
    table = {"color": list(map(float, color)), "vertices": lift(region.outer)}
    if region.holes:
        table["holes"] = [lift(h) for h in region.holes]
    try:
        parse_scene({"image": {"width": 1, "height": 1}, "polygons": [table]})
        return [table], False
    except SceneError:
        pass
    import mapbox_earcut

    rings = [region.outer, *region.holes]
    points = np.concatenate(rings)
    ends = np.cumsum([len(r) for r in rings]).astype(np.uint32)
    faces = mapbox_earcut.triangulate_float64(points, ends).reshape(-1, 3)
    tri = points[faces]
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    keep = np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]) > 1e-12
    return [{"color": table["color"], "vertices": lift(t)} for t in tri[keep]], True


def scene_document(
    width: int, height: int, background, layers: list[Layer], *,
    extension: tuple[str, Mapping[str, Any]] | None = None, frames: int = 1, translate=(0.0, 0.0),
) -> tuple[dict, int]:
    """A validated scene dictionary of the layers (first layer farthest). Returns (document, cut)."""
    polygons, cut = [], 0
    for k, layer in enumerate(layers):
        for region in layer.regions:
            tables, was_cut = region_polygons(region, layer.color, float(len(layers) - k))
            polygons.extend(tables)
            cut += was_cut
    document: dict[str, Any] = {
        "image": {"width": int(width), "height": int(height), "background": [float(v) for v in background]},
    }
    if frames != 1 or any(translate):
        document["animation"] = {"frames": int(frames), "translate": [float(v) for v in translate]}
    if extension is not None:
        document[extension[0]] = dict(extension[1])
    document["polygons"] = polygons
    return document, cut
