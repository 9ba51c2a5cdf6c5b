"""Polygon clipping against a line, with Catmull's clip flags (numba kernels).

A polygon is a run of vertices ``xs[start:start+n], ys[...]`` with a flag per vertex:
``flags[i] = 1`` when the edge from vertex i to the next lies on a clipping line (or a
pixel boundary) and so must never be chosen as a clipping edge again. Lines are
``a x + b y + c = 0`` with ``(a, b)`` a unit normal; side A is ``d < 0``, side B ``d > 0``
(Catmull 1978, "The Clipping Algorithm"), and points within ``EPS_LINE`` of the line
belong to both sides, so no near-duplicate vertices are made.
"""

from __future__ import annotations

from aaeval._jit import kernel

# Distance (pixels) under which a point counts as lying on a clipping line: far above
# float64 rounding of pixel coordinates, far below any area the tests resolve.
EPS_LINE = 1e-11


@kernel(inline="always")
def _side(d):
    if d < -EPS_LINE:
        return -1
    if d > EPS_LINE:
        return 1
    return 0


@kernel(inline="always")
def clip_split(xs, ys, fs, start, n, a, b, c, want_a, want_b,
               axs, ays, afs, astart, bxs, bys, bfs, bstart):
    """Split a polygon by a line into its side-A and side-B parts in one pass.

    Writes the wanted parts at ``astart`` / ``bstart`` and returns their vertex counts
    ``(ma, mb)`` (0 for a part not wanted or with fewer than 3 vertices; the caller checks
    the area, since a part may also degenerate to a line). Edges lying on the line get
    flag 1; the others keep the flag of the edge they are part of.
    """
    ma = 0
    mb = 0
    # one exit only: an early return keeps the array arguments' reference counts alive
    if n > 0:
        prev = start + n - 1
        dp = a * xs[prev] + b * ys[prev] + c
        sp = _side(dp)
        for i in range(start, start + n):
            d = a * xs[i] + b * ys[i] + c
            s = _side(d)
            if sp * s < 0:
                # strict crossing: the intersection belongs to both parts; the edge leaving
                # it continues the original edge prev->i (2 marks "on the line" until the end)
                t = dp / (dp - d)
                x = xs[prev] + t * (xs[i] - xs[prev])
                y = ys[prev] + t * (ys[i] - ys[prev])
                if b == 0.0:
                    x = -c / a
                elif a == 0.0:
                    y = -c / b
                if want_a:
                    axs[astart + ma] = x
                    ays[astart + ma] = y
                    afs[astart + ma] = 2 + fs[prev]
                    ma += 1
                if want_b:
                    bxs[bstart + mb] = x
                    bys[bstart + mb] = y
                    bfs[bstart + mb] = 2 + fs[prev]
                    mb += 1
            on = 2 if s == 0 else 0
            if want_a and s <= 0:
                axs[astart + ma] = xs[i]
                ays[astart + ma] = ys[i]
                afs[astart + ma] = on + fs[i]
                ma += 1
            if want_b and s >= 0:
                bxs[bstart + mb] = xs[i]
                bys[bstart + mb] = ys[i]
                bfs[bstart + mb] = on + fs[i]
                mb += 1
            prev = i
            dp = d
            sp = s
    return _settle_flags(afs, astart, ma), _settle_flags(bfs, bstart, mb)


@kernel(inline="always")
def _settle_flags(ofs, ostart, m):
    """An output edge lies on the line when both its ends do; else it keeps its flag."""
    if m < 3:
        return 0
    first_on = ofs[ostart] >= 2
    for k in range(m):
        cur = ofs[ostart + k]
        nxt_on = first_on if k == m - 1 else ofs[ostart + k + 1] >= 2
        if cur >= 2 and nxt_on:
            ofs[ostart + k] = 1
        else:
            ofs[ostart + k] = cur & 1
    return m


@kernel(inline="always")
def clip_side(xs, ys, fs, start, n, a, b, c, keep, oxs, oys, ofs, ostart):
    """Write the part of a polygon on side ``keep`` (-1: A, +1: B) of a line.

    Returns its vertex count (0 if nothing is left); see :func:`clip_split`.
    """
    ma, mb = clip_split(xs, ys, fs, start, n, a, b, c, keep < 0, keep > 0,
                        oxs, oys, ofs, ostart, oxs, oys, ofs, ostart)
    return ma if keep < 0 else mb


@kernel(inline="always")
def clip_to_column(xs, ys, fs, start, n, x0, oxs, oys, ofs, at, tmp):
    """Write the part of a polygon inside the pixel column ``x0 <= x <= x0 + 1`` at ``at``.

    The first clip (side B of ``x = x0``) goes to the scratch space at ``tmp``, which
    must not overlap the result: leave ``2 n + 4`` entries from each. Returns the vertex
    count (0 if nothing is left).
    """
    m1 = clip_side(xs, ys, fs, start, n, 1.0, 0.0, -x0, 1, oxs, oys, ofs, tmp)
    return clip_side(oxs, oys, ofs, tmp, m1, 1.0, 0.0, -(x0 + 1.0), -1, oxs, oys, ofs, at)


@kernel(inline="always")
def signed_area(xs, ys, start, n):
    """Shoelace area; positive for the orientation every polygon is normalised to."""
    s = 0.0
    x0 = xs[start]
    y0 = ys[start]
    for i in range(start + 1, start + n - 1):
        s += (xs[i] - x0) * (ys[i + 1] - y0) - (xs[i + 1] - x0) * (ys[i] - y0)
    return 0.5 * s


@kernel(inline="always")
def area_centroid(xs, ys, start, n):
    """Signed area and area centroid of a polygon (fan from its first vertex)."""
    x0 = xs[start]
    y0 = ys[start]
    s = 0.0
    sx = 0.0
    sy = 0.0
    for i in range(start + 1, start + n - 1):
        ax = xs[i] - x0
        ay = ys[i] - y0
        bx = xs[i + 1] - x0
        by = ys[i + 1] - y0
        cross = ax * by - bx * ay
        s += cross
        sx += cross * (ax + bx)
        sy += cross * (ay + by)
    if s == 0.0:
        return 0.0, x0, y0
    return 0.5 * s, x0 + sx / (3.0 * s), y0 + sy / (3.0 * s)
