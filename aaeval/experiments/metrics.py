"""The sweep's view of the metrics registry (``aaeval.metrics``): which names exist, and
how to call them with the context they need.

Per-frame metrics go through ``compute_metric(name, image_true, image_test, **context)``;
the ones that read the scene (an edge mask) get it built here. Temporal metrics need every
frame of a (scene, method) series and go through ``compute_temporal_metric`` when the
results table is built.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

__all__ = ["check_metric_names", "frame_metric", "temporal_metric", "image_metric_names", "temporal_metric_names"]

# Metrics that need more than two images, and what they need from the scene.
_SCENE_CONTEXT = {"edge_rmse": "mask"}


def _registry():
    try:  # the shared registry; a checkout without it still runs sweeps with rmse
        from aaeval.metrics import IMAGE_METRICS, TEMPORAL_METRICS, compute_metric, compute_temporal_metric
    except ImportError:
        return None
    return IMAGE_METRICS, TEMPORAL_METRICS, compute_metric, compute_temporal_metric


def image_metric_names() -> set[str]:
    reg = _registry()
    return set(reg[0]) if reg else set(_FALLBACK_IMAGE)


def temporal_metric_names() -> set[str]:
    reg = _registry()
    return set(reg[1]) if reg else set(_FALLBACK_TEMPORAL)


def check_metric_names(names: Sequence[str], *, temporal: bool) -> None:
    known = temporal_metric_names() if temporal else image_metric_names()
    unknown = [n for n in names if n not in known]
    if unknown:
        raise ValueError(f"unknown metric(s) {unknown}; available: {', '.join(sorted(known))}")


def frame_metric(name: str, image_true: np.ndarray, image_test: np.ndarray, scene=None) -> float:
    """One per-frame metric of ``image_test`` against ``image_true`` (``scene`` at that frame)."""
    reg = _registry()
    if reg is None:
        return float(_FALLBACK_IMAGE[name](image_true, image_test))
    context = {}
    if _SCENE_CONTEXT.get(name) == "mask":
        from aaeval.metrics import edge_mask

        context["mask"] = edge_mask(scene)
    return float(reg[2](name, image_true, image_test, **context))


def temporal_metric(name: str, frames_true: Sequence[np.ndarray], frames_test: Sequence[np.ndarray]) -> float:
    """A metric over the frames of one animation, in frame order."""
    reg = _registry()
    true, test = np.stack(frames_true), np.stack(frames_test)
    if reg is None:
        return float(_FALLBACK_TEMPORAL[name](true, test))
    return float(reg[3](name, true, test))


def _rmse(a, b):
    return np.sqrt(np.mean((np.asarray(a, float) - np.asarray(b, float)) ** 2))


def _sum_variation(true, test):
    from aaeval.metrics import intensity_sum, sum_variation

    return sum_variation([intensity_sum(f) for f in test])


# Used only where the shared metrics registry is missing.
_FALLBACK_IMAGE = {"rmse": _rmse}
_FALLBACK_TEMPORAL = {"sum_variation": _sum_variation}
