"""Highlight metrics for specular anti-aliasing (Amanatides 1992 experiments).

Images are (H, W) specular-only or (H, W, 3) linear RGB; animations are sequences of
them, frame first. Masks select the highlight: :func:`highlight_mask` marks the pixels
where the ground truth's specular term is significant.
"""

from __future__ import annotations

import numpy as np

from aaeval.metrics._checks import check_finite_pair, check_frame_mask, check_stack_pair
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
    frames_true, frames_test = check_stack_pair(frames_true, frames_test)
    mask = check_frame_mask(mask, frames_true.shape, per_frame="any")
    if not mask.any():
        return float("nan")
    change = np.diff(frames_test - frames_true, axis=0)[:, mask]
    return float(np.sqrt(np.mean(change**2)))


def highlight_profile_flicker(frames_true, frames_test, *, mask, direction: float | None = None,
                              section: float = 2.0, margin: int = 4) -> float:
    """Flicker of the highlight's energy per cross-section, after each cross-section's steady gain.

    Each highlight (a connected piece of the mask, widened by ``margin``) is cut across
    its own direction, found from the truth: the principal axis of the truth's
    time-averaged highlight, with a quadratic centre line along it, so a highlight at any
    angle, or a curved one, is cut across. The cuts follow the pixel axis nearest to the
    highlight's perpendicular (columns for a highlight nearer horizontal, rows for one
    nearer vertical); a cross-section is a Gaussian window of standard deviation
    ``section`` pixels along the highlight's axis, weighting each pixel by where its cut
    meets the centre line. The box-filtered truth keeps each cross-section's energy nearly
    constant as the highlight drifts by fractions of a pixel; a highlight that breaks up
    or pops does not.

    With ``P(t)`` the truth's and ``Q(t)`` the test's energy in a cross-section at frame
    ``t``, the cross-section's steady gain ``g = sum(P Q) / sum(P P)`` (least squares over
    the frames) is its bias; what is left, ``Q - g P``, is flicker. Returns
    ``sqrt(sum(|Q - g P|^2) / sum(P^2))`` over cross-sections and frames: a steady bias
    scores 0, a highlight brightened and dimmed by 20 % in alternate frames 0.2.

    Why these cuts: a box-filtered pixel holds its energy without saying where in the
    square it lies. A hard 1 px bin across a highlight at an angle splits squares, and the
    share of a split square that belongs to each bin changes as the highlight moves (by
    1.5 % of a bin at 19 degrees, 4.5 % at 45, with exact area weights); a window whose
    weight changes slowly over a pixel makes that share nearly irrelevant. And a cut
    exactly perpendicular to a highlight 5 degrees from vertical gives the pixels of one
    row different weights: a narrow highlight and a wider one drifting across that row
    together spread their energy over its pixels differently, and a steady wider
    highlight read 4e-3 of flicker. Cutting along rows there leaves it at 0.

    Parameters
    ----------
    frames_true, frames_test : ndarray, shape (T, H, W) (specular term) or (T, H, W, C)
        Channels are summed.
    mask : ndarray of bool, shape (H, W) or (T, H, W)
        The highlight's pixels (a per-frame mask counts the pixels masked in any frame).
    direction : float, optional
        The highlights' direction in degrees from the image's x axis toward its y axis (90:
        straight down the image, whose cross-sections are rows), taken straight; default:
        each highlight's own, found from the truth.
    section : float, optional
        Standard deviation in pixels of the window along the highlight that one
        cross-section sums over.
    margin : int, optional
        Pixels the mask is widened by, so that energy a steady blur spreads just outside
        the highlight still counts in its cross-section (a 1 px Gaussian, truncated at 4
        sigma, needs 4).

    Returns
    -------
    flicker : float
        Relative; NaN when the truth has no energy in the region.
    """
    frames_true, frames_test = check_stack_pair(frames_true, frames_test)
    mask = check_frame_mask(mask, frames_true.shape, per_frame="any")
    if direction is not None and not np.isfinite(direction):
        raise ValueError(f"direction must be a finite angle in degrees or None, got {direction!r}")
    if not section > 0 or not np.isfinite(section):
        raise ValueError(f"section must be a finite number of pixels > 0, got {section!r}")
    if int(margin) != margin or margin < 0:
        raise ValueError(f"margin must be a whole number of pixels >= 0, got {margin!r}")
    true, test = (f.sum(axis=-1) if f.ndim == 4 else f for f in (frames_true, frames_test))
    left, energy = 0.0, 0.0
    height, width = mask.shape
    for (rows, cols), highlight, along, cut in _cross_section_positions(true.mean(axis=0), mask, int(margin),
                                                                         direction):
        windows = _gaussian_windows(along, section)
        # A cut that the image's side ends inside the highlight holds part of a cross-section,
        # whose share changes as the highlight slides along that side: cross-sections with
        # more than 1 % of their highlight on the side are left out.
        side = (cols == 0) | (cols == width - 1) if cut == 1 else (rows == 0) | (rows == height - 1)
        windows = windows[:, (highlight * side) @ windows <= 0.01 * (highlight @ windows)]
        p, q = true[:, rows, cols] @ windows, test[:, rows, cols] @ windows
        power = (p * p).sum(axis=0)
        lit = power > 0
        gain = (p * q).sum(axis=0)[lit] / power[lit]
        left += float(((q[:, lit] - gain * p[:, lit]) ** 2).sum())
        energy += float(power.sum())
    if energy == 0:
        return float("nan")
    return float(np.sqrt(left / energy))


