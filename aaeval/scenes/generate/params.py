"""What several generators share, declared once: their common parameters (frames, the
step per frame, the image side), the size rule of a square image, and the animation
table a generated scene moves by."""

from __future__ import annotations

from typing import Any, Callable, Mapping

from aaeval.options import Option
from aaeval.scenes.format import Scene
from aaeval.scenes.write import scene_to_dict

__all__ = ["FRAMES", "MAX_SIDE", "STEP", "animated", "animation_table", "image_side", "square_image"]


# Parameters shared by several generators (declared once)
MAX_SIDE = 16384  # the scene format's largest image side
FRAMES = Option(int, 1, "frames of the animation (1 = a still scene)", minimum=1, maximum=100_000)
STEP = Option(float, 0.125, "sub-pixel translation per frame (px)", minimum=-64.0, maximum=64.0)


def image_side(default: int, doc: str = "image width and height (px)") -> Option:
    """An image-side parameter with its ``default``, from 4 px to :data:`MAX_SIDE`."""
    return Option(int, default, doc, minimum=4, maximum=MAX_SIDE)


def square_image(size_key: str = "size", polygons: Callable[[float, Mapping[str, Any]], int] = lambda d, p: 0):
    """A generator's ``size`` rule for a square image of side ``params[size_key]`` over
    ``params["frames"]`` frames, holding ``polygons(difficulty, params)`` polygons."""

    def size(d: float, p: Mapping[str, Any]) -> tuple[int, int]:
        return polygons(d, p), p[size_key] ** 2 * p["frames"]

    return size


def animation_table(frames: int, step: float) -> dict:
    """The ``[animation]`` table of ``frames`` frames moving by ``step`` px a frame."""
    # an irrational-looking direction so edges cross sample positions at many phases
    return {"frames": int(frames), "translate": [step, step * 0.61803398875]}


def animated(scene: Scene, frames: int, step: float) -> dict:
    """The document of ``scene``, moving over ``frames`` frames when there is more than one."""
    document = scene_to_dict(scene)
    if frames > 1:
        document["animation"] = animation_table(frames, step)
    return document
