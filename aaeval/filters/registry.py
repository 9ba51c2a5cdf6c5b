"""The one registry of pixel reconstruction filters, defined exactly as Mitsuba 3 defines them.

A filter is separable: the weight of a point ``(x, y)`` for the pixel centred at
``(cx, cy)`` is ``k(x - cx) * k(y - cy)`` with a one-dimensional profile ``k`` of
radius ``R``. Pixel centres sit at ``i + 1/2``, so the knots of a filter with integer
knots (tent, cubics) sit on the half-integer grid, and the unit cells between them are
``[m - 1/2, m + 1/2]`` for integer ``m``. Each filter is stored in the form the exact
integrator needs:

- piecewise-polynomial filters (tent, B-spline, Mitchell, Catmull-Rom): ``pieces[p + R]``
  holds the power-basis coefficients of ``k`` on ``[p, p + 1]`` in the local variable
  ``s = t - (p + 1/2)`` in ``[-1/2, 1/2]``, i.e. around the cell's own centre;
- the Gaussian: ``stddev``; Mitsuba cuts it at 4 stddev and subtracts the value there.

See ``docs/filters.md`` for Mitsuba's source and how its film normalises and treats the
image border (each pixel divided by the filter weight it collected inside the image).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np
from numpy.polynomial import Polynomial

from aaeval.filters.evaluate import profile_array
from aaeval.options import Registry

__all__ = [
    "PixelFilter",
    "FILTERS",
    "register_filter",
    "DEFAULT_FILTER",
    "KIND_BOX",
    "KIND_POLYNOMIAL",
    "KIND_GAUSSIAN",
    "filter_names",
    "get_filter",
    "axis_weights",
    "profile_args",
]

KIND_BOX = 0
KIND_POLYNOMIAL = 1
KIND_GAUSSIAN = 2


@dataclass(frozen=True)
class PixelFilter:
    """A registered reconstruction filter.

    Attributes
    ----------
    name : str
        Registry name (``catmull:filter=NAME``).
    summary : str
        One line: what it is and where the definition comes from.
    kind : int
        :data:`KIND_BOX`, :data:`KIND_POLYNOMIAL` or :data:`KIND_GAUSSIAN`.
    radius : float
        Support of the 1D profile: ``k(t) = 0`` for ``|t| >= radius``.
    mitsuba : Mapping
        The ``rfilter`` dictionary that makes Mitsuba 3's film use the same filter.
    pieces : ndarray, shape (2R, degree + 1)
        Polynomial filters: coefficients per unit piece in the cell-local variable.
    stddev : float
        Gaussian: standard deviation in pixels (0 for the others).
    partition_of_unity : bool
        Whether ``sum_i k(t - i) == 1`` for every t, so that the intensity sum of an image
        is invariant under sub-pixel translation (away from the border).
    """

    name: str
    summary: str
    kind: int
    radius: float
    mitsuba: Mapping
    pieces: np.ndarray = field(default_factory=lambda: np.zeros((0, 1)))
    stddev: float = 0.0
    partition_of_unity: bool = True

    @property
    def knot_radius(self) -> int:
        """Number of unit cells on each side of a pixel centre the support reaches."""
        return int(math.ceil(self.radius))

    @property
    def gaussian_alpha_bias(self) -> tuple[float, float]:
        """Mitsuba's Gaussian ``k(t) = max(0, exp(alpha t^2) - bias)``."""
        alpha = -1.0 / (2.0 * self.stddev * self.stddev)
        return alpha, math.exp(alpha * self.radius * self.radius)

    def profile(self, t) -> np.ndarray:
        """The 1D profile ``k(t)`` (vectorised; :func:`aaeval.filters.evaluate.profile_at`)."""
        t = np.asarray(t, dtype=np.float64)
        return profile_array(*profile_args(self), np.ascontiguousarray(t.ravel())).reshape(t.shape)

    def integral(self, a, b) -> np.ndarray:
        """``∫_a^b k(t) dt`` exactly (vectorised over ``a``, ``b``)."""
        a = np.asarray(a, dtype=np.float64)
        b = np.asarray(b, dtype=np.float64)
        return self._primitive(b) - self._primitive(a)

    def _primitive(self, t):
        """An antiderivative of ``k`` that is constant outside the support."""
        if self.kind == KIND_BOX:
            return np.clip(t, -0.5, 0.5)
        if self.kind == KIND_GAUSSIAN:
            alpha, bias = self.gaussian_alpha_bias
            tc = np.clip(t, -self.radius, self.radius)
            c = math.sqrt(-alpha)
            return (math.sqrt(math.pi) / (2.0 * c)) * _erf(c * tc) - bias * tc
        r = self.knot_radius
        tc = np.clip(t, -r, r)
        p = np.clip(np.floor(tc).astype(np.int64), -r, r - 1)
        total = np.zeros_like(tc)
        # whole pieces left of p, then the part of piece p up to t
        whole = np.array([_piece_integral(self.pieces[q], -0.5, 0.5) for q in range(2 * r)])
        before = np.concatenate([[0.0], np.cumsum(whole)])
        total = before[p + r] + _piece_integral(self.pieces[p + r], -0.5, tc - (p + 0.5))
        return total


