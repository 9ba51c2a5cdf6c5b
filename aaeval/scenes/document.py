"""A scene document read whole: :func:`load_scene` (a TOML file) and :func:`parse_scene`
(the parsed document), every rule of ``docs/scene_format.md`` checked.

The polygons and their rules are :mod:`aaeval.scenes.format`'s, polygons with holes
:mod:`aaeval.scenes.holes`'s; the extension tables parse with the functions registered
in :data:`aaeval.scenes.format.SECTIONS`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

import numpy as np

from aaeval._toml import collector_paused, read_toml
from aaeval.scenes.format import (
    CORE_KEYS,
    MAX_COORDINATE,
    MAX_PIXELS,
    SECTIONS,
    Scene,
    SceneError,
    no_unknown,
    rgb,
    vector,
)
from aaeval.scenes.holes import polygons_with_holes

__all__ = ["load_scene", "parse_scene"]


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file.

    Raises
    ------
    SceneError
        The file is missing, is not TOML, or breaks a rule of the format.
    """
    with collector_paused():  # a large scene's document holds no cycle (aaeval._toml)
        document, _ = read_toml(path, SceneError, "scene file")
        try:
            return parse_scene(document, source=str(path))
        finally:
            del document  # freed now, before the collector is back: it never walks the document


def parse_scene(document: Mapping[str, Any], *, source: str = "<scene>") -> Scene:
    """Validate a scene given as a dictionary (the parsed TOML)."""
    if not isinstance(document, Mapping):
        raise SceneError(f"{source}: a scene is a table of keys, got {type(document).__name__}")
    unknown = sorted(set(document) - CORE_KEYS - set(SECTIONS))
    if unknown:
        known = ", ".join(sorted(CORE_KEYS | set(SECTIONS)))
        raise SceneError(f"{source}: unknown top-level key(s) {unknown}; known keys: {known}")

    image = _table(document, "image", source, required=True)
    no_unknown(image, {"width", "height", "background"}, f"{source}: [image]")
    width = _positive_int(image, "width", f"{source}: [image]")
    height = _positive_int(image, "height", f"{source}: [image]")
    if width * height > MAX_PIXELS:
        raise SceneError(f"{source}: [image] {width}x{height} is over the limit of {MAX_PIXELS} pixels")
    background = rgb(image.get("background", [0.0, 0.0, 0.0]), f"{source}: [image].background")

    animation = _table(document, "animation", source, required=False)
    no_unknown(animation, {"frames", "translate", "phases", "seed"}, f"{source}: [animation]")
    frames = _positive_int(animation, "frames", f"{source}: [animation]") if "frames" in animation else 1
    translate = vector(animation.get("translate", [0.0, 0.0]), 2, f"{source}: [animation].translate")
    phases, phase_seed = _phases(animation, f"{source}: [animation]")

    raw_polygons = document.get("polygons", [])
    if not isinstance(raw_polygons, list):
        raise SceneError(f"{source}: 'polygons' must be an array of tables ([[polygons]])")
    polygons, holed = polygons_with_holes(raw_polygons, source)
    # phase offsets stay below 1 px: one more pixel of reach covers them
    _check_animation_range(polygons, frames, translate, f"{source}: [animation]", extra=phases != "none")

    extensions = {
        name: SECTIONS[name].parse(document[name], f"{source}: [{name}]", dict(document))
        for name in document
        if name in SECTIONS
    }
    return Scene(
        width=width,
        height=height,
        background=background,
        polygons=polygons,
        frames=frames,
        translate=translate,
        source=source,
        phases=phases,
        phase_seed=phase_seed,
        extensions=extensions,
        holed=holed,
    )


def _table(document: Mapping, key: str, source: str, *, required: bool) -> Mapping:
    if key not in document:
        if required:
            raise SceneError(f"{source}: missing required table [{key}]")
        return {}
    value = document[key]
    if not isinstance(value, Mapping):
        raise SceneError(f"{source}: [{key}] must be a table, got {type(value).__name__}")
    return value


def _positive_int(table: Mapping, key: str, where: str) -> int:
    if key not in table:
        raise SceneError(f"{where}: missing required key '{key}'")
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, int):
        raise SceneError(f"{where}: '{key}' must be an integer, got {value!r}")
    if value < 1:
        raise SceneError(f"{where}: '{key}' must be >= 1, got {value}")
    return value


def _phases(animation: Mapping, where: str) -> tuple[str, int]:
    """``phases`` (one of :data:`aaeval.scenes.phases.PHASES`, default "none") and its ``seed``."""
    from aaeval.scenes.phases import PHASES

    phases = animation.get("phases", "none")
    if not isinstance(phases, str) or phases not in PHASES:
        raise SceneError(f"{where}.phases: expected one of {', '.join(repr(p) for p in PHASES)}, got {phases!r}")
    if "seed" not in animation:
        return phases, 0
    seed = animation["seed"]
    if phases != "random":
        raise SceneError(f"{where}.seed: only phases = \"random\" takes a seed (phases is {phases!r})")
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**63:
        raise SceneError(f"{where}.seed: expected a whole number in [0, 2**63), got {seed!r}")
    return phases, seed


def _check_animation_range(polygons, frames: int, translate: np.ndarray, where: str, extra: bool = False) -> None:
    """Refuse an animation that moves a vertex beyond the coordinate limit (or to infinity)."""
    if frames < 2 or not (translate.any() or extra) or not polygons:
        return
    reach = max(float(np.abs(p.vertices[:, :2]).max()) for p in polygons) + (1.0 if extra else 0.0)
    last = frames - 1
    with np.errstate(over="ignore"):
        moved = reach + last * float(np.abs(translate).max())
    if not moved <= MAX_COORDINATE:  # also catches inf
        raise SceneError(f"{where}: frame {last} moves vertices to {moved:.3g}, beyond +-{MAX_COORDINATE:g} "
                         "(translate x frames too large)")
