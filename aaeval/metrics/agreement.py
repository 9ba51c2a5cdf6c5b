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
99.75% of the pixels pass). Two seeds give one sample of the noise per pixel, so each
value's standard deviation comes from a model pooled over the metric's pixels: on a pixel an
edge crosses, a sampled box filter's noise is its coverage estimate's times the spread of
the colours meeting there (:func:`aaeval.metrics.edges.noise_weight`: per channel, the range of the visible
fragments' flat colours; 1 where shading varies inside a fragment), with one scale for all
of them; the other pixels have a noise of their own (0 for flat colours: exact whatever the
sampler). Pooled without the colour weight, the noise of a bright channel at a
high-contrast edge is under-stated, and an exact method failed there (Khan's triangles:
99.72% of the values passing against 99.99% with it).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

__all__ = ["SIGNIFICANCE", "PASS_FRACTION", "ROUNDING", "EXACT_ROUNDING", "Truth", "truth_of", "within_truth",
           "sidak_level", "sidak_threshold", "noise_strata", "z_test_pass_fraction", "agrees"]

#: Family-wise significance of the per-pixel z-test (Mitsuba's render tests use 0.01).
SIGNIFICANCE = 0.01
#: Fraction of the pixels (channels) that must pass for a method to agree with the truth.
PASS_FRACTION = 0.9975
#: Differences below this always pass: Mitsuba's film accumulates in float32, so a pixel it
#: renders exactly (one flat colour) still differs from a float64 method by its rounding
#: (2.1e-6 seen at 4096 spp on a colour of 0.95; the same in both seeds, so no noise shows).
ROUNDING = 1e-5
#: Float64 rounding of an exact image: two exact algorithms (Catmull, Weiler-Atherton) agree to
#: about 1e-15 per value; sums over many pieces stay far below this.
EXACT_ROUNDING = 1e-12


class Truth(NamedTuple):
    """What a reference is as a truth, and its own uncertainty (:func:`truth_of`).

    ``kind`` is ``seeded`` (a Monte Carlo render: ``level`` is its measured noise RMS),
    ``bounded`` (noise-free, with an error bound: ``level`` is the bound's RMS, e.g. exact
    shading's quadrature), ``exact`` (noise-free, ``level`` 0) or ``unknown`` (deterministic but
    not exact, or a seeded truth whose noise was not measured: ``level`` NaN).
    """

    kind: str
    level: float

    @property
    def noise_free(self) -> bool:
        return self.kind in ("bounded", "exact")

    def words(self, fmt: str = ".2e") -> str:
        """The truth and its uncertainty in a few words, for tables and sentences."""
        if self.kind == "seeded":
            return f"seeded, noise RMS {format(self.level, fmt)}"
        if self.kind == "bounded":
            return f"exact, no noise; error bound RMS {format(self.level, fmt)}"
        if self.kind == "exact":
            return "exact, no noise"
        return "deterministic, its own error unknown"


def truth_of(reference_kind: str, level: float) -> Truth:
    """The one rule for what a reference is as a truth.

    Parameters
    ----------
    reference_kind : str
        ``exact``, ``stochastic`` or ``deterministic`` (the sweep's ``reference_kind``).
    level : float
        The sweep's ``reference_noise_rmse``: a seeded truth's measured noise, a noise-free
        truth's error bound (0 when it has none).

    Returns
    -------
    Truth
        A noise-free truth is never ``seeded``, whatever its level: an error bound is not noise.
    """
    level = float(level) if level is not None else math.nan
    if reference_kind == "exact":
        return Truth("bounded", level) if math.isfinite(level) and level > 0 else Truth("exact", 0.0)
    if reference_kind == "stochastic" and math.isfinite(level) and level > 0:
        return Truth("seeded", level)
    return Truth("unknown", math.nan)


def within_truth(error: float, truth: Truth, factor: float = 1.0) -> bool | None:
    """Whether an RMS ``error`` against ``truth`` is within what the truth can resolve.

    Against a seeded truth: within ``factor`` times its noise. Against a noise-free truth:
    within its error bound plus :data:`EXACT_ROUNDING` (``factor`` does not apply: a bound is
    not a spread to be a multiple of). None where the truth's uncertainty is unknown or the
    error is not finite.
    """
    if truth.kind == "unknown" or error is None or not math.isfinite(error):
        return None
    if truth.kind == "seeded":
        return bool(error <= factor * truth.level)
    return bool(error <= truth.level + EXACT_ROUNDING)


def sidak_level(n: int, alpha: float = SIGNIFICANCE) -> float:
    """The per-test significance ``1 - (1 - alpha) ** (1 / n)`` of ``n`` tests whose family
    fails with probability ``alpha`` (Sidak)."""
    if n < 1:
        raise ValueError(f"need at least one test, got {n}")
    return -math.expm1(math.log1p(-alpha) / n)  # accurate for large n


def sidak_threshold(n: int, alpha: float = SIGNIFICANCE) -> float:
    """The |z| above which a pixel fails: a two-sided z-test at :func:`sidak_level`."""
    # scipy.special, not scipy.stats (norm.isf is -ndtri, the same bits): scipy.stats takes
    # about half a second to import, paid by every sweep worker's first cell
    from scipy.special import ndtri

    return float(-ndtri(sidak_level(n, alpha) / 2.0))


def _sigma(edge: np.ndarray, weight: np.ndarray | None, scale_edge: float, sigma_other: float) -> np.ndarray:
    """Each value's modelled noise, (H, W, 3): ``scale_edge * weight`` on edge pixels,
    ``sigma_other`` elsewhere."""
    weight = np.ones(edge.shape + (3,)) if weight is None else np.asarray(weight, float)
    return np.where(edge[..., None], scale_edge * weight, sigma_other)


def noise_strata(truth: np.ndarray, twin: np.ndarray, mask: np.ndarray, edge: np.ndarray,
                 weight: np.ndarray | None = None) -> tuple[float, float, float]:
    """The truth's noise over ``mask`` as the metric reduces it, and the two numbers of the
    per-value noise model :func:`z_test_pass_fraction` reads.

    One render's noise is ``(truth - twin) / sqrt(2)`` (two independent renders, equal noise).
    On an edge pixel the model is ``noise = scale * weight`` (:func:`aaeval.metrics.edges.noise_weight`; all 1
    when ``weight`` is None): ``scale`` is the RMS of ``noise / weight`` over the masked
    edge values whose weight is not 0. Elsewhere the noise is the RMS over the masked
    other pixels.

    Parameters
    ----------
    truth, twin : ndarray, shape (H, W, 3)
        The ground truth and the same render with the next seed.
    mask : ndarray of bool, shape (H, W)
        The metric's pixels (all True for a whole-image metric).
    edge : ndarray of bool, shape (H, W)
        Pixels a visible edge crosses (:func:`aaeval.metrics.edges.edge_mask`).
    weight : ndarray, shape (H, W, 3), optional
        Relative noise of the edge values.

    Returns
    -------
    noise, scale, other : float
        The RMS noise per value over ``mask``; the edge values' scale; the other pixels'
        RMS noise. NaN where there is nothing to pool.
    """
    diff = (np.asarray(truth, float) - np.asarray(twin, float)) / math.sqrt(2.0)
    mask, edge = np.asarray(mask, bool), np.asarray(edge, bool)
    weight = np.ones(diff.shape) if weight is None else np.asarray(weight, float)

    def rms(values):
        return float(np.sqrt(np.mean(values ** 2))) if values.size else math.nan

    on_edges = weight[mask & edge] > 0.0
    relative = diff[mask & edge][on_edges] / weight[mask & edge][on_edges]
    return rms(diff[mask]), rms(relative), rms(diff[mask & ~edge])


def z_test_pass_fraction(truth: np.ndarray, test: np.ndarray, mask: np.ndarray, edge: np.ndarray,
                         scale_edge: float, sigma_other: float, *, weight: np.ndarray | None = None,
                         alpha: float = SIGNIFICANCE) -> float:
    """Fraction of the values (pixels x channels) of ``mask`` whose error passes the z-test.

    A value passes when ``|test - truth| <= z * sigma``, with ``z`` :func:`sidak_threshold`
    over the masked values and ``sigma`` the value's modelled noise (:func:`noise_strata`:
    ``scale_edge * weight`` on edge pixels, ``sigma_other`` elsewhere). Where that noise is
    0 (a value the truth renders exactly) any difference fails unless it is below
    :data:`ROUNDING`.

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
    sigma = _sigma(edge, weight, scale_edge, sigma_other)[mask]
    if np.isnan(sigma).any():
        return math.nan
    error = np.abs(test[mask] - truth[mask])  # (pixels, channels)
    bound = sidak_threshold(n, alpha) * sigma + ROUNDING
    return float(np.mean(error <= bound))


def agrees(pass_fraction: float) -> bool | None:
    """True when at least :data:`PASS_FRACTION` of the values passed; None when not tested."""
    if pass_fraction is None or not math.isfinite(pass_fraction):
        return None
    return bool(pass_fraction >= PASS_FRACTION)
