"""The generators of a shaded scene: one shiny cylinder of the ``[shaded]`` extension
whose Phong exponent (``shininess``) or curvature (``curvature``) is the difficulty."""

from __future__ import annotations

from typing import Any, Mapping

from aaeval.options import Option
from aaeval.scenes.generate.params import FRAMES, STEP, animation_table, image_side, square_image
from aaeval.scenes.generate.registry import MAX_POLYGONS, register_generator


def _shiny_cylinder(size: int, radius: float, n: float, frames: int, step: float, segments: int) -> dict:
    # one cylinder of the [shaded] extension (docs/shaded_scenes.md), lit from behind the
    # viewer, so the highlight runs along the axis where the normal faces the viewer
    c = size / 2
    return {
        "image": {"width": size, "height": size, "background": [0.02, 0.02, 0.03]},
        "animation": animation_table(frames, step),
        "shaded": {
            "light": {"type": "directional", "direction": [0.3, 0.0, -1.0]},
            "cylinders": [{
                "centre": [c + 0.173, c + 0.291, 200.0], "axis": [0.12, 1.0, 0.0], "radius": float(radius),
                "length": 0.8 * size, "segments": int(segments),
                "spin": {"axis": [0.0, 0.0, 1.0], "degrees": 0.2},
                "material": {"color": [0.75, 0.12, 0.10], "ka": 0.15, "kd": 0.55, "ks": 0.8, "n": float(n)},
            }],
        },
    }


_SEGMENTS = Option(int, 48, "facets around the cylinder", minimum=3, maximum=MAX_POLYGONS // 4)


def _cylinder_polygons(d: float, p: Mapping[str, Any]) -> int:
    return 4 * p["segments"]  # two side triangles and two cap triangles per facet


@register_generator(
    "shininess",
    difficulty="Phong exponent n",
    difficulty_param=Option(float, None, "Phong exponent of the cylinder", minimum=1, maximum=1e6),
    params={"size": image_side(32), "radius": Option(float, 9.0, "cylinder radius (px)", minimum=0, maximum=1e6, low_open=True),
            "frames": FRAMES, "step": STEP, "segments": _SEGMENTS},
    size=square_image(polygons=_cylinder_polygons),
)
def _shininess(difficulty: float, *, size: int, radius: float, frames: int, step: float, segments: int) -> dict:
    """A shiny cylinder whose Phong exponent is ``difficulty``: the highlight narrows as it grows."""
    return _shiny_cylinder(size, radius, difficulty, frames, step, segments)


@register_generator(
    "curvature",
    difficulty="curvature 1 / radius (1/px)",
    difficulty_param=Option(float, None, "1 / cylinder radius, 1/px", minimum=0, maximum=2, low_open=True),
    params={"size": image_side(32), "n": Option(float, 200.0, "Phong exponent of the cylinder", minimum=1, maximum=1e6),
            "frames": FRAMES, "step": STEP, "segments": _SEGMENTS},
    size=square_image(polygons=_cylinder_polygons),
)
def _curvature(difficulty: float, *, size: int, n: float, frames: int, step: float, segments: int) -> dict:
    """A shiny cylinder of radius ``1 / difficulty``: the normal turns faster across a pixel as it grows."""
    return _shiny_cylinder(size, min(1.0 / difficulty, 0.4 * size), n, frames, step, segments)
