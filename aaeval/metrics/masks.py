"""Masks the masked metrics are computed over, built from the scene by name.

A metric declares the mask it needs by name (``register_metric(..., mask="edge")``); the
measuring engine (:mod:`aaeval.experiments.measure`) builds it from the scene at the
frame being measured with :func:`build_mask`, once per scene frame, and passes it as the
metric's ``mask`` option. This is the only place that knows how a mask is made.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from aaeval.options import Registry

__all__ = ["MASKS", "Mask", "register_mask", "build_mask", "HIGHLIGHT_THRESHOLD", "HIGHLIGHT_SPP", "INTERIOR_MARGIN"]

#: A pixel is in the highlight when the ground truth's box-filtered specular term exceeds this.
HIGHLIGHT_THRESHOLD = 0.02
#: Samples per pixel of the Mitsuba Phong ground truth the highlight mask is read from: the
#: specular groups' own ground truth (``mitsuba:spp=4096,seed=0``), so a page has one
#: specular truth and the mask is a cache hit.
HIGHLIGHT_SPP = 4096
#: Pixels this close to the outline of what the scene covers are left out of ``interior``
#: (the widest pixel filter reaches 2 pixels).
INTERIOR_MARGIN = 2


@dataclass(frozen=True)
class Mask:
    name: str
    build: Callable[..., np.ndarray]  # build(scene_at_frame) -> bool (H, W)
    summary: str
    applies: Callable[..., bool] = lambda scene: True  # False: the mask is empty on this scene

    def applies_to(self, scene) -> bool:
        return bool(self.applies(scene))


MASKS: Registry = Registry("mask")


def register_mask(name: str, build: Callable[..., np.ndarray] | None = None, summary: str = "",
                  applies: Callable[..., bool] | None = None):
    """Register ``build(scene) -> bool (H, W)``: ``register_mask(name, build, summary)`` or
    ``@register_mask(name, summary=...)``; ``applies(scene)`` is False where it is always empty."""

    def decorate(func):
        MASKS.add(name, Mask(name, func, summary, applies or (lambda scene: True)))
        return func

    return decorate if build is None else decorate(build)


def build_mask(name: str, scene) -> np.ndarray:
    """The mask ``name`` of ``scene`` (at the frame wanted), bool (H, W)."""
    mask = np.asarray(MASKS.get_entry(name).build(scene), dtype=bool)
    if mask.shape != (scene.height, scene.width):
        raise ValueError(f"mask {name!r} has shape {mask.shape}, expected {(scene.height, scene.width)}")
    return mask


def _edge(scene) -> np.ndarray:
    from aaeval.metrics.edges import edge_mask

    return edge_mask(scene)


def _highlight(scene) -> np.ndarray:
    """Pixels where the Mitsuba Phong ground truth's specular term exceeds the threshold.

    Read from the independent ground truth (cached on disk), not from a method under test,
    so no method defines where it is judged. A scene without shaded objects has no highlight.
    """
    from aaeval.metrics.specular import highlight_mask

    if not _has_shaded(scene):
        return np.zeros((scene.height, scene.width), bool)
    from aaeval.groundtruth import groundtruth_phong

    _, specular, _ = groundtruth_phong(scene, spp=HIGHLIGHT_SPP)
    return highlight_mask(specular, threshold=HIGHLIGHT_THRESHOLD)


def _interior(scene) -> np.ndarray:
    """Pixels some polygon covers, at least :data:`INTERIOR_MARGIN` pixels inside the outline
    of everything covered (exact coverage: the exact renderer's image differs from the
    background there; a polygon of the background's colour counts as uncovered)."""
    from scipy.ndimage import binary_erosion

    from aaeval.catmull import render_flat
    from aaeval.scenes.shaded import has_shaded

    if has_shaded(scene):
        from aaeval.renderers import render

        image = render(scene, "catmull")
    else:
        # the flat kernel straight away: the same bits as the "catmull" method on a flat
        # scene, without parsing a spec inside the sweep (specs are parsed where a config is read)
        image = render_flat(scene)
    covered = np.any(np.abs(image - np.asarray(scene.background, dtype=float)) > 1e-9, axis=2)
    size = 2 * INTERIOR_MARGIN + 1
    return binary_erosion(covered, structure=np.ones((size, size), bool))


register_mask("edge", _edge, "pixels a visible edge crosses (exact coverage, aaeval.metrics.edges.edge_mask)")
register_mask("interior", _interior,
              f"pixels covered by the scene, {INTERIOR_MARGIN} px or more inside the outline of what is covered")
def _has_shaded(scene) -> bool:
    from aaeval.scenes.shaded import has_shaded

    return has_shaded(scene)


register_mask("highlight", _highlight,
              f"pixels where the Mitsuba Phong ground truth ({HIGHLIGHT_SPP} spp) specular term > {HIGHLIGHT_THRESHOLD}",
              applies=_has_shaded)
