"""Image metrics, one plain function per metric: ``metric(image_true, image_test, *, ...)``."""

from aaeval.metrics.temporal import intensity_sum, sum_variation
from aaeval.metrics.specular import detection_precision_recall, highlight_energy_bias, highlight_energy_flicker, highlight_flicker, highlight_mask, highlight_profile_flicker, highlight_rmse  # noqa: E501,F401

__all__ = ["intensity_sum", "sum_variation"]
