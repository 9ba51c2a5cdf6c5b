"""Input checks shared by the metrics: every metric checks its inputs before any work."""

from __future__ import annotations

import numpy as np

__all__ = ["check_image_pair", "check_frames_pair", "check_positive"]


def check_image_pair(image_true, image_test) -> tuple[np.ndarray, np.ndarray]:
    """Both images as float64 arrays, after checking they are finite (H, W, 3) of one shape."""
    image_true = np.asarray(image_true, dtype=np.float64)
    image_test = np.asarray(image_test, dtype=np.float64)
    if image_true.shape != image_test.shape:
        raise ValueError(f"images differ in shape: {image_true.shape} (true) vs {image_test.shape} (test)")
    if image_true.ndim != 3 or image_true.shape[2] != 3:
        raise ValueError(f"expected (H, W, 3) RGB images, got shape {image_true.shape}")
    for label, image in (("true", image_true), ("test", image_test)):
        if not np.isfinite(image).all():
            raise ValueError(f"the {label} image has non-finite values (NaN or inf)")
    return image_true, image_test


def check_frames_pair(frames_true, frames_test) -> tuple[np.ndarray, np.ndarray]:
    """Both frame sequences as float64 (F, H, W, 3) arrays of one shape, finite, F >= 1."""
    frames_true = np.asarray(frames_true, dtype=np.float64)
    frames_test = np.asarray(frames_test, dtype=np.float64)
    if frames_true.shape != frames_test.shape:
        raise ValueError(
            f"frame sequences differ in shape: {frames_true.shape} (true) vs {frames_test.shape} (test)"
        )
    if frames_true.ndim != 4 or frames_true.shape[3] != 3 or frames_true.shape[0] == 0:
        raise ValueError(f"expected a non-empty (F, H, W, 3) sequence of RGB frames, got shape {frames_true.shape}")
    for label, frames in (("true", frames_true), ("test", frames_test)):
        if not np.isfinite(frames).all():
            raise ValueError(f"the {label} frames have non-finite values (NaN or inf)")
    return frames_true, frames_test


def check_positive(name: str, value) -> None:
    """Refuse an option that must be a positive number (NaN included)."""
    if not value > 0:
        raise ValueError(f"{name} must be positive, got {value!r}")
