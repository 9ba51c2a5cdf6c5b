"""What every builder of a generated scene shares: the positive-count check of its
arguments and the step that turns its polygons into a :class:`~aaeval.scenes.Scene`
through :func:`~aaeval.scenes.document.parse_scene`, so that what a builder returns has
passed the same validation as a file."""

from __future__ import annotations

from typing import Any

import numpy as np

from aaeval.scenes.document import parse_scene
from aaeval.scenes.format import Scene

__all__ = ["built_scene", "check_count"]


def built_scene(width, height, polygons, *, animation=None, source) -> Scene:
    """The scene of ``polygons`` (TOML-shaped tables) in a ``width`` x ``height`` image,
    parsed and validated as a file is; ``source`` names the builder call."""
    document: dict[str, Any] = {"image": {"width": int(width), "height": int(height)}, "polygons": polygons}
    if animation:
        document["animation"] = animation
    return parse_scene(document, source=source)


def check_count(n: Any, name: str) -> None:
    """Refuse a count argument ``name`` that is not a positive integer (a ValueError)."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"{name} must be a positive integer, got {n!r}")
