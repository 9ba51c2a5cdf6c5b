"""Input checks shared by the metrics: every metric checks its inputs before any work."""

from __future__ import annotations

import numpy as np

__all__ = ["check_finite_pair", "check_image_pair", "check_frames_pair", "check_stack_pair", "check_frame_mask", "check_positive"]


def check_finite_pair(true, test, what: str) -> tuple[np.ndarray, np.ndarray]:
    """Both as float64 arrays of one shape with finite values; ``what`` names them in errors."""
    true = np.asarray(true, dtype=np.float64)
    test = np.asarray(test, dtype=np.float64)
    if true.shape != test.shape:
        raise ValueError(f"{what} differ in shape: {true.shape} (true) vs {test.shape} (test)")
    for label, values in (("true", true), ("test", test)):
        if not np.isfinite(values).all():
            raise ValueError(f"the {label} {what} have non-finite values (NaN or inf)")
    return true, test


def check_image_pair(image_true, image_test) -> tuple[np.ndarray, np.ndarray]:
    """Both images as float64 arrays, after checking they are finite (H, W, 3) of one shape."""
    image_true, image_test = check_finite_pair(image_true, image_test, "images")
    if image_true.ndim != 3 or image_true.shape[2] != 3:
        raise ValueError(f"expected (H, W, 3) RGB images, got shape {image_true.shape}")
    return image_true, image_test


def check_frames_pair(frames_true, frames_test) -> tuple[np.ndarray, np.ndarray]:
    """Both frame sequences as float64 (F, H, W, 3) arrays of one shape, finite, F >= 1."""
    frames_true, frames_test = check_finite_pair(frames_true, frames_test, "frames")
    if frames_true.ndim != 4 or frames_true.shape[3] != 3 or frames_true.shape[0] == 0:
        raise ValueError(f"expected a non-empty (F, H, W, 3) sequence of RGB frames, got shape {frames_true.shape}")
    return frames_true, frames_test


def check_stack_pair(frames_true, frames_test) -> tuple[np.ndarray, np.ndarray]:
    """Both stacks as float64 (T, H, W[, C]) arrays of one shape, finite, T >= 2."""
    frames_true, frames_test = check_finite_pair(frames_true, frames_test, "frames")
    if frames_true.ndim < 3 or frames_true.shape[0] < 2:
        raise ValueError(f"need a stack of at least 2 frames (T, H, W[, C]), got shape {frames_true.shape}")
    return frames_true, frames_test


def check_frame_mask(mask, frames_shape, *, per_frame: str) -> np.ndarray:
    """``mask`` as one (H, W) bool mask for frames of ``frames_shape``; a per-frame (T, H, W)
    mask is reduced to the pixels masked in ``per_frame`` ("every" or "any") frame."""
    mask = np.asarray(mask, dtype=bool)
    if mask.ndim == 3:
        mask = mask.all(axis=0) if per_frame == "every" else mask.any(axis=0)
    if mask.shape != tuple(frames_shape[1:3]):
        raise ValueError(f"mask shape {mask.shape} does not match frames of shape {tuple(frames_shape[1:3])}")
    return mask


def check_positive(name: str, value) -> None:
    """Refuse an option that must be a positive number (NaN included)."""
    if not value > 0:
        raise ValueError(f"{name} must be positive, got {value!r}")
