"""Pictures for notebooks: a Scene or a rendered image shown at a size people can see.

A 32 x 32 scene drawn pixel for pixel is a speck on a screen. Every picture here is
enlarged by a whole factor with nearest-neighbour pixels (each rendered pixel a sharp
square, so aliasing stays visible as aliasing) until its long side reaches
:data:`PREVIEW_SIZE` pixels; :func:`show` takes another ``size``, and setting
``aaeval.preview.PREVIEW_SIZE`` changes the default for every Scene shown afterwards.
"""

from __future__ import annotations

import math
import sys

import numpy as np

from aaeval.errors import ArgumentError

__all__ = ["PREVIEW_METHOD", "PREVIEW_SIZE", "Picture", "show", "png_bytes", "scene_png", "show_scenes_in"]

#: The method a Scene's preview is rendered with: exact and fast on small scenes.
PREVIEW_METHOD = "catmull"
#: The least long side, in screen pixels, of a picture shown in a notebook.
PREVIEW_SIZE = 256
#: The largest long side a picture is enlarged to (a larger image is shown as it is).
_MAX_SIZE = 4096


def enlarged(image: np.ndarray, size: int) -> np.ndarray:
    """``image`` (H, W, ...) repeated by the whole factor that brings its long side to at
    least ``size`` (1 when it is already that large)."""
    long_side = max(image.shape[:2])
    factor = max(1, math.ceil(size / long_side)) if long_side else 1
    return np.repeat(np.repeat(image, factor, axis=0), factor, axis=1)


def png_bytes(image: np.ndarray, size: int | None = None) -> bytes:
    """An (H, W, 3) linear RGB image as sRGB PNG bytes, enlarged to ``size``
    (:data:`PREVIEW_SIZE` when None) on its long side."""
    import io

    from PIL import Image

    from aaeval.imageio import linear_to_srgb8

    image = enlarged(np.asarray(image), _checked_size(PREVIEW_SIZE if size is None else size))
    buffer = io.BytesIO()
    Image.fromarray(linear_to_srgb8(image), "RGB").save(buffer, format="PNG")
    return buffer.getvalue()


def _checked_size(size) -> int:
    if isinstance(size, bool) or not isinstance(size, int) or not 1 <= size <= _MAX_SIZE:
        raise ArgumentError(f"size must be a whole number of pixels from 1 to {_MAX_SIZE}, got {size!r}")
    return size


def scene_png(scene, size: int | None = None) -> bytes:
    """The scene at its frame rendered with :data:`PREVIEW_METHOD`, as PNG bytes."""
    from aaeval import registries
    from aaeval.renderers import render

    registries.load()  # a notebook may show a Scene before calling anything that loads them
    return png_bytes(render(scene, PREVIEW_METHOD, frame=scene.frame), size)


class Picture:
    """A rendered image or a Scene that a notebook shows as a PNG of long side ``size``."""

    def __init__(self, subject, size: int | None = None):
        from aaeval.scenes import Scene

        if not isinstance(subject, Scene):
            subject = np.asarray(subject)
            if subject.ndim != 3 or subject.shape[2] != 3 or subject.dtype.kind not in "fiu" or not subject.size:
                raise ArgumentError(f"show() takes a Scene or an (H, W, 3) image, got an array of shape {subject.shape}")
        self.subject, self.size = subject, None if size is None else _checked_size(size)

    def _repr_png_(self) -> bytes:
        if isinstance(self.subject, np.ndarray):
            return png_bytes(self.subject, self.size)
        return scene_png(self.subject, self.size)

    def __repr__(self) -> str:
        shape = getattr(self.subject, "shape", None)
        return f"<aaeval picture of {shape[1]}x{shape[0]} px>" if shape else "<aaeval picture>"


def show(subject, size: int | None = None) -> Picture:
    """A Scene or a rendered (H, W, 3) image, drawn by a notebook at long side ``size``
    (default :data:`PREVIEW_SIZE`), nearest-neighbour so pixels stay pixels.

    Examples
    --------
    >>> aaeval.show(aaeval.render(scene, "point"), size=512)  # doctest: +SKIP
    """
    return Picture(subject, size)


def show_scenes_in(shell) -> None:
    """Make the IPython ``shell`` draw a :class:`~aaeval.scenes.Scene` as its preview
    (:func:`scene_png`). A Scene is data and renders nothing itself; this module, above
    the renderers, lends it the picture."""
    formatter = shell.display_formatter.formatters["image/png"]
    formatter.for_type_by_name("aaeval.scenes.format", "Scene", scene_png)


def show_scenes_in_a_running_notebook() -> None:
    ipython = sys.modules.get("IPython")  # a notebook has it imported; a script need not
    shell = ipython.get_ipython() if ipython is not None else None
    if shell is not None:
        show_scenes_in(shell)
