"""Image metrics, one plain function per metric: ``metric(image_true, image_test, *, ...)``.

Every metric checks its inputs first: two finite (H, W, 3) linear RGB images of one shape
(or, for temporal metrics, two (F, H, W, 3) frame sequences). Look metrics up by name in
:data:`IMAGE_METRICS` / :data:`TEMPORAL_METRICS` and call them with
:func:`compute_metric` / :func:`compute_temporal_metric`.
"""

from aaeval.metrics.colour_difference import ciede2000_map, ciede2000_mean, ciede2000_p95, linear_rgb_to_lab
from aaeval.metrics.edges import edge_mask, edge_rmse
from aaeval.metrics.image import psnr, rmse, ssim
from aaeval.metrics.perceptual import flip
from aaeval.metrics.registry import (
    IMAGE_METRICS,
    TEMPORAL_METRICS,
    MetricError,
    compute_metric,
    compute_temporal_metric,
)
from aaeval.metrics.temporal import flicker, intensity_sum, sum_variation
from aaeval.metrics.specular import detection_precision_recall, highlight_energy_bias, highlight_energy_flicker, highlight_flicker, highlight_mask, highlight_profile_flicker, highlight_rmse  # noqa: E501,F401

__all__ = [
    "IMAGE_METRICS",
    "TEMPORAL_METRICS",
    "MetricError",
    "compute_metric",
    "compute_temporal_metric",
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
    "intensity_sum",
    "sum_variation",
]
