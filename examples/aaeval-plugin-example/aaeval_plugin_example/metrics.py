"""Metric ``max_abs_error``, registered by :func:`register` (entry point group ``aaeval.metrics``)."""

import numpy as np


def max_abs_error(image_true, image_test):
    """Largest absolute difference of any pixel and channel."""
    return float(np.max(np.abs(np.asarray(image_test) - np.asarray(image_true))))


def register():
    from aaeval.metrics.registry import register_metric

    register_metric("max_abs_error", max_abs_error, kind="image", title="max |error|", fmt=".3e",
                    higher_is_better=False)
