"""The sweep's view of the metrics registry (``aaeval.metrics``): which names a config may
use, and how to call them with the context they need.

Per-frame metrics go through ``compute_metric(name, image_true, image_test, **context)``
with the scene's edge mask in the context when ``edge_rmse`` asks for it. Temporal
metrics need every frame of a (scene, method) series and are computed when the results
table is built: the registry's ``TEMPORAL_METRICS`` through ``compute_temporal_metric``,
plus ``sum_variation`` of the intensity sums (Catmull's invariance under translation).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from aaeval.metrics import (
    IMAGE_METRICS,
    TEMPORAL_METRICS,
    compute_metric,
    compute_temporal_metric,
    edge_mask,
    intensity_sum,
    sum_variation,
)

__all__ = ["check_metric_names", "frame_metric", "temporal_metric", "image_metric_names", "temporal_metric_names"]

# Metrics that read the scene, and the context entry they need.
_SCENE_CONTEXT = {"edge_rmse": ("mask", edge_mask)}


def image_metric_names() -> set[str]:
    return set(IMAGE_METRICS)


def temporal_metric_names() -> set[str]:
    return {"sum_variation", *TEMPORAL_METRICS}


def check_metric_names(names: Sequence[str], *, temporal: bool) -> None:
    known = temporal_metric_names() if temporal else image_metric_names()
    unknown = [n for n in names if n not in known]
    if unknown:
        raise ValueError(f"unknown metric(s) {unknown}; available: {', '.join(sorted(known))}")


def frame_metric(name: str, image_true: np.ndarray, image_test: np.ndarray, scene=None) -> float:
    """One per-frame metric of ``image_test`` against ``image_true`` (``scene`` at that frame)."""
    context = {}
    if name in _SCENE_CONTEXT:
        key, build = _SCENE_CONTEXT[name]
        context[key] = build(scene)
    return float(compute_metric(name, image_true, image_test, **context))


def temporal_metric(name: str, frames_true: Sequence[np.ndarray], frames_test: Sequence[np.ndarray]) -> float:
    """A metric over the frames of one animation, in frame order."""
    if name == "sum_variation":
        return sum_variation([intensity_sum(f) for f in frames_test])
    return float(compute_temporal_metric(name, np.stack(frames_true), np.stack(frames_test)))
