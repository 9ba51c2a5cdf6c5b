"""The ground truth's noise at each metric's own pixels, and the test that says whether a
method agrees with the truth within it.

A sampled ground truth (Mitsuba at high spp) has noise, and that noise is not spread evenly:
a pixel one surface covers whole is exact whatever the sampler (box filter, flat colour),
while a pixel an edge crosses carries the coverage estimate's variance. A noise level
measured over the whole image is therefore too low for a metric over edge pixels (an exact
method then reads as off by 2-3x) and too high for the flat pixels. Here the noise is
measured like the metric: on the same pixels, with the same reduction (RMS for the RMS
metrics), from the truth against a second render with the next seed.

The agreement test is Mitsuba's render-test recipe (``mitsuba/python/test``: a per-pixel
z-test at significance 0.01 with a Sidak correction over the pixels, passing when at least
99.75% of the pixels pass), with each pixel's standard deviation pooled over the metric's
pixels of its kind: those an edge crosses, and the others (two seeds give one sample of the
noise per pixel; pooling over pixels of like variance gives a usable estimate).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["SIGNIFICANCE", "PASS_FRACTION", "ROUNDING", "sidak_threshold", "noise_strata", "z_test_pass_fraction", "agrees"]

#: Family-wise significance of the per-pixel z-test (Mitsuba's render tests use 0.01).
SIGNIFICANCE = 0.01
#: Fraction of the pixels (channels) that must pass for a method to agree with the truth.
PASS_FRACTION = 0.9975
#: Differences below this always pass: Mitsuba's film accumulates in float32, so a pixel it
#: renders exactly (one flat colour) still differs from a float64 method by its rounding.
ROUNDING = 1e-6


def sidak_threshold(n: int, alpha: float = SIGNIFICANCE) -> float:
    """The |z| above which a pixel fails: a two-sided z-test at the Sidak-corrected level
    ``1 - (1 - alpha) ** (1 / n)`` for ``n`` tests, so the family fails with probability alpha."""
    from scipy.stats import norm

    if n < 1:
        raise ValueError(f"need at least one test, got {n}")
    per_test = -math.expm1(math.log1p(-alpha) / n)  # 1 - (1 - alpha)**(1/n), accurate for large n
    return float(norm.isf(per_test / 2.0))


def noise_strata(truth: np.ndarray, twin: np.ndarray, mask: np.ndarray, edge: np.ndarray) -> tuple[float, float, float]:
    """The truth's RMS noise per pixel and channel over ``mask``, over its edge pixels, over the rest.

    One render's noise is ``(truth - twin) / sqrt(2)`` (two independent renders, equal noise).

    Parameters
    ----------
    truth, twin : ndarray, shape (H, W, 3)
        The ground truth and the same render with the next seed.
    mask : ndarray of bool, shape (H, W)
        The metric's pixels (all True for a whole-image metric).
    edge : ndarray of bool, shape (H, W)
        Pixels a visible edge crosses (:func:`aaeval.metrics.edges.edge_mask`).

    Returns
    -------
    all, edge, other : float
        NaN for a stratum without pixels.
    """
    diff = (np.asarray(truth, float) - np.asarray(twin, float)) / math.sqrt(2.0)

    def rms(where):
        return float(np.sqrt(np.mean(diff[where] ** 2))) if where.any() else math.nan

    mask, edge = np.asarray(mask, bool), np.asarray(edge, bool)
    return rms(mask), rms(mask & edge), rms(mask & ~edge)


def z_test_pass_fraction(truth: np.ndarray, test: np.ndarray, mask: np.ndarray, edge: np.ndarray,
                         sigma_edge: float, sigma_other: float, *, alpha: float = SIGNIFICANCE) -> float:
    """Fraction of the values (pixels x channels) of ``mask`` whose error passes the z-test.

    A value passes when ``|test - truth| <= z * sigma``, with ``z`` :func:`sidak_threshold`
    over the masked values and ``sigma`` the truth's noise of the pixel's kind (edge or
    not). Where that noise is 0 (a pixel the truth renders exactly) any difference fails
    unless it is below :data:`ROUNDING`.

    Returns
    -------
    fraction : float
        In [0, 1]; NaN when the mask is empty or a needed noise is unknown (NaN).
    """
    truth, test = np.asarray(truth, float), np.asarray(test, float)
    mask, edge = np.asarray(mask, bool), np.asarray(edge, bool)
    n = int(mask.sum()) * truth.shape[-1]
    if n == 0:
        return math.nan
    sigma = np.where(edge, sigma_edge, sigma_other)[mask]
    if np.isnan(sigma).any():
        return math.nan
    error = np.abs(test[mask] - truth[mask])  # (pixels, channels)
    bound = sidak_threshold(n, alpha) * sigma[:, None] + ROUNDING
    return float(np.mean(error <= bound))


def agrees(pass_fraction: float) -> bool | None:
    """True when at least :data:`PASS_FRACTION` of the values passed; None when not tested."""
    if pass_fraction is None or not math.isfinite(pass_fraction):
        return None
    return bool(pass_fraction >= PASS_FRACTION)
