"""Whether a sampled render agrees with an exact image within its own noise: a stated test.

Mitsuba's own render tests compare against references with a variance image by a per-pixel
z-test at significance 0.01 with a Sidak correction over the pixels, and pass when 99.75 %
of the pixels pass (field notes). Here the variance is measured, not known: K independent
renders (seeds) of the same scene at spp each, so each pixel channel's mean (K x spp samples)
is tested against the exact value by Student's t with K - 1 degrees of freedom.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy import stats

from aaeval.metrics.agreement import PASS_FRACTION, SIGNIFICANCE, sidak_level

__all__ = ["Agreement", "agreement"]


class Agreement(NamedTuple):
    passed: bool
    fraction: float  # of the pixel channels that pass
    alpha_each: float  # the Sidak-corrected significance per pixel channel
    worst_t: float  # the largest |t| seen
    renders: int


def agreement(renders, exact, *, alpha: float = SIGNIFICANCE, pass_fraction: float = PASS_FRACTION,
              floor: float = 1e-6) -> Agreement:
    """Test ``renders`` (K, H, W[, C]) of independent seeds against ``exact`` (H, W[, C]).

    A pixel channel passes when the two-sided p-value of ``t = (mean - exact) / (s / sqrt K)``
    is above the Sidak-corrected level (:func:`aaeval.metrics.agreement.sidak_level`); where the renders do not vary
    (``s`` = 0: every sample saw the same value) it passes when the mean is within ``floor``
    (relative, at least 1e-6 absolute) of the exact value: Mitsuba's film is float32, whose
    rounding is about 6e-8 relative per sample.
    """
    r = np.asarray(renders, dtype=np.float64)
    e = np.asarray(exact, dtype=np.float64)
    if r.ndim != e.ndim + 1 or r.shape[1:] != e.shape or r.shape[0] < 2:
        raise ValueError(f"agreement: renders {r.shape} must be (K >= 2,) + the exact image's shape {e.shape}")
    k = r.shape[0]
    mean = r.mean(axis=0)
    s = r.std(axis=0, ddof=1)
    n = e.size
    alpha_each = sidak_level(n, alpha)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.abs(mean - e) / (s / np.sqrt(k))
    flat = s == 0
    ok = np.where(flat, np.abs(mean - e) <= floor * np.maximum(np.abs(e), 1.0), 2.0 * stats.t.sf(np.where(flat, 0.0, t), k - 1) > alpha_each)
    fraction = float(ok.mean())
    worst = float(np.max(np.where(flat, 0.0, t))) if n else 0.0
    return Agreement(fraction >= pass_fraction, fraction, alpha_each, worst, k)
