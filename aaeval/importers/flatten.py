"""Curves to polylines no finer than the pixels need: every point of the curve lies
within ``tol`` pixels of the polyline, and each segment gets only as many vertices as
its own shape asks for.

Three bounds, one per kind of curve:

- Bézier curves of degree k (quadratic, cubic): Wang's bound. Linear interpolation at n
  equal parameter steps misses the curve by at most ``h^2/8 max|B''|`` with ``h = 1/n``,
  and ``|B''| <= k (k-1) max |P[i] - 2 P[i+1] + P[i+2]|``, so
  ``n = ceil(sqrt(k (k-1) M / (8 tol)))`` steps suffice.
- Elliptical arcs: an ellipse is an affine image of the unit circle, whose arc of angle d
  leaves its chord by ``1 - cos(d/2)``; the map stretches distances by at most the larger
  radius, so steps of ``2 acos(1 - tol / r_max)`` suffice.
- Rational quadratics (conics, from Skia's round joins and caps): a conic with end points
  on a chord rises above it by at most ``w/(1+w)`` times its middle control point's
  height, at t = 1/2; it is halved until that is within ``tol``.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from aaeval.importers.limits import charge

__all__ = ["bezier_points", "arc_points", "conic_points", "bezier_steps", "DEFAULT_TOLERANCE"]

DEFAULT_TOLERANCE = 1.0 / 16.0  # pixels
# A curve never gets more steps than this (a tolerance of 1e-9 px on a 1e9 px curve).
MAX_STEPS = 1 << 16


def bezier_steps(control: np.ndarray, tol: float) -> int:
    """Equal parameter steps that keep a Bézier curve within ``tol`` of its polyline."""
    _check_tol(tol)
    k = len(control) - 1
    if k < 2:
        return 1
    if control.shape == (3, 2):
        m = _quadratic_second_difference(control)
    else:
        if not np.isfinite(control).all():
            raise ValueError(_NOT_FINITE)
        second = control[2:] - 2.0 * control[1:-1] + control[:-2]
        m = float(np.hypot(second[:, 0], second[:, 1]).max())
    return int(min(MAX_STEPS, max(1, math.ceil(math.sqrt(k * (k - 1) * m / (8.0 * tol))))))


_NOT_FINITE = "a curve has a control point that is not a finite number"


def _quadratic_second_difference(control: np.ndarray) -> float:
    """``|P0 - 2 P1 + P2|`` of a quadratic (every TrueType curve), in plain floats: the same
    operations in the same order as the array form, a third of its time on three points."""
    (x0, y0), (x1, y1), (x2, y2) = control.tolist()
    if not all(map(math.isfinite, (x0, y0, x1, y1, x2, y2))):
        raise ValueError(_NOT_FINITE)
    return float(np.hypot((x2 - 2.0 * x1) + x0, (y2 - 2.0 * y1) + y0))  # numpy's hypot, as for arrays


def bezier_points(control, tol: float) -> np.ndarray:
    """The polyline of a Bézier curve (control points (k+1, 2)), without its start point.

    Returns an (n, 2) array ending at the curve's end point.
    """
    control = np.asarray(control, dtype=np.float64)
    n = bezier_steps(control, tol)
    charge(n)
    points = _bernstein(len(control) - 1, n) @ control
    points[-1] = control[-1]  # the end point exactly, so consecutive segments join
    return points


@functools.lru_cache(maxsize=256)
def _bernstein(k: int, n: int) -> np.ndarray:
    """The degree-k Bernstein basis at t = 1/n, 2/n, ..., 1, (n, k+1): the same for every
    curve cut into n steps (a glyph's curves mostly take one to four), so made once."""
    t = np.arange(1, n + 1) / n
    basis = np.stack([math.comb(k, i) * t**i * (1 - t) ** (k - i) for i in range(k + 1)], axis=1)
    basis.flags.writeable = False
    return basis


def arc_points(centre, rx: float, ry: float, rotation: float, start: float, sweep: float, tol: float) -> np.ndarray:
    """The polyline of an elliptical arc, without its start point.

    The arc is ``centre + R(rotation) (rx cos t, ry sin t)`` for t from ``start`` to
    ``start + sweep`` (radians). Returns an (n, 2) array.
    """
    _check_tol(tol)
    r = max(abs(rx), abs(ry))
    if r <= tol:
        step = math.pi
    elif tol / r > 1e-8:
        step = 2.0 * math.acos(1.0 - tol / r)
    else:  # 1 - tol/r rounds towards 1: acos(1 - x) = sqrt(2x) (1 + x/12 + ...)
        step = 2.0 * math.sqrt(2.0 * tol / r)
    if not all(map(math.isfinite, (rx, ry, rotation, start, sweep, centre[0], centre[1]))):
        raise ValueError("an arc has a value that is not a finite number")
    steps = abs(sweep) / min(step, math.pi) if step > 0 else math.inf
    n = int(min(MAX_STEPS, max(1, math.ceil(steps)))) if steps < MAX_STEPS else MAX_STEPS
    charge(n)
    t = start + sweep * np.arange(1, n + 1) / n
    c, s = math.cos(rotation), math.sin(rotation)
    x, y = rx * np.cos(t), ry * np.sin(t)
    return np.column_stack([centre[0] + c * x - s * y, centre[1] + s * x + c * y])


def conic_points(p0, p1, p2, w: float, tol: float) -> np.ndarray:
    """The polyline of a conic (rational quadratic, weight ``w > 0``), without its start point."""
    _check_tol(tol)
    out = []
    stack = [(np.asarray(p0, float), np.asarray(p1, float), np.asarray(p2, float), float(w), 0)]
    while stack:  # depth first, second half pushed first: points come out in order
        a, b, c, w, depth = stack.pop()
        charge(1)
        if _conic_height(a, b, c) * w / (1.0 + w) <= tol or depth >= 24:
            out.append(c)
            continue
        # halve at t = 1/2; both halves keep weight sqrt((1 + w) / 2)
        m = (a + 2.0 * w * b + c) / (2.0 + 2.0 * w)
        half = math.sqrt((1.0 + w) / 2.0)
        stack.append((m, (w * b + c) / (1.0 + w), c, half, depth + 1))
        stack.append((a, (a + w * b) / (1.0 + w), m, half, depth + 1))
    return np.array(out).reshape(-1, 2)


def _conic_height(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
    """Distance of the middle control point from the chord's line (from ``a`` if a == c)."""
    chord = c - a
    length = math.hypot(chord[0], chord[1])
    d = b - a
    if length == 0.0:
        return math.hypot(d[0], d[1])
    return abs(chord[0] * d[1] - chord[1] * d[0]) / length


def _check_tol(tol: float) -> None:
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise ValueError(f"flattening tolerance must be a positive number of pixels, got {tol!r}")
