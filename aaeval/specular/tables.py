"""Fourier tables of the Phong highlight cos^n (Amanatides 1992).

cos^n x = 2^-n sum_k C(n, k) cos((n - 2k) x): the component at frequency |n - 2k| has
coefficient 2^-n C(n, k) on each of e^{+i(n-2k)x} and e^{-i(n-2k)x}, so by Parseval the
power at frequencies <= f is sum over k with |n - 2k| <= f of (2^-n C(n, k))^2.

The paper's three tables:

- ``MinDot[n]``: the smallest dot product of two normals that cannot alias. The sampling
  step above which cos^n aliases is pi/n in alpha; a normal turn of d turns alpha by 2d,
  so the largest safe normal turn is pi/(2n) and MinDot[n] = cos(pi/(2n)). The aggressive
  form replaces n (the highest frequency) by the cutoff frequency below which a fraction
  P of the power lies.
- ``Maximum[n]``: the DC component of cos^n, 2^-n C(n, n/2) for even n. It is the mean of
  |cos x|^n, which we use for every real n (Gamma-function form, equal to the binomial
  for even n) so that clamped exponents need not be integers.
- ``MaxnAllowed[f]``: the largest exponent whose P-power cutoff is at most f.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

__all__ = [
    "power_spectrum",
    "power_cutoff",
    "cutoff_table",
    "min_dot",
    "maximum",
    "max_n_allowed",
]


def power_spectrum(n: int) -> np.ndarray:
    """Power of cos^n at frequencies 0..n (float64, sums to the mean of cos^2n).

    Parameters
    ----------
    n : int
        Non-negative integer exponent.

    Returns
    -------
    ndarray, shape (n + 1,)
        ``power[f]``: power of the frequency-f component; zero where f and n differ in
        parity.
    """
    n = _check_exponent(n)
    k = np.arange(n + 1)
    # log of 2^-n C(n, k), exact to float64 rounding also for n in the thousands
    log_c = (
        np.array([math.lgamma(n + 1)]) - _lgamma(k + 1) - _lgamma(n - k + 1) - n * math.log(2.0)
    )
    power = np.zeros(n + 1)
    np.add.at(power, np.abs(n - 2 * k), np.exp(2.0 * log_c))
    return power


def power_cutoff(n: int, power: float) -> int:
    """Smallest frequency f such that a fraction ``power`` of cos^n's power lies at <= f.

    Amanatides 1992, figure 2: for n = 500, 99.9 % of the power lies at or below 52 and
    99 % at or below 40.

    Parameters
    ----------
    n : int
        Non-negative integer exponent.
    power : float
        Fraction in (0, 1]; 1 gives n itself (the conservative bound).
    """
    n = _check_exponent(n)
    power = _check_power(power)
    return int(cutoff_table(n, power)[n])


@lru_cache(maxsize=32)
def cutoff_table(n_max: int, power: float) -> np.ndarray:
    """``power_cutoff(n, power)`` for n = 0..n_max (int64 array, read-only)."""
    n_max = _check_exponent(n_max)
    power = _check_power(power)
    table = np.arange(n_max + 1, dtype=np.int64)
    if power < 1.0:
        for n in range(1, n_max + 1):
            cumulative = np.cumsum(power_spectrum(n))
            # relative tolerance: a fraction reached up to float rounding counts as reached
            table[n] = int(np.searchsorted(cumulative, power * cumulative[-1] * (1 - 1e-12)))
    table.setflags(write=False)
    return table


def min_dot(n, power: float = 1.0):
    """Smallest normal-pair dot product that cannot alias for exponent ``n``.

    ``cos(pi / (2 f))`` with ``f = n`` (conservative, ``power = 1``) or the ``power``
    cutoff frequency of cos^n (aggressive). Accepts arrays of exponents.
    """
    f = _cutoff_of(n, power)
    with np.errstate(divide="ignore"):
        return np.where(f > 0, np.cos(np.pi / (2.0 * np.maximum(f, 1e-300))), -1.0)


def maximum(n):
    """DC component of cos^n: mean of |cos x|^n = Gamma((n+1)/2) / (sqrt(pi) Gamma(n/2+1)).

    Equals 2^-n C(n, n/2) for even integers n (Maximum[500] = 0.035665); defined for every
    real n >= 0 so that clamped exponents may be fractional. Accepts arrays.
    """
    n = np.asarray(n, dtype=np.float64)
    if np.any(n < 0):
        raise ValueError("Maximum[n] needs n >= 0")
    log_m = _lgamma((n + 1.0) / 2.0) - 0.5 * math.log(math.pi) - _lgamma(n / 2.0 + 1.0)
    return np.exp(log_m)


def max_n_allowed(frequency, power: float, n_max: int):
    """Largest exponent n <= n_max whose ``power`` cutoff frequency is at most ``frequency``.

    With ``power = 1`` this is the frequency itself (the paper's conservative
    ``n' = sampleFrequency``, not rounded). Exponents whose cutoff table is not monotone
    are handled by taking the largest n below which *every* cutoff fits. Accepts arrays.
    """
    power = _check_power(power)
    frequency = np.asarray(frequency, dtype=np.float64)
    if power == 1.0:
        return np.minimum(frequency, float(n_max))
    envelope = np.maximum.accumulate(cutoff_table(int(n_max), power))
    # envelope[n] <= f for n < idx; envelope[0] = 0 so idx >= 1 for f >= 0
    idx = np.searchsorted(envelope, frequency, side="right")
    return np.maximum(idx - 1, 0).astype(np.float64)


def _cutoff_of(n, power: float) -> np.ndarray:
    power = _check_power(power)
    n = np.asarray(n, dtype=np.float64)
    if power == 1.0:
        return n
    n_int = np.rint(n).astype(np.int64)
    if n_int.size == 0:
        return n
    table = cutoff_table(int(n_int.max()), power)
    return table[n_int].astype(np.float64)


def _lgamma(x):
    # scipy.special takes about 0.5 s to import: loaded when a table is first built, not with
    # aaeval.renderers (every command and sweep worker imports this module through it)
    from scipy.special import gammaln

    return gammaln(np.asarray(x, dtype=np.float64))


def _check_exponent(n) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise ValueError(f"exponent must be a non-negative integer, got {n!r}")
    return int(n)


def _check_power(power) -> float:
    power = float(power)
    if not (0.0 < power <= 1.0):
        raise ValueError(f"power fraction must lie in (0, 1], got {power!r}")
    return power