def _cross_section_positions(truth, mask, margin, direction):
    """For each highlight (a connected piece of ``mask`` widened by ``margin``), its pixels,
    the truth on those of them in the mask (0 elsewhere), and where each pixel lies along
    the highlight with the cut that places it (:func:`_position_along`)."""
    from scipy import ndimage  # here, not at the top: every command line loads this module, few measure

    disk = np.hypot(*np.mgrid[-margin:margin + 1, -margin:margin + 1]) <= margin
    region = ndimage.binary_dilation(mask, structure=disk) if margin else mask
    pieces, count = ndimage.label(region, structure=np.ones((3, 3), bool))
    weight = np.where(mask, np.clip(truth, 0, None), 0.0)
    for piece in range(1, count + 1):
        rows, cols = np.nonzero(pieces == piece)
        w = weight[rows, cols]
        if not w.sum() > 0:
            continue
        centres = np.stack([cols + 0.5, rows + 0.5], axis=1)
        yield (rows, cols), w, *_position_along(centres, w, direction)


def _position_along(points, weight, direction):
    """Where each point's cut meets the highlight's centre line, as a distance along it, and
    the cut (0: columns, 1: rows).

    The centre line runs along the principal axis of the weighted points (or ``direction``),
    bent by a quadratic fitted across it. A point's cut is its pixel column when the line
    is nearer horizontal, its row when nearer vertical: the pixel axis nearest to the
    line's perpendicular (within 45 degrees of it), so that energy moving across the
    highlight from pixel to pixel of one row (or column) stays in its cross-section.
    """
    centre = weight @ points / weight.sum()
    offsets = points - centre
    if direction is None:
        spread = (offsets * weight[:, None]).T @ offsets
        axis = np.linalg.eigh(spread)[1][:, -1]  # the principal axis: the largest spread
    else:
        axis = np.array([np.cos(np.radians(direction)), np.sin(np.radians(direction))])
    across = np.array([-axis[1], axis[0]])
    cut = 0 if abs(axis[0]) >= abs(axis[1]) else 1  # 0: columns cut the line, 1: rows
    target = offsets[:, cut]
    t = target / axis[cut]
    lit = weight > 0
    u = offsets[lit] @ axis
    degree = min(2, len(np.unique(u)) - 1)
    if direction is not None or degree < 1:
        return t, cut
    line = np.polynomial.Polynomial.fit(u, offsets[lit] @ across, degree, w=np.sqrt(weight[lit]))
    slope = line.deriv()
    for _ in range(8):  # Newton's steps to the centre line's point t * axis + line(t) * across in the cut
        t -= (t * axis[cut] + line(t) * across[cut] - target) / (axis[cut] + slope(t) * across[cut])
    return t, cut


def _gaussian_windows(position, sigma):
    """Weights (pixels x windows) of Gaussian windows spaced ``sigma`` apart along ``position``."""
    centres = np.arange(position.min() - 2 * sigma, position.max() + 2 * sigma + sigma, sigma)
    return np.exp(-0.5 * ((position[:, None] - centres[None, :]) / sigma) ** 2)


def _energy_ratios(frames_true, frames_test, mask) -> np.ndarray:
    frames_true, frames_test = check_stack_pair(frames_true, frames_test)
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
    frames_true, frames_test, mask
        As for :func:`highlight_bias`.

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
    image_true, image_test = check_finite_pair(image_true, image_test, "images")
    mask = np.asarray(mask, dtype=bool)
    if image_true.ndim == 3 and image_true.shape[2] != 3 and mask.ndim == 2:
        raise ValueError(f"expected (H, W) specular or (H, W, 3) RGB images, got shape {image_true.shape}")
    if image_true.shape[: mask.ndim] != mask.shape:
        raise ValueError(f"mask shape {mask.shape} does not match images of shape {image_true.shape}")
    return image_true, image_test, mask


