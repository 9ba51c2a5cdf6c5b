"""Scenes: the polygon scene format, its extensions, and scene generators."""

from aaeval.scenes.format import (
    Polygon,
    PolygonArrays,
    Scene,
    SceneError,
    load_scene,
    newell_normal,
    parse_scene,
    register_section,
)

__all__ = [
    "Polygon",
    "PolygonArrays",
    "Scene",
    "SceneError",
    "load_scene",
    "newell_normal",
    "parse_scene",
    "register_section",
]
