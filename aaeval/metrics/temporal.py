"""Metrics over the frames of an animation."""

from __future__ import annotations

import numpy as np

from aaeval.metrics._checks import check_frames_pair

__all__ = ["intensity_sum", "sum_variation", "intensity_sum_variation", "flicker"]


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


def intensity_sum_variation(frames_true, frames_test) -> float:
    """Relative variation of the test's intensity sums over the frames (the reference is unused).

    ``sum_variation([intensity_sum(f) for f in frames_test])``: the registry's temporal
    ``sum_variation``, with the signature every temporal metric shares.

    Parameters
    ----------
    frames_true : array_like, shape (F, H, W, 3)
        Reference frames; only checked against the test frames' shape.
    frames_test : array_like, shape (F, H, W, 3)
        The test method's frames.

    Returns
    -------
    variation : float
        ``(max - min) / mean`` of the per-frame sums; 0 for a single frame.
    """
    frames_true, frames_test = check_frames_pair(frames_true, frames_test)
    return sum_variation(frames_test.sum(axis=(1, 2, 3)))


def flicker(frames_true, frames_test) -> float:
    """Temporal flicker of a method's error: how much it changes from frame to frame.

    The error ``frames_test - frames_true`` is taken per pixel and channel; its standard
    deviation across frames (population, ``ddof=0``) is computed for every pixel and
    channel, and the root mean square of those over pixels and channels is returned. An
    error that stays put (however large) gives 0; an error alternating between ``+d``
    and ``-d`` on every pixel gives ``d``.

    Parameters
    ----------
    frames_true : array_like, shape (F, H, W, 3)
        Reference frames of the animation (linear RGB).
    frames_test : array_like, shape (F, H, W, 3)
        The test method's frames, same shape.

    Returns
    -------
    flicker : float
        ``sqrt(mean over pixels and channels of var over frames of the error)``.
    """
    frames_true, frames_test = check_frames_pair(frames_true, frames_test)
    error = frames_test - frames_true
    return float(np.sqrt(np.mean(np.var(error, axis=0))))
