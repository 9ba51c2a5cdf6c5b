"""Metrics over the frames of an animation."""

from __future__ import annotations

import numpy as np

__all__ = ["intensity_sum", "sum_variation"]


def intensity_sum(image: np.ndarray) -> float:
    """Sum of every pixel's intensity (all channels) of an (H, W, 3) linear image.

    Area sampling keeps it constant when the scene translates inside the frame
    (Catmull 1978); point sampling does not.
    """
    image = np.asarray(image, dtype=np.float64)
    if image.ndim != 3:
        raise ValueError(f"expected an (H, W, C) image, got shape {image.shape}")
    return float(image.sum())


def sum_variation(sums) -> float:
    """Relative variation ``(max - min) / mean`` of per-frame intensity sums."""
    sums = np.asarray(sums, dtype=np.float64)
    if sums.ndim != 1 or sums.size == 0:
        raise ValueError("expected a non-empty 1-D sequence of sums")
    mean = sums.mean()
    if mean == 0.0:
        return 0.0 if np.ptp(sums) == 0.0 else float("inf")
    return float(np.ptp(sums) / abs(mean))
