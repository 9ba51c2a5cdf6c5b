"""Point samples at one fixed offset from every pixel centre, with the polygon each one sees.

The shipped real-time methods (``msaa``, ``fxaa``, ``taa``) sample every pixel at the same
sub-pixel offsets (a multisample pattern, the pixel centre, one jitter per frame). The
point-sampling kernel (``aaeval.native.samplers.sample_image``, :mod:`aaeval.renderers.sampling`) samples
pixel centres; a sample at ``(col + 1/2 + dx, row + 1/2 + dy)`` is the pixel centre of the
scene moved by ``(-dx, -dy)``, so each offset is one centre-sampled pass over the moved
kernel arrays (vertices shifted, depth planes rewritten for the shift: the same planes,
evaluated at the same scene points). The kernel, its inside rule and the scene format's
near-tie rule are used unchanged; no kernel code is added.

The kernel returns colours; here every polygon's "colour" is its kernel index (and the
background -1), so one pass gives the visible polygon of each sample, from which
:class:`OffsetSampler` gives flat colours, or Phong shades for ``[shaded]`` scenes
(``docs/shaded_scenes.md``) evaluated at any point the caller chooses: the pixel centre
(MSAA: one shade per pixel and polygon) or the sample itself.
"""

from __future__ import annotations

import numpy as np

from aaeval.native.samplers import sample_image
from aaeval.filters import get_filter
from aaeval.filters.registry import profile_args
from aaeval.catmull import kernel_inputs
from aaeval.scenes import Scene

__all__ = ["OffsetSampler", "halton"]


class OffsetSampler:
    """A scene prepared once (kernel arrays, near ties resolved) for samples at any offset.

    Parameters
    ----------
    scene : Scene
        At its frame; ``[shaded]`` objects are expanded into their triangles and shaded
        with the scene's Phong material and light.
    """

    def __init__(self, scene: Scene):
        from aaeval.scenes.shaded import expand_shaded, has_shaded

        self.width, self.height = scene.width, scene.height
        self.field = None
        if has_shaded(scene):
            expanded = expand_shaded(scene)
            scene, self.field = expanded.scene, expanded.field
        self.scene = scene  # with [shaded] objects expanded into their triangles
        start, length, x, y, planes, source, eps_z = kernel_inputs(scene)
        self._kernel = (start, length, x, y, planes, eps_z)
        self.source = source
        n = len(start)
        self._ids = np.zeros((n, 3))
        self._ids[:, 0] = np.arange(n)
        self.colors = np.ascontiguousarray(scene.arrays.colors[source]).reshape(n, 3)
        self.background = np.asarray(scene.background, dtype=np.float64)
        self._box = profile_args(get_filter("box"))

    def ids(self, dx: float, dy: float) -> np.ndarray:
        """Kernel polygon visible at ``(col + 1/2 + dx, row + 1/2 + dy)`` of every pixel
        (``-1``: background), shape (H, W)."""
        start, length, x, y, planes, eps_z = self._kernel
        moved = planes.copy()
        # z at scene point X + d, written as a plane in the moved frame's coordinate X
        moved[:, 2] += planes[:, 0] * dx + planes[:, 1] * dy
        out = sample_image(self.width, self.height, start, length, x - dx, y - dy, moved, eps_z, self._ids,
                           np.array([-1.0, 0.0, 0.0]), 1, False, 0, *self._box)
        return np.rint(out[:, :, 0]).astype(np.int64)

    def colours(self, ids: np.ndarray, shade_x: np.ndarray | None = None, shade_y: np.ndarray | None = None) -> np.ndarray:
        """Linear RGB (H, W, 3) of the polygons ``ids``: their flat colour, or for shaded
        polygons the Phong shade at image point ``(shade_x, shade_y)`` (H, W each)."""
        out = np.empty(ids.shape + (3,))
        hit = ids >= 0
        out[~hit] = self.background
        out[hit] = self.colors[ids[hit]]
        if self.field is not None and hit.any():
            from aaeval.specular.shading import phong

            poly = np.full(ids.shape, -1, np.int64)
            poly[hit] = self.source[ids[hit]]
            shaded = hit & self.field.shaded[np.maximum(poly, 0)]
            if shaded.any():
                p = poly[shaded]
                xs, ys = shade_x[shaded], shade_y[shaded]
                f = self.field
                rgb, _ = phong(f.normals(p, xs, ys), f.light_directions(p, xs, ys), f.color[p], f.ka[p], f.kd[p],
                               f.ks[p], f.n[p])
                out[shaded] = rgb
        return out

    def sample(self, dx: float, dy: float, *, shade_at_centre: bool = False) -> np.ndarray:
        """The image of one sample per pixel at offset ``(dx, dy)`` from the centre; shaded
        polygons are shaded at the sample, or at the pixel centre when ``shade_at_centre``."""
        cols = np.arange(self.width) + 0.5
        rows = np.arange(self.height) + 0.5
        sx, sy = np.meshgrid(cols, rows)
        if not shade_at_centre:
            sx, sy = sx + dx, sy + dy
        return self.colours(self.ids(dx, dy), sx, sy)


def halton(index: int, base: int) -> float:
    """The radical inverse of ``index`` in ``base`` (Halton 1960): 1 -> 1/2, 2 -> 1/4, 3 -> 3/4 in base 2."""
    result, f = 0.0, 1.0
    while index > 0:
        f /= base
        result += f * (index % base)
        index //= base
    return result
