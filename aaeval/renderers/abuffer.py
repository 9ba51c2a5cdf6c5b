"""Method ``abuffer``: Carpenter 1984, "The A-buffer, an antialiased hidden surface method".

The kernel is C++ (``src/samplers/abuffer.cpp``, module ``aaeval.native.samplers``).

Per pixel, every polygon that reaches a subsample becomes a *fragment*: a 4 x 8 bit
coverage mask (4 rows of 8 subsamples, bit ``8 j + i`` at the subcell centre
``(col + (i + 1/2)/8, row + (j + 1/2)/4)``) and the z range of its plane over the part
of the polygon inside the pixel. The mask is Carpenter's XOR of per-edge masks (a bit
flips for every edge crossing to its right), i.e. the crossing-parity test of
the point samplers' ``inside`` at the 32 subcell centres. The z range
is exact: the plane is linear, so its extremes over polygon ∩ pixel lie at that
region's vertices, which are the polygon's edges clipped to the pixel square and the
pixel corners inside the polygon.

Resolution, front to back: fragments are sorted on ``zmin`` by the scene format's tie
rule (fragments within ``eps_z`` of the nearest ``zmin`` are tied, the later polygon in
the file first: :func:`aaeval.scenes.depth.front_to_back`'s rule) and each one claims the subsamples of its mask that no nearer fragment has
claimed. Where the z range of a fragment ``f`` overlaps that of the next fragment ``g``
whose mask meets f's claimed bits, the two surfaces may cross inside the pixel, and the
paper blends them on the shared bits by the fraction of f estimated to be in front,
assuming the two planes run in opposite directions across the pixel::

    front = (g.zmax - f.zmin) / ((f.zmax - f.zmin) + (g.zmax - g.zmin))

(clamped to [0, 1]). The paper is not in ``shared/seeds``: this formula is the one the
A-buffer is usually described with, not checked against its text. For planes of equal
and opposite slope across the pixel the estimate is exact.

This is a simple version of Carpenter's recursive blender: only the next overlapping
fragment is blended in (not the whole chain behind it), and two fragments on one plane
over the pixel are not blended — the later polygon in the file takes the shared bits,
as the scene format requires. Everything else is quantised to 1/32 of the pixel.
"""

from __future__ import annotations

import numpy as np

from aaeval.native.samplers import abuffer_image
from aaeval.renderers.catmull import BOX_ONLY
from aaeval.renderers.cost import scene_load
from aaeval.renderers.registry import register_method
from aaeval.renderers.sampling import kernel_scene, warmup_scene
from aaeval.scenes import Scene

__all__ = ["render_abuffer"]


@register_method(
    "abuffer",
    summary="Carpenter 1984 A-buffer: 4x8 coverage masks with z ranges, resolved front to back",
    options=BOX_ONLY,
    warmup=lambda: render_abuffer(warmup_scene()),
    # fragments of one row are buffered (5 arrays, doubling); each pixel's are sorted by
    # insertion, or by a stable merge sort (same order) beyond 16: the front-to-back pass
    # still visits every fragment below the first to find the one to blend with, so time
    # can grow with the square of the depth per pixel (a bound, not the usual cost)
    memory=lambda scene, o: 2 * 40 * scene_load(scene).fragments / max(scene.height, 1),
    seconds=lambda scene, o: 2e-9 * scene_load(scene).depth_squares,
)
def render_abuffer(scene: Scene, filter: str = "box") -> np.ndarray:
    return abuffer_image(*kernel_scene(scene))
