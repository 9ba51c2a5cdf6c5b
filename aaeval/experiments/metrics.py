"""The sweep's view of the metrics: per-frame metrics through the registry's dispatcher
``aaeval.metrics.compute_metric``, and the temporal metrics over a cell series.

Per-frame metrics need only the two images, except the ones that read the scene (an edge
mask); :func:`frame_metric` builds that context. Temporal metrics need every frame of a
(scene, method) series and are computed when the results table is built.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

__all__ = ["TEMPORAL_METRICS", "check_metric_names", "frame_metric", "temporal_metric", "registered_metrics"]

TEMPORAL_METRICS = ("sum_variation", "flicker")

# Metrics that need more than two images, and how to build what they need from the scene.
_SCENE_CONTEXT = {"edge_rmse": "mask"}


def _registry():
    try:
        from aaeval.metrics import METRICS, compute_metric  # the shared registry, once merged
    except ImportError:
        return None, None
    return METRICS, compute_metric


def registered_metrics() -> set[str]:
    metrics, _ = _registry()
    if metrics is None:
        return set(_FALLBACK)
    return set(metrics)


def check_metric_names(names: Sequence[str], *, temporal: bool) -> None:
    known = set(TEMPORAL_METRICS) if temporal else registered_metrics() - set(TEMPORAL_METRICS)
    unknown = [n for n in names if n not in known]
    if unknown:
        raise ValueError(f"unknown metric(s) {unknown}; available: {', '.join(sorted(known))}")


def frame_metric(name: str, image_true: np.ndarray, image_test: np.ndarray, scene=None) -> float:
    """One per-frame metric of ``image_test`` against ``image_true``."""
    _, compute = _registry()
    if compute is None:
        return float(_FALLBACK[name](image_true, image_test))
    context = {}
    if _SCENE_CONTEXT.get(name) == "mask":
        from aaeval.metrics import edge_mask

        context["mask"] = edge_mask(scene)
    return float(compute(name, image_true, image_test, **context))


def temporal_metric(name: str, frames_true: Sequence[np.ndarray], frames_test: Sequence[np.ndarray]) -> float:
    """A metric over the frames of one animation, in frame order."""
    if name == "sum_variation":
        from aaeval.metrics import intensity_sum, sum_variation

        return sum_variation([intensity_sum(f) for f in frames_test])
    if name == "flicker":
        return flicker(frames_true, frames_test)
    raise ValueError(f"unknown temporal metric {name!r}; available: {', '.join(TEMPORAL_METRICS)}")


def flicker(frames_true: Sequence[np.ndarray], frames_test: Sequence[np.ndarray]) -> float:
    """RMS frame-to-frame change of the error ``test - true``.

    A method that is wrong the same way in every frame does not flicker; one whose error
    jumps as edges cross sample positions does. Zero for a single frame.
    """
    if len(frames_true) != len(frames_test):
        raise ValueError(f"{len(frames_true)} reference frames but {len(frames_test)} test frames")
    if len(frames_test) < 2:
        return 0.0
    err = np.stack([np.asarray(b, float) - np.asarray(a, float) for a, b in zip(frames_true, frames_test)])
    return float(np.sqrt(np.mean(np.diff(err, axis=0) ** 2)))


def _rmse(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        raise ValueError(f"images differ in shape: {a.shape} vs {b.shape}")
    return np.sqrt(np.mean((a - b) ** 2))


# Used only until the shared metrics registry is merged.
_FALLBACK = {"rmse": _rmse}
