"""Image metrics, one plain function per metric: ``metric(image_true, image_test, *, ...)``.

Every metric checks its inputs first: two finite (H, W, 3) linear RGB images of one shape
(or, for temporal metrics, two (F, H, W, 3) frame sequences). :data:`METRICS` is the
registry: each metric with its title, format, direction and what it needs
(:func:`register_metric`); :data:`IMAGE_METRICS` / :data:`TEMPORAL_METRICS` are its
functions by kind, called with :func:`compute_metric` / :func:`compute_temporal_metric`.
Masks for the masked metrics are built by :mod:`aaeval.metrics.masks`. The names are
loaded on first use (PEP 562): :mod:`aaeval.metrics.info` (what a metric is, without its
function) is importable without loading any metric, mask or renderer.
"""

from aaeval._lazy import lazy_names

_EXPORTS = {
    "colour_difference": ("ciede2000_map", "ciede2000_mean", "ciede2000_p95", "linear_rgb_to_lab"),
    "edges": ("edge_mask", "edge_rmse"),
    "image": ("psnr", "rmse", "ssim"),
    "masks": ("MASKS", "build_mask"),
    "perceptual": ("flip",),
    "info": ("format_value",),
    "registry": ("IMAGE_METRICS", "METRICS", "TEMPORAL_METRICS", "Metric", "MetricError", "check_metric_names",
                 "compute_metric", "compute_temporal_metric", "default_metrics", "get_metric", "register_metric"),
    "specular": ("detection_precision_recall", "highlight_bias", "highlight_energy_bias", "highlight_energy_flicker",
                 "highlight_flicker", "highlight_mask", "highlight_profile_flicker", "highlight_rmse"),
    "temporal": ("flicker", "image_flicker", "intensity_sum", "relative_variation", "sum_bias", "sum_variation",
                 "temporal_bias"),
    "video": ("cvvdp",),
}
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = [
    "METRICS",
    "IMAGE_METRICS",
    "TEMPORAL_METRICS",
    "MASKS",
    "Metric",
    "MetricError",
    "build_mask",
    "check_metric_names",
    "compute_metric",
    "compute_temporal_metric",
    "default_metrics",
    "format_value",
    "get_metric",
    "register_metric",
    "rmse",
    "psnr",
    "ssim",
    "ciede2000_map",
    "ciede2000_mean",
    "ciede2000_p95",
    "linear_rgb_to_lab",
    "flip",
    "edge_mask",
    "edge_rmse",
    "flicker",
    "temporal_bias",
    "image_flicker",
    "intensity_sum",
    "relative_variation",
    "sum_variation",
    "sum_bias",
    "highlight_mask",
    "highlight_rmse",
    "highlight_energy_bias",
    "highlight_bias",
    "highlight_flicker",
    "highlight_energy_flicker",
    "highlight_profile_flicker",
    "detection_precision_recall",
    "cvvdp",
]


__getattr__, __dir__ = lazy_names(__name__, _MODULE_OF)
