"""Highlight metrics for specular anti-aliasing (Amanatides 1992 experiments).

Images are (H, W) specular-only or (H, W, 3) linear RGB; animations are sequences of
them, frame first. Masks select the highlight: :func:`highlight_mask` marks the pixels
where the ground truth's specular term is significant.
"""

from __future__ import annotations

import numpy as np

from aaeval.metrics.image import masked_rmse

__all__ = [
    "highlight_mask",
    "highlight_rmse",
    "highlight_energy_bias",
    "highlight_flicker",
    "highlight_profile_flicker",
    "highlight_bias",
    "highlight_energy_flicker",
    "detection_precision_recall",
]


def highlight_mask(specular_true, *, threshold: float = 0.02) -> np.ndarray:
    """Pixels where the reference specular term exceeds ``threshold``.

    Parameters
    ----------
    specular_true : ndarray, shape (..., H, W)
        Box-filtered specular term of the reference (one frame or a stack of frames).
    threshold : float, optional
        Absolute linear intensity; default 0.02 (2 % of a unit highlight).

    Returns
    -------
    mask : ndarray of bool, same shape
    """
    specular_true = np.asarray(specular_true, dtype=np.float64)
    if threshold < 0 or not np.isfinite(threshold):
        raise ValueError(f"threshold must be a finite number >= 0, got {threshold!r}")
    return specular_true > threshold


def highlight_rmse(image_true, image_test, *, mask) -> float:
    """Root-mean-square error over the masked pixels (every channel).

    Parameters
    ----------
    image_true, image_test : ndarray, shape (H, W) or (H, W, C)
        Reference and test image (or stacks (T, H, W[, C]) with a mask of shape (T, H, W)).
    mask : ndarray of bool
        Pixels to measure, shape of the images without the channel axis.

    Returns
    -------
    rmse : float
        NaN when the mask is empty.
    """
    image_true, image_test, mask = _checked(image_true, image_test, mask)
    return masked_rmse(image_true, image_test, mask)


def highlight_energy_bias(image_true, image_test, *, mask) -> float:
    """Relative energy of the test against the reference inside the mask.

    ``sum(test[mask]) / sum(true[mask]) - 1``: negative when the highlight is dimmer than
    the reference, positive when brighter. Pass specular-only images to measure the
    highlight alone.

    Parameters
    ----------
    image_true, image_test : ndarray
        As in :func:`highlight_rmse`.
    mask : ndarray of bool

    Returns
    -------
    bias : float
        NaN when the reference has no energy in the mask.
    """
    image_true, image_test, mask = _checked(image_true, image_test, mask)
    total = image_true[mask].sum()
    if total == 0:
        return float("nan")
    return float(image_test[mask].sum() / total - 1.0)


def highlight_flicker(frames_true, frames_test, *, mask) -> float:
    """Temporal error: how much the test's frame-to-frame change departs from the truth's.

    With ``D_t = frame_{t+1} - frame_t``, the RMS over masked pixels, channels and frame
    pairs of ``D_t(test) - D_t(true)``. A highlight that moves as the true one does scores
    0, even if it is biased by a steady amount; one that pops or breaks up between frames
    scores high — and so does one that stays still while the true highlight moves
    (over-smoothing shows up here too).

    Parameters
    ----------
    frames_true, frames_test : ndarray, shape (T, H, W) or (T, H, W, C), T >= 2
    mask : ndarray of bool, shape (H, W) or (T, H, W)
        Pixels to measure; a per-frame mask is reduced to the pixels masked in any frame.

    Returns
    -------
    flicker : float
        NaN when the mask is empty.
    """
    frames_true, frames_test = _frames(frames_true, frames_test)
    mask = _still_mask(mask, frames_true.shape)
    if not mask.any():
        return float("nan")
    change = np.diff(frames_test - frames_true, axis=0)[:, mask]
    return float(np.sqrt(np.mean(change**2)))


