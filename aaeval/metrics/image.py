"""Pixel-wise fidelity metrics: RMSE, PSNR and SSIM of a test image against a reference.

Images are (H, W, 3) linear RGB, the renderers' output. PSNR and SSIM are scikit-image's
(:mod:`skimage.metrics`) with every channel treated alike.
"""

from __future__ import annotations

import numpy as np

from aaeval.metrics._checks import check_image_pair, check_positive

__all__ = ["rmse", "masked_rmse", "psnr", "ssim"]


def rmse(image_true, image_test) -> float:
    """Root-mean-square error over every pixel and channel.

    Parameters
    ----------
    image_true, image_test : ndarray, shape (H, W, 3)
        The reference and the test image (linear RGB), the same shape.

    Returns
    -------
    rmse : float
        ``sqrt(mean((image_test - image_true) ** 2))``; 0 for identical images.
    """
    image_true, image_test = check_image_pair(image_true, image_test)
    return float(np.sqrt(np.mean((image_test - image_true) ** 2)))


def masked_rmse(image_true: np.ndarray, image_test: np.ndarray, mask: np.ndarray) -> float:
    """RMSE over the pixels of ``mask`` (every channel); NaN when the mask selects none.

    The one masked RMSE behind ``edge_rmse`` and ``highlight_rmse``: they check their
    inputs, this only computes. ``mask`` has the images' shape without the channel axis.
    """
    if not mask.any():
        return float("nan")
    return float(np.sqrt(np.mean((image_test[mask] - image_true[mask]) ** 2)))


def psnr(image_true, image_test, *, data_range: float = 1.0) -> float:
    """Peak signal-to-noise ratio in decibels (scikit-image).

    Parameters
    ----------
    image_true, image_test : ndarray, shape (H, W, 3)
        The reference and the test image (linear RGB), the same shape.
    data_range : float, optional
        Peak-to-peak range of the signal; 1.0 (the default) for colours in [0, 1].

    Returns
    -------
    psnr : float
        ``10 log10(data_range**2 / MSE)``; ``inf`` for identical images.
    """
    image_true, image_test = check_image_pair(image_true, image_test)
    check_positive("data_range", data_range)
    # scikit-image imports scipy.stats (about 1 s): loaded on first use, not with aaeval.metrics,
    # so a command or a sweep worker that never computes PSNR or SSIM does not pay for it
    from skimage.metrics import peak_signal_noise_ratio

    with np.errstate(divide="ignore"):  # identical images: MSE 0, PSNR inf, not a warning
        return float(peak_signal_noise_ratio(image_true, image_test, data_range=data_range))


def ssim(image_true, image_test, *, data_range: float = 1.0, win_size: int = 7) -> float:
    """Mean structural similarity (Wang et al. 2004) over pixels and channels (scikit-image).

    scikit-image's defaults: a uniform ``win_size`` x ``win_size`` window, sample
    covariance, K1 = 0.01, K2 = 0.03, each RGB channel computed alone and averaged.

    Parameters
    ----------
    image_true, image_test : ndarray, shape (H, W, 3)
        The reference and the test image (linear RGB), the same shape.
    data_range : float, optional
        As for :func:`psnr`: 1.0 (the default) for colours in [0, 1].
    win_size : int, optional
        Odd side of the window, 7 by default. On images with a side shorter than that it
        shrinks to the largest odd number that fits (at least 3).

    Returns
    -------
    ssim : float
        In [-1, 1]; 1 for identical images.
    """
    image_true, image_test = check_image_pair(image_true, image_test)
    check_positive("data_range", data_range)
    if win_size < 3 or win_size % 2 == 0:
        raise ValueError(f"win_size must be an odd number >= 3, got {win_size!r}")
    side = min(image_true.shape[:2])
    fitted = min(win_size, side if side % 2 else side - 1)
    if fitted < 3:
        raise ValueError(f"SSIM needs images at least 3 pixels on each side, got {image_true.shape[:2]}")
    from skimage.metrics import structural_similarity  # on first use (see psnr)

    return float(
        structural_similarity(image_true, image_test, data_range=data_range, channel_axis=-1, win_size=fitted)
    )
