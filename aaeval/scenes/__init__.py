"""Scenes: the polygon scene format, its extensions, and scene generators."""

from aaeval.scenes.format import (
    Polygon,
    PolygonArrays,
    Scene,
    SceneError,
    newell_normal,
    register_section,
)
from aaeval.scenes.document import load_scene, parse_scene

from aaeval.scenes.holes import HoledPolygon  # noqa: E402

# extensions of the scene format register their tables on import
from aaeval.scenes import shaded  # noqa: E402,F401
from aaeval.scenes import sources  # noqa: E402,F401

__all__ = [
    "HoledPolygon",
    "Polygon",
    "PolygonArrays",
    "Scene",
    "SceneError",
    "load_scene",
    "newell_normal",
    "parse_scene",
    "register_section",
]