def highlight_profile_flicker(frames_true, frames_test, *, mask, axis: int = 1, margin: int = 4) -> float:
    """Flicker of the highlight's cross-section energy, relative to the truth's.

    Sums the masked pixels along ``axis`` (1: along rows, for a highlight running up and
    down the image) into a profile per frame. The box-filtered truth keeps each
    cross-section's energy nearly constant as the highlight drifts sideways by fractions
    of a pixel; a highlight that breaks up does not. Returns the RMS over profile
    positions of the temporal standard deviation of ``profile_test - profile_true``,
    divided by the mean true profile.

    Parameters
    ----------
    frames_true, frames_test : ndarray, shape (T, H, W) (specular term) or (T, H, W, C)
    mask : ndarray of bool, shape (H, W)
        The region holding one highlight line.
    axis : {0, 1}, optional
        Image axis summed over: 1 sums each row (default), 0 each column.
    margin : int, optional
        Pixels the mask is widened by along ``axis``, so that energy a steady blur spreads
        just outside the highlight still counts in its cross-section (a 1 px Gaussian,
        truncated at 4 sigma, needs 4).

    Returns
    -------
    flicker : float
        Relative; NaN when the truth has no energy in the region.
    """
    frames_true, frames_test = _frames(frames_true, frames_test)
    mask = _still_mask(mask, frames_true.shape)
    if axis not in (0, 1):
        raise ValueError(f"axis must be 0 (columns) or 1 (rows), got {axis!r}")
    if margin > 0:
        from scipy import ndimage  # here, not at the top: every command line loads this module, few dilate

        reach = np.zeros((1, 2 * margin + 1) if axis == 1 else (2 * margin + 1, 1), dtype=bool)
        reach[...] = True
        mask = ndimage.binary_dilation(mask, structure=reach)
    weight = mask.astype(np.float64)
    if frames_true.ndim == 4:
        weight = weight[..., None]

    def profile(frames):
        p = (frames * weight).sum(axis=axis + 1)
        return p.sum(axis=-1) if p.ndim == 3 else p

    true, test = profile(frames_true), profile(frames_test)
    lines = true.mean(axis=0) > 0
    if not lines.any():
        return float("nan")
    spread = (test - true)[:, lines].std(axis=0)
    return float(np.sqrt(np.mean(spread**2)) / true[:, lines].mean())


def _energy_ratios(frames_true, frames_test, mask) -> np.ndarray:
    frames_true, frames_test = _frames(frames_true, frames_test)
    mask = np.broadcast_to(np.asarray(mask, dtype=bool), frames_true.shape[:3])
    return np.array([highlight_energy_bias(t, s, mask=m) + 1.0 for t, s, m in zip(frames_true, frames_test, mask)])


def highlight_bias(frames_true, frames_test, *, mask) -> float:
    """Bias of the highlight over an animation: the time-average of its energy error.

    The mean over frames of :func:`highlight_energy_bias` (``sum(test) / sum(true) - 1``
    over each frame's highlight pixels). The highlight's mask moves with it, so a highlight
    that is steadily dimmer or wider than the truth's wherever it goes is bias here, not
    flicker; :func:`highlight_energy_flicker` is what is left (the frame-to-frame change).

    Parameters
    ----------
    frames_true, frames_test : ndarray, shape (T, H, W) or (T, H, W, C), T >= 2
    mask : ndarray of bool, shape (H, W) or (T, H, W)

    Returns
    -------
    bias : float
        Negative: dimmer than the truth on average; NaN when the truth has no energy in a frame's mask.
    """
    return float(np.mean(_energy_ratios(frames_true, frames_test, mask)) - 1.0)


