"""Metrics over the frames of an animation."""

from __future__ import annotations

import numpy as np

from aaeval.metrics._checks import check_frame_mask, check_frames_pair

__all__ = ["intensity_sum", "relative_variation", "sum_variation", "sum_bias", "temporal_bias", "flicker",
           "image_flicker"]


def intensity_sum(image: np.ndarray) -> float:
    """Sum of every pixel's intensity (all channels) of an (H, W, 3) linear image.

    Area sampling keeps it constant when the scene translates inside the frame
    (Catmull 1978); point sampling does not.
    """
    image = np.asarray(image, dtype=np.float64)
    if image.ndim != 3:
        raise ValueError(f"expected an (H, W, C) image, got shape {image.shape}")
    return float(image.sum())


def relative_variation(sums) -> float:
    """Relative variation ``(max - min) / mean`` of per-frame intensity sums."""
    sums = np.asarray(sums, dtype=np.float64)
    if sums.ndim != 1 or sums.size == 0:
        raise ValueError("expected a non-empty 1-D sequence of sums")
    mean = sums.mean()
    if mean == 0.0:
        return 0.0 if np.ptp(sums) == 0.0 else float("inf")
    return float(np.ptp(sums) / abs(mean))


def sum_variation(frames_true, frames_test) -> float:
    """Relative variation of the test's intensity sums over the frames (the reference is unused).

    ``relative_variation([intensity_sum(f) for f in frames_test])``, with the signature
    every temporal metric shares (registered as ``sum_variation``).

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
    return relative_variation(frames_test.sum(axis=(1, 2, 3)))


def sum_bias(frames_true, frames_test, *, exact) -> float:
    """Bias of the test's intensity sum against the exact sum, in the typical frame.

    ``median over frames of sum(test_k) / sum(exact_k) - 1``. :func:`sum_variation` says
    how much a method's sum moves; this says where it sits: a regular 4 x 4 grid on a
    fence of 0.3 px bars, one per pixel, sees one sample column per bar in four frames of
    five (sum 90 against the exact 108: -16.7%) and two in the fifth (+66.7%). The median
    is that typical frame; the mean over evenly spread phases would be 0 for every sampler
    whose samples lie evenly in the pixel (their average over phases is the box filter), so
    it would only measure how evenly the frames happened to fall.

    Parameters
    ----------
    frames_true : array_like, shape (F, H, W, 3)
        Reference frames; only checked against the test frames' shape (a sampled reference
        has noise; the exact sums below have none).
    frames_test : array_like, shape (F, H, W, 3)
        The test method's frames.
    exact : array_like, shape (F, H, W, 3)
        The exact box-filtered frames (Catmull's area sampling) whose sums are the truth.

    Returns
    -------
    bias : float
        Signed relative bias (-0.167 is 16.7% too dark); NaN where an exact sum is 0.
    """
    frames_true, frames_test = check_frames_pair(frames_true, frames_test)
    _, exact = check_frames_pair(frames_true, exact)
    truth = exact.sum(axis=(1, 2, 3))
    if np.any(truth == 0.0):
        return float("nan")
    return float(np.median(frames_test.sum(axis=(1, 2, 3)) / truth - 1.0))


def temporal_bias(frames_true, frames_test) -> float:
    """Bias of a method over an animation: the part of its error that stays put.

    The error ``frames_test - frames_true`` is averaged over the frames for every pixel and
    channel; the root mean square of that time-average over pixels and channels is
    returned. With :func:`flicker` (what is left) it splits the error of the whole
    animation: ``temporal_bias**2 + flicker**2`` is the mean square error over every frame.

    Parameters
    ----------
    frames_true, frames_test : array_like, shape (F, H, W, 3)
        The reference's and the test method's frames of the animation (linear RGB).

    Returns
    -------
    bias : float
        ``sqrt(mean over pixels and channels of (mean over frames of the error)**2)``.
    """
    return float(np.sqrt(np.mean(np.mean(_errors(frames_true, frames_test), axis=0) ** 2)))


def flicker(frames_true, frames_test) -> float:
    """Temporal flicker of a method's error: what is left of it after its time-average.

    The error ``frames_test - frames_true`` is taken per pixel and channel; its standard
    deviation across frames (population, ``ddof=0``) is computed for every pixel and
    channel, and the root mean square of those over pixels and channels is returned. An
    error that stays put (however large) gives 0 (it is :func:`temporal_bias`); an error
    alternating between ``+d`` and ``-d`` on every pixel gives ``d``.

    Parameters
    ----------
    frames_true, frames_test : array_like, shape (F, H, W, 3)
        The reference's and the test method's frames of the animation (linear RGB).

    Returns
    -------
    flicker : float
        ``sqrt(mean over pixels and channels of var over frames of the error)``; 0 for one frame.
    """
    return float(np.sqrt(np.mean(np.var(_errors(frames_true, frames_test), axis=0))))


def image_flicker(frames_true, frames_test, *, mask) -> float:
    """How much the test image itself changes over the frames inside ``mask`` (no reference).

    The RMS over the masked pixels and channels of each pixel's standard deviation across
    the frames (population). Inside a region where an ideal low-pass image is constant (the
    interior of a picket fence whose bars repeat at or above the Nyquist rate), every
    temporal change is aliasing that the pixel filter let through.

    Parameters
    ----------
    frames_true : array_like, shape (F, H, W, 3)
        Reference frames; only checked against the test frames' shape.
    frames_test : array_like, shape (F, H, W, 3)
        The test method's frames.
    mask : array_like of bool, shape (H, W) or (F, H, W)
        Pixels to measure; a per-frame mask is reduced to the pixels masked in every frame.

    Returns
    -------
    flicker : float
        NaN when the mask is empty.
    """
    frames_true, frames_test = check_frames_pair(frames_true, frames_test)
    mask = check_frame_mask(mask, frames_test.shape, per_frame="every")
    if not mask.any():
        return float("nan")
    return float(np.sqrt(np.mean(np.var(frames_test, axis=0)[mask])))


def _errors(frames_true, frames_test) -> np.ndarray:
    """The test's error on every frame and pixel channel, after the checks."""
    frames_true, frames_test = check_frames_pair(frames_true, frames_test)
    return frames_test - frames_true
