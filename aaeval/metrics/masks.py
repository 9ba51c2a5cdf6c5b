"""Masks the masked metrics are computed over, built from the scene by name.

A metric declares the mask it needs by name (``register_metric(..., mask="edge")``); the
measuring engine (:mod:`aaeval.sweeps.measure`) builds it from the scene at the
frame being measured with :func:`build_mask`, once per scene frame, and passes it as the
metric's ``mask`` option. This is the only place that knows how a mask is made.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from aaeval.options import Registry

__all__ = ["MASKS", "Mask", "SOURCES", "register_mask", "build_mask", "HIGHLIGHT_THRESHOLD", "HIGHLIGHT_SPP", "INTERIOR_MARGIN"]

#: A pixel is in the highlight when the ground truth's box-filtered specular term exceeds this.
HIGHLIGHT_THRESHOLD = 0.02
#: Samples per pixel of the Mitsuba Phong ground truth the highlight mask is read from: the
#: specular groups' own ground truth (``mitsuba:spp=4096,seed=0``), so a page has one
#: specular truth and the mask is a cache hit.
HIGHLIGHT_SPP = 4096
#: Pixels this close to the outline of what the scene covers are left out of ``interior``
#: (the widest pixel filter reaches 2 pixels).
INTERIOR_MARGIN = 2


#: What a mask may be read from besides the scene, rendered by the measuring engine
#: (:func:`aaeval.sweeps.measure.mask_source`) and passed in: ``exact``, the exact
#: box-filtered image of the scene (Catmull's area sampling; one shade per visible piece
#: on a shaded scene); ``specular``, the specular term of the Mitsuba Phong ground truth at
#: :data:`HIGHLIGHT_SPP`.
SOURCES = ("exact", "specular")


@dataclass(frozen=True)
class Mask:
    name: str
    build: Callable[..., np.ndarray]  # build(scene_at_frame[, source]) -> bool (H, W)
    summary: str
    applies: Callable[..., bool] = lambda scene: True  # False: the mask is empty on this scene
    source: str | None = None  # a name of SOURCES: build takes that image as its second argument

    def applies_to(self, scene) -> bool:
        return bool(self.applies(scene))


MASKS: Registry = Registry("mask")


def register_mask(name: str, build: Callable[..., np.ndarray] | None = None, summary: str = "",
                  applies: Callable[..., bool] | None = None, source: str | None = None):
    """Register ``build(scene) -> bool (H, W)``: ``register_mask(name, build, summary)`` or
    ``@register_mask(name, summary=...)``; ``applies(scene)`` is False where it is always
    empty; with ``source`` (one of :data:`SOURCES`) ``build(scene, image)`` also gets that
    image of the scene."""
    if source is not None and source not in SOURCES:
        raise ValueError(f"mask {name!r}: source must be one of {', '.join(SOURCES)}, got {source!r}")

    def decorate(func):
        MASKS.add(name, Mask(name, func, summary, applies or (lambda scene: True), source))
        return func

    return decorate if build is None else decorate(build)


def build_mask(name: str, scene, source: np.ndarray | None = None) -> np.ndarray:
    """The mask ``name`` of ``scene`` (at the frame wanted), bool (H, W). A mask read from
    a render (:attr:`Mask.source`) takes that render as ``source``
    (:func:`aaeval.sweeps.measure.scene_mask` renders it); where the mask does not
    apply it is empty and needs none."""
    mask = MASKS.get_entry(name)
    if not mask.applies_to(scene):
        return np.zeros((scene.height, scene.width), bool)
    if mask.source is None:
        found = mask.build(scene)
    elif source is None:
        raise ValueError(f"mask {name!r} is read from the scene's {mask.source} render: pass it as source= "
                         "(aaeval.sweeps.measure.scene_mask renders it)")
    else:
        found = mask.build(scene, source)
    found = np.asarray(found, dtype=bool)
    if found.shape != (scene.height, scene.width):
        raise ValueError(f"mask {name!r} has shape {found.shape}, expected {(scene.height, scene.width)}")
    return found


def _edge(scene) -> np.ndarray:
    from aaeval.metrics.edges import edge_mask

    return edge_mask(scene)


def _highlight(scene, specular: np.ndarray) -> np.ndarray:
    """Pixels where the Mitsuba Phong ground truth's specular term exceeds the threshold.

    Read from the independent ground truth, not from a method under test, so no method
    defines where it is judged. A scene without shaded objects has no highlight.
    """
    from aaeval.metrics.specular import highlight_mask

    return highlight_mask(specular, threshold=HIGHLIGHT_THRESHOLD)


def _interior(scene, exact: np.ndarray) -> np.ndarray:
    """Pixels some polygon covers, at least :data:`INTERIOR_MARGIN` pixels inside the outline
    of everything covered (exact coverage: the exact render differs from the background
    there; a polygon of the background's colour counts as uncovered)."""
    from scipy.ndimage import binary_erosion

    covered = np.any(np.abs(exact - np.asarray(scene.background, dtype=float)) > 1e-9, axis=2)
    size = 2 * INTERIOR_MARGIN + 1
    return binary_erosion(covered, structure=np.ones((size, size), bool))


def _has_shaded(scene) -> bool:
    from aaeval.scenes.shaded import has_shaded

    return has_shaded(scene)


register_mask("edge", _edge, "pixels a visible edge crosses (exact coverage, aaeval.metrics.edges.edge_mask)")
register_mask("interior", _interior,
              f"pixels covered by the scene, {INTERIOR_MARGIN} px or more inside the outline of what is covered",
              source="exact")
register_mask("highlight", _highlight,
              f"pixels where the Mitsuba Phong ground truth ({HIGHLIGHT_SPP} spp) specular term > {HIGHLIGHT_THRESHOLD}",
              applies=_has_shaded, source="specular")
