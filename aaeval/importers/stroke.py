"""Stroke outlines from the true curves: offsets, joins and caps (SVG stroke geometry).

SVG's stroke is the area swept by a segment of the stroke width held normal to the path,
plus a join where two segments meet and a cap at each end of an open subpath. It is built
here from the segments themselves, never from their flattened chords:

- Each segment (line, quadratic or cubic Bézier, elliptical arc) is sampled at parameters
  where the curve and both offset curves (``p(t) ± d n(t)``, ``d`` half the width, ``n``
  the true unit normal) stay within the tolerance of their chords: an interval is halved
  until the curve and both offsets at a quarter, the middle and three quarters of it lie
  within ``tol`` of the chords and the tangent turns by at most :data:`MAX_TURN` over it.
  Consecutive samples give quadrilaterals (the swept band between two normals); where two
  normals cross (the inner offset folds back, radius of curvature under ``d``), the band is
  the two triangles on either side of the crossing, as the sweep covers it.
- Joins are decided on the true tangents at the join: the end tangent of one segment and
  the start tangent of the next, each taken from the next distinct control point where the
  first one coincides with the end point (``C1 == P0``). Miter ratio ``1/cos(a/2)`` for a
  turn of ``a`` against ``stroke-miterlimit``; bevel beyond it; round joins as the circular
  sector on the outer side, inscribed within ``tol``.
- Caps: butt, square (half a width beyond the end along the end tangent), round (a half
  disc). Where a cubic stops and turns back inside a segment (a cusp: its derivative
  vanishes), a disc of the stroke width is added, a round join over the reversal, as Skia
  and GTK draw it. A subpath of zero length draws a dot with round caps and an axis-aligned square
  with square caps, as SVG says.

Every piece is a positively oriented ring, so their union is the nonzero fill of all of
them, resolved in float64 by :func:`aaeval.importers.fill.resolve_fill`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from aaeval.importers.fillrings import ring_area

__all__ = ["Seg", "stroke_pieces", "MAX_TURN"]

MAX_TURN = math.pi / 8  # most the tangent may turn within one sampled interval
MAX_DEPTH = 30


@dataclass(frozen=True)
class Seg:
    """One path segment in absolute pixel coordinates.

    ``kind`` is ``"line"``, ``"bezier"`` (``ctrl`` holds 2, 3 or 4 points) or ``"arc"``
    (``arc`` = (cx, cy, rx, ry, rotation, start, sweep), the point at t being
    ``c + R(rotation) (rx cos(start + sweep t), ry sin(start + sweep t))``).
    """

    kind: str
    ctrl: np.ndarray  # (k, 2); for an arc its start and end points
    arc: tuple | None = None

    @property
    def start(self) -> np.ndarray:
        return self.ctrl[0]

    @property
    def end(self) -> np.ndarray:
        return self.ctrl[-1]

    def degenerate(self) -> bool:
        if self.kind == "arc":
            cx, cy, rx, ry, rot, start, sweep = self.arc
            return sweep == 0 or (rx == 0 and ry == 0)
        return bool(np.all(self.ctrl == self.ctrl[0]))

    def _arc(self, t: np.ndarray, *, derivative: bool) -> np.ndarray:
        """The arc's points at ``t`` (or their derivative): the ellipse's own axes turned by
        its rotation, and moved to its centre for points."""
        cx, cy, rx, ry, rot, start, sweep = self.arc
        th = start + sweep * t
        c, s = math.cos(rot), math.sin(rot)
        if derivative:
            x, y = -rx * np.sin(th) * sweep, ry * np.cos(th) * sweep
            return np.column_stack([c * x - s * y, s * x + c * y])
        x, y = rx * np.cos(th), ry * np.sin(th)
        return np.column_stack([cx + c * x - s * y, cy + s * x + c * y])

    def points(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=np.float64)
        if self.kind == "arc":
            out = self._arc(t, derivative=False)
            out[t == 0.0] = self.ctrl[0]
            out[t == 1.0] = self.ctrl[-1]
            return out
        k = len(self.ctrl) - 1
        basis = np.stack([math.comb(k, i) * t**i * (1 - t) ** (k - i) for i in range(k + 1)], axis=1)
        out = basis @ self.ctrl
        out[t == 0.0] = self.ctrl[0]
        out[t == 1.0] = self.ctrl[-1]
        return out

    def derivative(self, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=np.float64)
        if self.kind == "arc":
            return self._arc(t, derivative=True)
        k = len(self.ctrl) - 1
        diff = k * np.diff(self.ctrl, axis=0)
        if k == 1:
            return np.repeat(diff, len(t), axis=0)
        basis = np.stack([math.comb(k - 1, i) * t**i * (1 - t) ** (k - 1 - i) for i in range(k)], axis=1)
        return basis @ diff

    def cusps(self) -> list[float]:
        """Parameters in (0, 1) where a cubic's derivative vanishes: the curve stops and turns
        back (its tangent reverses)."""
        if self.kind != "bezier" or len(self.ctrl) != 4:
            return []
        p0, p1, p2, p3 = self.ctrl
        # B'(t)/3 = a t^2 + b t + c per coordinate
        a = -p0 + 3 * p1 - 3 * p2 + p3
        b = 2 * (p0 - 2 * p1 + p2)
        c = p1 - p0
        scale = max(1.0, float(np.abs(self.ctrl).max()))
        out = []
        for k in (0, 1):
            roots = np.roots([a[k], b[k], c[k]]) if np.any([a[k], b[k], c[k]]) else np.array([])
            for r in roots:
                if abs(r.imag) > 1e-12 or not (0.0 < r.real < 1.0):
                    continue
                t = float(r.real)
                d = a * t * t + b * t + c
                if math.hypot(d[0], d[1]) <= 1e-9 * scale and all(abs(t - u) > 1e-9 for u in out):
                    out.append(t)
        return sorted(out)

    def tangents(self, t: np.ndarray) -> np.ndarray:
        """Unit tangents at ``t``; where the derivative vanishes (a control point on an end
        point, a cusp), the direction the curve actually leaves or enters in."""
        t = np.asarray(t, dtype=np.float64)
        if self.kind == "line":
            d = self.ctrl[-1] - self.ctrl[0]
            return np.repeat((d / math.hypot(d[0], d[1]))[None, :], len(t), axis=0)
        d = self.derivative(t)
        norm = np.hypot(d[:, 0], d[:, 1])
        scale = max(1.0, float(np.abs(self.ctrl).max()))
        bad = norm <= 1e-12 * scale
        for k in np.flatnonzero(bad):
            d[k] = self._fallback_direction(float(t[k]))
        norm = np.hypot(d[:, 0], d[:, 1])
        norm[norm == 0] = 1.0
        return d / norm[:, None]

    def _fallback_direction(self, t: float) -> np.ndarray:
        if self.kind == "arc" and self.arc[6] != 0:
            # a sliver of an arc (a dash ending on a segment's end leaves one) still has the
            # ellipse's direction: the derivative per unit of angle, which does not vanish
            return self.derivative(np.array([t]))[0] / abs(self.arc[6])
        if self.kind == "bezier" and t <= 0.0:
            for p in self.ctrl[1:]:
                if np.any(p != self.ctrl[0]):
                    return p - self.ctrl[0]
        if self.kind == "bezier" and t >= 1.0:
            for p in self.ctrl[-2::-1]:
                if np.any(p != self.ctrl[-1]):
                    return self.ctrl[-1] - p
        h = 1e-7
        a, b = max(0.0, t - h), min(1.0, t + h)
        pa, pb = self.points(np.array([a, b]))
        return pb - pa


def _seg_dist(p, a, b):
    """Distance of points p from segments a-b (all (n, 2))."""
    d = b - a
    l2 = (d * d).sum(axis=1)
    safe = np.where(l2 > 0, l2, 1.0)
    t = np.clip(((p - a) * d).sum(axis=1) / safe, 0.0, 1.0)
    t = np.where(l2 > 0, t, 0.0)
    q = a + t[:, None] * d
    return np.hypot(p[:, 0] - q[:, 0], p[:, 1] - q[:, 1])


def sample(seg: Seg, d: float, tol: float, budget) -> np.ndarray:
    """Parameters (sorted, 0 and 1 included) at which the curve and its two offsets at
    distance ``d`` stay within ``tol`` of their chords and turn by at most MAX_TURN."""
    if seg.kind == "line":
        return np.array([0.0, 1.0])
    t0 = np.array([0.0])
    t1 = np.array([1.0])
    done = []
    for depth in range(MAX_DEPTH + 1):
        if len(t0) == 0:
            break
        budget(len(t0))
        ends = np.concatenate([t0, t1])
        probes = np.concatenate([t0 + (t1 - t0) * f for f in (0.25, 0.5, 0.75)])
        p_end, n_end = seg.points(ends), _normals(seg.tangents(ends))
        p_pr, n_pr = seg.points(probes), _normals(seg.tangents(probes))
        m = len(t0)
        ok = np.ones(m, dtype=bool)
        for sgn in (0.0, 1.0, -1.0):
            a = p_end[:m] + sgn * d * n_end[:m]
            b = p_end[m:] + sgn * d * n_end[m:]
            for f in range(3):
                q = p_pr[f * m:(f + 1) * m] + sgn * d * n_pr[f * m:(f + 1) * m]
                ok &= _seg_dist(q, a, b) <= tol
        turn = np.arccos(np.clip((n_end[:m] * n_end[m:]).sum(axis=1), -1.0, 1.0))
        mid_turn = np.arccos(np.clip((n_end[:m] * n_pr[m:2 * m]).sum(axis=1), -1.0, 1.0))
        ok &= (turn <= MAX_TURN) & (mid_turn <= MAX_TURN)
        if depth == MAX_DEPTH:
            ok[:] = True
        done.append(t1[ok])
        mid = 0.5 * (t0[~ok] + t1[~ok])
        t0, t1 = np.concatenate([t0[~ok], mid]), np.concatenate([mid, t1[~ok]])
    ts = np.unique(np.concatenate([[0.0], *done]))
    return ts


def _normals(tangent: np.ndarray) -> np.ndarray:
    """Left normals (the tangent turned by +90 degrees in x-right, y-up terms)."""
    return np.column_stack([-tangent[:, 1], tangent[:, 0]])


def _positive(ring: np.ndarray) -> np.ndarray | None:
    a = ring_area(ring)
    if a == 0.0:
        return None
    return ring if a > 0 else ring[::-1]


def _cross2(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _band(seg: Seg, d: float, tol: float, budget) -> list[np.ndarray]:
    """The area swept by the normal segment of half-length d along one segment."""
    if seg.kind == "line":  # a rectangle (the common case, kept cheap)
        a, b = seg.ctrl[0], seg.ctrl[-1]
        t = b - a
        t = t / math.hypot(t[0], t[1])
        n = d * np.array([-t[1], t[0]])
        budget(4)
        ring = _positive(np.array([a - n, b - n, b + n, a + n]))
        return [] if ring is None else [ring]
    ts = sample(seg, d, tol, budget)
    p = seg.points(ts)
    n = _normals(seg.tangents(ts))
    L, R = p + d * n, p - d * n
    budget(2 * len(ts))
    # quad k: R_k, R_k+1, L_k+1, L_k. Its normals (R_k-L_k and R_k+1-L_k+1) cross where
    # the inner offset folds back.
    a, b, c, e = R[:-1], R[1:], L[1:], L[:-1]
    # do normals k and k+1 cross? (segments R_k L_k and R_k+1 L_k+1)
    u = e - a
    v = c - b
    denom = _cross2(u, v)
    w = b - a
    with np.errstate(divide="ignore", invalid="ignore"):
        s = _cross2(w, v) / denom
        r = _cross2(w, u) / denom
    crossing = (denom != 0) & (s > 0) & (s < 1) & (r > 0) & (r < 1)
    quad_area = 0.5 * (_cross2(a, b) + _cross2(b, c) + _cross2(c, e) + _cross2(e, a))
    sign = np.sign(quad_area[~crossing])
    if not crossing.any() and (len(sign) == 0 or np.all(sign == sign[0])) and (len(sign) == 0 or sign[0] != 0):
        ring = np.concatenate([R, L[::-1]])
        ring = _positive(_dedupe(ring))
        return [] if ring is None else [ring]
    pieces = []
    for k in range(len(a)):
        if crossing[k]:
            x = a[k] + s[k] * u[k]
            for tri in (np.array([a[k], b[k], x]), np.array([x, c[k], e[k]])):
                t = _positive(tri)
                if t is not None:
                    pieces.append(t)
        else:
            q = _positive(_dedupe(np.array([a[k], b[k], c[k], e[k]])))
            if q is not None:
                pieces.append(q)
    return pieces


def _dedupe(ring: np.ndarray) -> np.ndarray:
    keep = np.any(ring != np.roll(ring, 1, axis=0), axis=1)
    return ring[keep] if keep.any() else ring[:1]


def _arc_fan(centre, d, a0: float, sweep: float, tol: float) -> np.ndarray:
    """Points on the circle of radius d from angle a0 through sweep (both ends included),
    chords within tol of the circle."""
    step = 2.0 * math.acos(max(-1.0, 1.0 - tol / d)) if d > tol else math.pi / 2
    n = max(1, int(math.ceil(abs(sweep) / min(step, math.pi / 2))))
    ang = a0 + sweep * np.arange(n + 1) / n
    return np.column_stack([centre[0] + d * np.cos(ang), centre[1] + d * np.sin(ang)])


def _join(p, t_in, t_out, d, join: str, miter_limit: float, tol: float) -> list[np.ndarray]:
    cross = float(_cross2(t_in, t_out))
    dot = float(np.dot(t_in, t_out))
    if cross == 0.0 and dot > 0.0:
        return []
    sigma = -1.0 if cross > 0 else 1.0  # the outer side: right of a left turn
    n_in = sigma * np.array([-t_in[1], t_in[0]])
    n_out = sigma * np.array([-t_out[1], t_out[0]])
    pa, pb = p + d * n_in, p + d * n_out
    turn = math.atan2(abs(cross), dot)  # 0..pi
    if join == "round":
        a0 = math.atan2(n_in[1], n_in[0])
        sweep = turn if cross > 0 else -turn
        if cross == 0.0:  # a full reversal: the half disc ahead
            sweep = math.pi if _cross2(n_in, t_in) > 0 else -math.pi
        fan = _arc_fan(p, d, a0, sweep, tol)
        piece = _positive(np.concatenate([[p], fan]))
        return [] if piece is None else [piece]
    if join == "miter" and turn < math.pi:
        ratio = 1.0 / math.cos(turn / 2.0)
        if ratio <= miter_limit:
            bis = n_in + n_out
            bis /= math.hypot(bis[0], bis[1])
            tip = p + d * ratio * bis
            piece = _positive(np.array([p, pa, tip, pb]))
            return [] if piece is None else [piece]
    piece = _positive(np.array([p, pa, pb]))
    return [] if piece is None else [piece]


def _cap(p, t, d, cap: str, tol: float, at_end: bool) -> list[np.ndarray]:
    """Cap at point p; t is the tangent pointing out of the stroke (forward at the end,
    backward at the start)."""
    if cap == "butt":
        return []
    n = np.array([-t[1], t[0]])
    if cap == "square":
        ring = np.array([p + d * n, p + d * n + d * t, p - d * n + d * t, p - d * n])
        piece = _positive(ring)
        return [] if piece is None else [piece]
    a0 = math.atan2(n[1], n[0])
    fan = _arc_fan(p, d, a0, -math.pi, tol)  # from +n through t to -n
    piece = _positive(fan)
    return [] if piece is None else [piece]


def _dot(p, d, cap: str, tol: float) -> list[np.ndarray]:
    if cap == "round":
        return [_positive(_arc_fan(p, d, 0.0, 2 * math.pi, tol)[:-1])]
    if cap == "square":
        return [_positive(np.array([p + (-d, -d), p + (d, -d), p + (d, d), p + (-d, d)]))]
    return []


def stroke_pieces(subpaths, width: float, *, cap: str = "butt", join: str = "miter",
                  miter_limit: float = 4.0, tol: float, budget=lambda n: None) -> list[np.ndarray]:
    """Positively oriented rings whose union is the stroke of the subpaths.

    ``subpaths`` is a sequence of (segments, closed). ``budget(n)`` is called with the
    number of vertices about to be made (it raises to stop a run over the limit).
    """
    d = 0.5 * float(width)
    pieces: list[np.ndarray] = []
    for segments, closed in subpaths:
        if not segments:
            continue
        live = [s for s in segments if not s.degenerate()]
        if not live:
            pieces.extend(p for p in _dot(np.asarray(segments[0].start, float), d, cap, tol) if p is not None)
            continue
        starts = [s.tangents(np.array([0.0]))[0] for s in live]
        ends = [s.tangents(np.array([1.0]))[0] for s in live]
        for s in live:
            pieces.extend(_band(s, d, tol, budget))
            for t in s.cusps():  # the tangent reverses: a round join over the turn, as Skia
                # and GTK draw it (the sweep already covers the half behind the cusp)
                pieces.extend(p for p in _dot(s.points(np.array([t]))[0], d, "round", tol) if p is not None)
        for k in range(len(live) - 1):
            pieces.extend(_join(live[k].end, ends[k], starts[k + 1], d, join, miter_limit, tol))
        if closed:
            pieces.extend(_join(live[-1].end, ends[-1], starts[0], d, join, miter_limit, tol))
        else:
            pieces.extend(_cap(live[0].start, -starts[0], d, cap, tol, False))
            pieces.extend(_cap(live[-1].end, ends[-1], d, cap, tol, True))
    return [p for p in pieces if p is not None and len(p) >= 3]
