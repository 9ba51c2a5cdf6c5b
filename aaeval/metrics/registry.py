"""Metrics by name: one mapping per kind and a dispatcher, in colour-science's style
(``colour.difference.DELTA_E_METHODS`` and ``colour.delta_E``).

The names are stable: sweeps and reports address metrics by them.
"""

from __future__ import annotations

import inspect
from typing import Any, Callable, Mapping

from aaeval.metrics.colour_difference import ciede2000_mean, ciede2000_p95
from aaeval.metrics.edges import edge_rmse
from aaeval.metrics.image import psnr, rmse, ssim
from aaeval.metrics.perceptual import flip
from aaeval.metrics.temporal import flicker

__all__ = [
    "IMAGE_METRICS",
    "TEMPORAL_METRICS",
    "MetricError",
    "compute_metric",
    "compute_temporal_metric",
]


class MetricError(ValueError):
    """An unknown metric name, an unknown option, or a required option missing."""


#: Image metrics ``metric(image_true, image_test, **options) -> float`` on (H, W, 3) images.
IMAGE_METRICS: dict[str, Callable[..., float]] = {
    "rmse": rmse,
    "psnr": psnr,
    "ssim": ssim,
    "ciede2000_mean": ciede2000_mean,
    "ciede2000_p95": ciede2000_p95,
    "flip": flip,
    "edge_rmse": edge_rmse,
}

#: Temporal metrics ``metric(frames_true, frames_test, **options) -> float`` on (F, H, W, 3) frames.
TEMPORAL_METRICS: dict[str, Callable[..., float]] = {
    "flicker": flicker,
}


def compute_metric(name: str, image_true, image_test, **context: Any) -> float:
    """Compute the image metric ``name`` of ``image_test`` against ``image_true``.

    Parameters
    ----------
    name : str
        A key of :data:`IMAGE_METRICS`.
    image_true, image_test : ndarray, shape (H, W, 3)
        Reference and test images.
    **context
        Options for the metrics. Each metric receives only the ones it accepts (``mask``
        reaches ``edge_rmse`` alone, ``data_range`` reaches ``psnr`` and ``ssim``), so one
        context can serve every metric; an option no metric accepts is an error.

    Returns
    -------
    value : float
    """
    return _dispatch(IMAGE_METRICS, "image", name, image_true, image_test, context)


def compute_temporal_metric(name: str, frames_true, frames_test, **context: Any) -> float:
    """Compute the temporal metric ``name`` (a key of :data:`TEMPORAL_METRICS`) over frames.

    Options are passed as in :func:`compute_metric`.
    """
    return _dispatch(TEMPORAL_METRICS, "temporal", name, frames_true, frames_test, context)


def _keyword_options(func: Callable) -> dict[str, inspect.Parameter]:
    params = inspect.signature(func).parameters.values()
    return {p.name: p for p in params if p.kind is inspect.Parameter.KEYWORD_ONLY}


def _dispatch(registry: Mapping[str, Callable], kind: str, name: str, true, test, context) -> float:
    if name not in registry:
        raise MetricError(f"unknown {kind} metric {name!r}; available: {', '.join(registry)}")
    known = set().union(*(_keyword_options(f) for f in registry.values()))
    unknown = sorted(set(context) - known)
    if unknown:
        raise MetricError(
            f"unknown {kind} metric option(s) {unknown}; options: {', '.join(sorted(known)) or 'none'}"
        )
    accepted = _keyword_options(registry[name])
    missing = sorted(k for k, p in accepted.items() if p.default is inspect.Parameter.empty and k not in context)
    if missing:
        raise MetricError(f"{kind} metric {name!r} needs option(s) {missing}")
    return registry[name](true, test, **{k: v for k, v in context.items() if k in accepted})
