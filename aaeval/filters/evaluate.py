"""Point evaluation of a registered filter's profile (numba), for samplers that splat.

:func:`profile_at` is the one evaluation of ``k(t)``; :meth:`PixelFilter.profile` and the
sampling baselines both call it. A filter reaches numba as the tuple
:func:`profile_args` returns.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from aaeval.filters.registry import KIND_BOX, KIND_GAUSSIAN

__all__ = ["profile_at", "profile_array", "profile_args"]


def profile_args(filt) -> tuple:
    """``(kind, radius, pieces, alpha, bias)`` of a :class:`~aaeval.filters.PixelFilter` for :func:`profile_at`."""
    alpha, bias = filt.gaussian_alpha_bias if filt.kind == KIND_GAUSSIAN else (0.0, 0.0)
    pieces = np.ascontiguousarray(filt.pieces if filt.pieces.size else np.zeros((1, 1)), dtype=np.float64)
    return filt.kind, float(filt.radius), pieces, alpha, bias


@njit(cache=True)
def profile_at(kind, radius, pieces, alpha, bias, t):
    """``k(t)``: box ``|t| <= 1/2`` (Mitsuba's box is closed), Gaussian, or the polynomial piece of ``t``."""
    if kind == KIND_BOX:
        return 1.0 if abs(t) <= 0.5 else 0.0
    if abs(t) >= radius:
        return 0.0
    if kind == KIND_GAUSSIAN:
        return max(0.0, math.exp(alpha * t * t) - bias)
    p = int(math.floor(t))
    r = pieces.shape[0] // 2
    s = t - (p + 0.5)
    row = p + r
    value = 0.0
    for a in range(pieces.shape[1] - 1, -1, -1):  # Horner in the piece's local variable
        value = value * s + pieces[row, a]
    return value


@njit(cache=True)
def profile_array(kind, radius, pieces, alpha, bias, t):
    """:func:`profile_at` over a flat array."""
    out = np.empty(t.size)
    for i in range(t.size):
        out[i] = profile_at(kind, radius, pieces, alpha, bias, t[i])
    return out