def highlight_energy_flicker(frames_true, frames_test, *, mask) -> float:
    """Standard deviation over frames of the relative highlight energy test / true.

    What is left of the highlight's energy error after its time-average
    (:func:`highlight_bias`): a highlight that pops or breaks up between frames.

    Parameters
    ----------
    frames_true, frames_test : ndarray, shape (T, H, W) or (T, H, W, C), T >= 2
    mask : ndarray of bool, shape (H, W) or (T, H, W)

    Returns
    -------
    flicker : float
        0 for a method whose highlight energy follows the reference's exactly.
    """
    return float(np.std(_energy_ratios(frames_true, frames_test, mask)))


def detection_precision_recall(image_true, image_test, *, flagged, tolerance: float = 0.02) -> tuple[float, float]:
    """How well a flag image finds the pixels that really alias.

    A pixel *aliases* when the unclamped test image's error against the reference
    exceeds ``tolerance`` in some channel. Precision = flagged pixels that alias /
    flagged pixels; recall = aliasing pixels flagged / aliasing pixels.

    Parameters
    ----------
    image_true : ndarray, shape (H, W[, C])
        Reference.
    image_test : ndarray, same shape
        The image without specular anti-aliasing (one shade per piece).
    flagged : ndarray of bool, shape (H, W)
        The detector's output (e.g. ``specular_aliasing_map(scene).flag``).
    tolerance : float, optional
        Absolute error above which a pixel counts as aliased.

    Returns
    -------
    precision, recall : float
        NaN where the denominator is zero.
    """
    flagged = np.asarray(flagged, dtype=bool)
    image_true, image_test, flagged = _checked(image_true, image_test, flagged)
    error = np.abs(image_test - image_true)
    if error.ndim == 3:
        error = error.max(axis=2)
    aliased = error > tolerance
    hits = np.count_nonzero(flagged & aliased)
    n_flag, n_alias = np.count_nonzero(flagged), np.count_nonzero(aliased)
    precision = hits / n_flag if n_flag else float("nan")
    recall = hits / n_alias if n_alias else float("nan")
    return float(precision), float(recall)


def _checked(image_true, image_test, mask):
    image_true = np.asarray(image_true, dtype=np.float64)
    image_test = np.asarray(image_test, dtype=np.float64)
    mask = np.asarray(mask, dtype=bool)
    if image_true.shape != image_test.shape:
        raise ValueError(f"images differ in shape: {image_true.shape} vs {image_test.shape}")
    if image_true.ndim == 3 and image_true.shape[2] != 3 and mask.ndim == 2:
        raise ValueError(f"expected (H, W) specular or (H, W, 3) RGB images, got shape {image_true.shape}")
    for label, image in (("true", image_true), ("test", image_test)):
        if not np.isfinite(image).all():
            raise ValueError(f"the {label} image has non-finite values (NaN or inf)")
    if image_true.shape[: mask.ndim] != mask.shape:
        raise ValueError(f"mask shape {mask.shape} does not match images of shape {image_true.shape}")
    return image_true, image_test, mask


def _still_mask(mask, shape) -> np.ndarray:
    mask = np.asarray(mask, dtype=bool)
    if mask.ndim == 3:
        mask = mask.any(axis=0)
    if mask.shape != tuple(shape[1:3]):
        raise ValueError(f"mask shape {mask.shape} does not match frames of shape {tuple(shape[1:3])}")
    return mask


def _frames(frames_true, frames_test):
    frames_true = np.asarray(frames_true, dtype=np.float64)
    frames_test = np.asarray(frames_test, dtype=np.float64)
    if frames_true.shape != frames_test.shape:
        raise ValueError(f"frame stacks differ in shape: {frames_true.shape} vs {frames_test.shape}")
    for label, frames in (("true", frames_true), ("test", frames_test)):
        if not np.isfinite(frames).all():
            raise ValueError(f"the {label} frames have non-finite values (NaN or inf)")
    if frames_true.ndim < 3 or frames_true.shape[0] < 2:
        raise ValueError(f"need a stack of at least 2 frames (T, H, W[, C]), got shape {frames_true.shape}")
    return frames_true, frames_test
