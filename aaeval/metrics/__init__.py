"""Image metrics, one plain function per metric: ``metric(image_true, image_test, *, ...)``."""

from aaeval.metrics.temporal import intensity_sum, sum_variation

__all__ = ["intensity_sum", "sum_variation"]
