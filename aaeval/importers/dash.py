"""Dashes: a stroke's subpaths cut into the dashes of ``stroke-dasharray`` (SVG 2, 13.5.7).

Each subpath is measured along its true segments (an arc-length table of
:data:`SAMPLES` chords per curved segment: the chords' total is within a relative
``1/(24 SAMPLES^2)`` of the arc length for a segment turning by less than a radian per
chord), the pattern is laid along it from ``stroke-dashoffset`` (restarting at every
subpath; on a closed subpath a dash over its start is one dash, joined there), and every
dash becomes an open subpath of sub-segments: lines cut at their
points, Béziers by de Casteljau's construction, elliptical arcs at their angles. The
dashes are then stroked like any open subpath, each with its caps; a dash of length
zero is a dot (round caps) or a square (square caps), nothing with butt caps.
"""

from __future__ import annotations

import numpy as np

from aaeval.importers.stroke import Seg

__all__ = ["dash_subpaths", "path_length", "SAMPLES"]

SAMPLES = 256


def _table(seg: Seg) -> tuple[np.ndarray, np.ndarray]:
    """(parameters, cumulative length) along one segment."""
    if seg.kind == "line":
        t = np.array([0.0, 1.0])
        return t, np.array([0.0, float(np.hypot(*(seg.end - seg.start)))])
    t = np.linspace(0.0, 1.0, SAMPLES + 1)
    points = seg.points(t)
    steps = np.hypot(*np.diff(points, axis=0).T)
    return t, np.concatenate([[0.0], np.cumsum(steps)])


def path_length(subpaths) -> float:
    """The length of every subpath together (for ``pathLength``)."""
    return float(sum(_table(seg)[1][-1] for segs, _ in subpaths for seg in segs))


def _split_bezier(ctrl: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    """de Casteljau: the control points of the parts before and after ``t``."""
    left, right = [ctrl[0]], [ctrl[-1]]
    points = ctrl
    while len(points) > 1:
        points = (1 - t) * points[:-1] + t * points[1:]
        left.append(points[0])
        right.append(points[-1])
    return np.array(left), np.array(right[::-1])


def sub_segment(seg: Seg, t0: float, t1: float) -> Seg:
    """The part of ``seg`` between parameters ``t0 <= t1``."""
    if seg.kind == "line":
        return Seg("line", seg.points(np.array([t0, t1])) if (t0, t1) != (0.0, 1.0) else seg.ctrl)
    if seg.kind == "arc":
        cx, cy, rx, ry, rot, start, sweep = seg.arc
        ends = seg.points(np.array([t0, t1]))
        return Seg("arc", ends, (cx, cy, rx, ry, rot, start + sweep * t0, sweep * (t1 - t0)))
    ctrl = seg.ctrl
    if t1 < 1.0:
        ctrl = _split_bezier(ctrl, t1)[0]
    if t0 > 0.0:
        ctrl = _split_bezier(ctrl, t0 / t1 if t1 > 0 else 0.0)[1]
    return Seg("bezier", ctrl)


def _piece(segs, tables, starts, a: float, b: float) -> list[Seg]:
    """The sub-segments of one subpath between lengths ``a <= b`` along it."""
    out = []
    for seg, (t, cum), s0 in zip(segs, tables, starts):
        length = cum[-1]
        lo, hi = max(a - s0, 0.0), min(b - s0, length)
        if hi < lo or (hi == lo and out):
            continue
        t0 = float(np.interp(lo, cum, t)) if length > 0 else 0.0
        t1 = float(np.interp(hi, cum, t)) if length > 0 else 0.0
        out.append(sub_segment(seg, t0, t1))
        if b - s0 <= length:
            break
    return out


def dash_subpaths(subpaths, pattern, offset: float, budget=lambda n: None) -> list[tuple[list[Seg], bool]]:
    """The dashes of ``pattern`` (positive lengths, summing to more than zero; an odd
    count is repeated, as SVG says) along each subpath, from ``offset``: open subpaths.
    ``budget(n)`` is told of every dash before it is made."""
    pattern = [float(v) for v in pattern]
    if len(pattern) % 2:
        pattern = pattern * 2
    period = sum(pattern)
    out = []
    for segs, closed in subpaths:
        tables = [_table(seg) for seg in segs]
        lengths = [cum[-1] for _, cum in tables]
        starts = np.concatenate([[0.0], np.cumsum(lengths)])[:-1]
        total = float(sum(lengths))
        phase = float(offset) % period
        k, remaining = 0, pattern[0]
        while phase > 0:  # where the offset falls in the pattern (a dash of zero length at 0 stays)
            if remaining <= phase:
                phase -= remaining
                k = (k + 1) % len(pattern)
                remaining = pattern[k]
            else:
                remaining, phase = remaining - phase, 0.0
        s = 0.0
        dashes: list[tuple[float, float]] = []
        while True:
            e = min(total, s + remaining)
            if k % 2 == 0:
                budget(4)
                dashes.append((s, e))
            if e >= total:
                break
            s = e
            k = (k + 1) % len(pattern)
            remaining = pattern[k]
        pieces = [_piece(segs, tables, starts, a, b) for a, b in dashes]
        if closed and len(dashes) > 1 and dashes[0][0] == 0.0 and dashes[-1][1] == total and total > 0:
            # a dash over the start of a closed subpath is one dash, joined there (as Skia and browsers dash)
            pieces = [pieces[-1] + pieces[0]] + pieces[1:-1]
        elif closed and len(dashes) == 1 and dashes[0] == (0.0, total) and total > 0:
            out.append((list(segs), True))
            continue
        out.extend((piece, False) for piece in pieces if piece)
    return out