def profile_args(filt: PixelFilter) -> tuple:
    """``(kind, radius, pieces, alpha, bias)`` of ``filt``: what the native profile
    (:func:`aaeval.filters.evaluate.profile_at`) and the samplers' splat take."""
    alpha, bias = filt.gaussian_alpha_bias if filt.kind == KIND_GAUSSIAN else (0.0, 0.0)
    pieces = np.ascontiguousarray(filt.pieces if filt.pieces.size else np.zeros((1, 1)), dtype=np.float64)
    return filt.kind, float(filt.radius), pieces, alpha, bias


def _erf(x):
    from scipy.special import erf

    return erf(x)


def _piece_integral(coeffs, lo, hi):
    """``∫_lo^hi sum_a coeffs[..., a] s^a ds`` for coefficient rows (vectorised)."""
    coeffs = np.asarray(coeffs)
    total = 0.0
    for a in range(coeffs.shape[-1]):
        total = total + coeffs[..., a] * (np.power(hi, a + 1) - np.power(lo, a + 1)) / (a + 1)
    return total


def _pieces_from_abs(inner: Polynomial, outer: Polynomial | None, radius: int) -> np.ndarray:
    """Cell-local coefficients of a symmetric profile given in ``|t|``.

    ``inner`` holds on ``|t| < 1``, ``outer`` on ``1 <= |t| < 2`` (radius 2 only).
    """
    degree = max(inner.degree(), outer.degree() if outer is not None else 0)
    rows = []
    for p in range(-radius, radius):
        centre = p + 0.5
        sign = 1.0 if p >= 0 else -1.0
        lo = p if p >= 0 else -p - 1  # |t| runs over [lo, lo + 1] on this piece
        poly = inner if lo == 0 else outer
        local = poly(Polynomial([sign * centre, sign]))  # |t| = sign * (s + centre)
        coef = np.zeros(degree + 1)
        coef[: len(local.coef)] = local.coef
        rows.append(coef)
    return np.array(rows)


def _mitchell(b: float, c: float) -> tuple[Polynomial, Polynomial]:
    """Mitchell-Netravali (1988) cubic in ``|t|``, as in Mitsuba's ``mitchell.cpp``."""
    inner = Polynomial([6 - 2 * b, 0.0, -18 + 12 * b + 6 * c, 12 - 9 * b - 6 * c]) / 6
    outer = Polynomial([8 * b + 24 * c, -12 * b - 48 * c, 6 * b + 30 * c, -b - 6 * c]) / 6
    return inner, outer


#: Every pixel filter, by name, in registration order (:func:`register_filter`).
FILTERS: Registry = Registry("filter")


def register_filter(name: str, *args, **kwargs) -> PixelFilter:
    """Register the :class:`PixelFilter` ``PixelFilter(name, *args, **kwargs)``; a name
    registered twice is refused."""
    return FILTERS.add(name, PixelFilter(name, *args, **kwargs))


def _register_cubic(name: str, summary: str, b: float, c: float, mitsuba: Mapping) -> PixelFilter:
    return register_filter(name, summary, KIND_POLYNOMIAL, 2.0, mitsuba, _pieces_from_abs(*_mitchell(b, c), 2),
                           partition_of_unity=abs(b + 2 * c - 1) < 1e-15)


register_filter("box", "box of one pixel (Mitsuba box, radius 1/2): the exact area average", KIND_BOX, 0.5,
                {"type": "box"})
register_filter("tent", "tent (Mitsuba tent, radius 1): k(t) = max(0, 1 - |t|)", KIND_POLYNOMIAL, 1.0,
                {"type": "tent", "radius": 1.0}, _pieces_from_abs(Polynomial([1.0, -1.0]), None, 1))
_register_cubic("bspline", "cubic B-spline = Mitchell-Netravali B=1, C=0 (Mitsuba has no bspline plugin)", 1.0, 0.0,
                {"type": "mitchell", "B": 1.0, "C": 0.0})
_register_cubic("mitchell", "Mitchell-Netravali B = C = 1/3, radius 2 (Mitsuba mitchell, its defaults)",
                1.0 / 3.0, 1.0 / 3.0, {"type": "mitchell", "B": 1.0 / 3.0, "C": 1.0 / 3.0})
_register_cubic("catmullrom", "Catmull-Rom = Mitchell-Netravali B=0, C=1/2, radius 2 (Mitsuba catmullrom)", 0.0, 0.5,
                {"type": "catmullrom"})
register_filter("gaussian", "Gaussian, stddev 1/2, cut at 4 stddev with the value there subtracted "
                "(Mitsuba gaussian, Mitsuba's default filter)", KIND_GAUSSIAN, 2.0,
                {"type": "gaussian", "stddev": 0.5}, stddev=0.5, partition_of_unity=False)

DEFAULT_FILTER = "box"


def filter_names() -> tuple[str, ...]:
    """Registered filter names, in registry order."""
    return tuple(FILTERS)


def get_filter(name: str) -> PixelFilter:
    """The filter registered as ``name``; ``ValueError`` listing the valid names otherwise."""
    if name not in FILTERS:
        raise ValueError(f"unknown filter {name!r}; valid filters: {', '.join(FILTERS)}")
    return FILTERS[name]


def axis_weights(filt: PixelFilter, n: int) -> np.ndarray:
    """Filter weight each pixel of a row of ``n`` collects inside the image, ``∫_0^n k(x - i - 1/2) dx``.

    Mitsuba's film divides every pixel by the weight it accumulated, and samples lie only
    inside the image, so a border pixel is a truncated, renormalised filter: the 2D
    weight is ``axis_weights(f, W)[i] * axis_weights(f, H)[j]``.
    """
    centres = np.arange(n) + 0.5
    return filt.integral(-centres, n - centres)
