"""Catmull 1978 scanline hidden-surface algorithm with the pixel integrator (numba).

The structure follows the paper's "Hidden-surface Algorithm":

I.   polygons are sorted on their highest y (smallest y here: y grows downward);
II.  an active polygon list starts empty;
III. for each scanline (a strip one pixel high)
     A. polygons entering on this scanline join the active list;
     C. from each active polygon the strip piece on this scanline is clipped off and the
        polygon replaced by what remains below; the exact area of the piece over every
        pixel column it spans is found (the edge integral -∫ y dx per column), which
        splits it into a solid run (pixels it covers completely) and irregular pieces;
        pieces go into an x-bucket by their leftmost pixel;
     E. sweeping the pixels, pieces move from the x-bucket into the z-list, which is kept
        sorted front to back; the pixel is then evaluated:
        - a solid piece in front of everything: its colour;
        - one irregular piece in front of a solid one: the two weighted by area;
        - otherwise the pixel integrator.

The pixel integrator recursively clips the pixel's polygon list against the first
unclipped edge of the front polygon (clip flags mark edges that lie on clipping lines
or pixel boundaries), with a dummy solid background polygon last. When the front
polygon is clipped on all sides it covers the whole region of its list, and its colour
weighted by its area is returned. Interpenetrating polygons are handled where the paper
says to: when a polygon behind the front one crosses its depth plane, the list is split
along the line where the two planes meet; when one is wholly in front it moves to the
front. The recursion runs on an explicit stack.

The kernel returns *fragments*: for every pixel, each visible polygon's area and area
centroid (all its visible pieces in the pixel merged), so flat colours and per-piece
shading are resolved outside it.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from aaeval.renderers._clip import EPS_LINE, area_centroid, clip_side, clip_split, signed_area

# Coverage within this of 1 is a solid piece; below COV_EMPTY a piece is absent.
COV_SOLID = 1.0 - 1e-12
COV_EMPTY = 1e-15
# Pieces of smaller area are dropped inside the integrator (slivers from rounding).
AREA_EMPTY = 1e-15
# Safety bound on integrator steps for one pixel; never reached on valid scenes.
MAX_STEPS = 100_000
BACKGROUND = -1


# --- growable buffers -------------------------------------------------------------
# Polygons live in vertex buffers (x, y, clip flag) with records (start, length, source).


@njit(cache=True)
def _grow(a, n):
    """``a`` with room for at least ``n`` entries along its first axis (contents kept)."""
    if n <= a.shape[0]:
        return a
    b = np.empty((max(n, 2 * a.shape[0]),) + a.shape[1:], a.dtype)
    b[: a.shape[0]] = a
    return b


@njit(cache=True)
def _grow_verts(x, y, f, n):
    return _grow(x, n), _grow(y, n), _grow(f, n)


@njit(cache=True)
def _new_verts(n):
    return np.empty(n), np.empty(n), np.zeros(n, np.uint8)


@njit(cache=True, inline="always")
def _record(recs, k, start, length, src):
    recs[k, 0] = start
    recs[k, 1] = length
    recs[k, 2] = src
    return k + 1


@njit(cache=True, inline="always")
def _emit(fi, ff, n, pix, src, area, cx, cy):
    """Append one fragment (pixel, source; area, centroid) and return the new count."""
    fi[n, 0] = pix
    fi[n, 1] = src
    ff[n, 0] = area
    ff[n, 1] = cx
    ff[n, 2] = cy
    return n + 1


# --- depth relations --------------------------------------------------------------


@njit(cache=True, inline="always")
def _depth(planes, p, x, y):
    return planes[p, 0] * x + planes[p, 1] * y + planes[p, 2]


@njit(cache=True)
def _in_front_on_square(planes, p, q, x0, y0, eps_z):
    """Whether polygon p hides polygon q everywhere over the square [x0,x0+1]x[y0,y0+1].

    Depth differences are linear, so the four corners decide. On one shared plane the
    one later in the file is in front (the scene format's rule).
    """
    if q == BACKGROUND:
        return True
    if p == BACKGROUND:
        return False
    lo = np.inf
    hi = -np.inf
    for cx in (x0, x0 + 1.0):
        for cy in (y0, y0 + 1.0):
            d = _depth(planes, p, cx, cy) - _depth(planes, q, cx, cy)
            lo = min(lo, d)
            hi = max(hi, d)
    if hi <= eps_z and lo >= -eps_z:
        return p > q
    return hi <= eps_z


@njit(cache=True)
def _relation(planes, q, f, xs, ys, start, n, eps_z):
    """Where polygon q (the outline at ``start``) lies in depth against polygon f's plane.

    0: behind f everywhere on q; 1: in front everywhere on q; 2: the planes cross inside
    q. The test is made on the signed distance of q's vertices to the line where the
    planes meet, with the same tolerance the clipper uses, so after a split along that
    line every piece classifies cleanly and the split is never repeated.
    """
    da = planes[q, 0] - planes[f, 0]
    db = planes[q, 1] - planes[f, 1]
    dc = planes[q, 2] - planes[f, 2]
    g = np.sqrt(da * da + db * db)
    lo = np.inf
    hi = -np.inf
    for v in range(start, start + n):
        d = da * xs[v] + db * ys[v] + dc
        lo = min(lo, d)
        hi = max(hi, d)
    if g <= eps_z and hi <= eps_z and lo >= -eps_z:
        # one shared plane: the polygon later in the file is in front
        return 1 if q > f else 0
    if g <= eps_z:
        # parallel planes: a constant depth difference decides
        return 1 if hi < 0.0 else 0
    lo /= g
    hi /= g
    if lo >= -EPS_LINE and hi <= EPS_LINE:
        return 1 if lo + hi < 0.0 else 0  # a sliver along the crossing line
    if lo >= -EPS_LINE:
        return 0
    if hi <= EPS_LINE:
        return 1
    return 2


# --- the pixel integrator ---------------------------------------------------------


@njit(cache=True)
def integrate_pixel(wx, wy, wf, recs, n_init, n_vert, planes, eps_z, litems, lists, stack, oi, of):
    """Resolve the polygon list ``recs[0:n_init]`` (front to back, background last).

    Polygon record ``j`` is ``w*[recs[j,0] : recs[j,0] + recs[j,1]]`` with source
    ``recs[j,2]``; vertices from ``n_vert`` on are free. Writes the visible pieces'
    (source; area, centroid) to ``oi, of`` and returns their count, or -1 if a work array
    was too small (the caller grows them and calls again).
    """
    n_poly = n_init
    for j in range(n_init):
        litems[j] = j
    n_items = n_init
    lists[0, 0] = 0
    lists[0, 1] = n_init
    n_lists = 1
    stack[0] = 0
    top = 1
    n_out = 0
    steps = 0
    while top > 0 and steps < MAX_STEPS:
        steps += 1
        top -= 1
        L = stack[top]
        s0 = lists[L, 0]
        cnt = lists[L, 1]
        f = litems[s0]
        fs = recs[f, 0]
        fn = recs[f, 1]
        src_f = recs[f, 2]
        # 2. the first unclipped (and not degenerate) edge of the front polygon
        clip = False
        a = 0.0
        b = 0.0
        c = 0.0
        if cnt > 1:
            for k in range(fn):
                if wf[fs + k] == 0:
                    k2 = fs + (k + 1) % fn
                    ex = wx[k2] - wx[fs + k]
                    ey = wy[k2] - wy[fs + k]
                    norm = np.sqrt(ex * ex + ey * ey)
                    if norm > EPS_LINE:
                        a = ey / norm
                        b = -ex / norm
                        c = -(a * wx[fs + k] + b * wy[fs + k])
                        clip = True
                        break
        if cnt > 1 and not clip and _is_sliver(wx, wy, recs, litems, s0, cnt):
            # F has no edge left to clip along, so it should be the whole region; when it
            # is smaller it is a rounding remnant (a spike along two clip lines, or edges
            # too short to clip along): it is dropped and the list looked at again
            for i in range(cnt - 1):
                litems[s0 + i] = litems[s0 + i + 1]
            lists[L, 1] = cnt - 1
            stack[top] = L
            top += 1
            continue
        if cnt > 1 and not clip:
            # F is clipped on all sides, so it covers its list's region: check depth
            front = -1
            for i in range(1, cnt):
                q = litems[s0 + i]
                sq = recs[q, 2]
                if sq == BACKGROUND:
                    continue
                rel = _relation(planes, sq, src_f, wx, wy, recs[q, 0], recs[q, 1], eps_z)
                if rel == 1:
                    front = i
                    break
                if rel == 2:
                    # q crosses F's depth plane: split along the line z_q = z_F
                    da = planes[sq, 0] - planes[src_f, 0]
                    db = planes[sq, 1] - planes[src_f, 1]
                    norm = np.sqrt(da * da + db * db)
                    a = da / norm
                    b = db / norm
                    c = (planes[sq, 2] - planes[src_f, 2]) / norm
                    clip = True
                    break
            if front > 0:
                # the nearer polygon moves to the front and the list is looked at again
                q = litems[s0 + front]
                for i in range(front, 0, -1):
                    litems[s0 + i] = litems[s0 + i - 1]
                litems[s0] = q
                stack[top] = L
                top += 1
                continue
        if not clip:
            # 2. the front polygon's colour, weighted by its area, for this region
            if n_out >= oi.shape[0]:
                return -1
            area, cx, cy = area_centroid(wx, wy, fs, fn)
            oi[n_out] = src_f
            of[n_out, 0] = area
            of[n_out, 1] = cx
            of[n_out, 2] = cy
            n_out += 1
            continue
        # 3. clip every polygon in the list against the line into two lists
        if n_lists + 2 > lists.shape[0] or top + 2 > stack.shape[0] \
                or n_items + 2 * cnt > litems.shape[0] or n_poly + 2 * cnt > recs.shape[0]:
            return -1
        a_start = n_items
        b_start = n_items + cnt
        a_cnt = 0
        b_cnt = 0
        for i in range(cnt):
            p = litems[s0 + i]
            n = recs[p, 1]
            at_b = n_vert + 2 * n + 2  # a half-plane clip at most doubles the vertices
            if at_b + 2 * n + 2 > wx.shape[0]:
                return -1
            ma, mb = clip_split(wx, wy, wf, recs[p, 0], n, a, b, c, True, True,
                                wx, wy, wf, n_vert, wx, wy, wf, at_b)
            if ma > 0 and signed_area(wx, wy, n_vert, ma) > AREA_EMPTY:
                litems[a_start + a_cnt] = n_poly
                a_cnt += 1
                n_poly = _record(recs, n_poly, n_vert, ma, recs[p, 2])
            if mb > 0 and signed_area(wx, wy, at_b, mb) > AREA_EMPTY:
                litems[b_start + b_cnt] = n_poly
                b_cnt += 1
                n_poly = _record(recs, n_poly, at_b, mb, recs[p, 2])
            n_vert = at_b + mb
        n_items += 2 * cnt
        # 4. reenter the algorithm for each of the two lists
        for new_start, new_cnt in ((a_start, a_cnt), (b_start, b_cnt)):
            if new_cnt > 0:
                lists[n_lists, 0] = new_start
                lists[n_lists, 1] = new_cnt
                stack[top] = n_lists
                top += 1
                n_lists += 1
    return n_out


@njit(cache=True)
def _is_sliver(wx, wy, recs, litems, s0, cnt):
    """Whether the front polygon of a list is much smaller than the list's region.

    Every list holds a polygon spanning its whole region (the background or a solid
    piece, only ever clipped by the region's own lines), so the region's area is the
    largest area in the list.
    """
    f = litems[s0]
    area_f = signed_area(wx, wy, recs[f, 0], recs[f, 1])
    region = area_f
    for i in range(1, cnt):
        q = litems[s0 + i]
        region = max(region, signed_area(wx, wy, recs[q, 0], recs[q, 1]))
    return area_f < region * (1.0 - 1e-9)


@njit(cache=True)
def _pixel_polygons(sx, sy, sf, pieces, plist, n_pl, solid, x0, y0, wx, wy, wf, recs):
    """The pixel's polygon list as integrator records, background square last if needed.

    Each listed strip piece is clipped to the pixel column; a solid piece becomes the
    pixel square with every edge flagged. Returns ``(vertices used, records)``, or
    ``(-1, 0)`` if the workspace is too small.
    """
    used = 0
    n_rec = 0
    total = n_pl + (1 if solid < 0 else 0)
    if total > recs.shape[0]:
        return -1, 0
    for t in range(total):
        if t < n_pl and plist[t] != solid:
            k = plist[t]
            n = pieces[k, 1]
            # the first clip goes above the space the second one (up to 4n) writes into
            tmp = used + 4 * n + 8
            if tmp + 2 * n + 4 > wx.shape[0]:
                return -1, 0
            # the pixel column: x >= x0 (side B of x - x0), then x <= x0+1 (side A)
            m1 = clip_side(sx, sy, sf, pieces[k, 0], n, 1.0, 0.0, -x0, 1, wx, wy, wf, tmp)
            m2 = clip_side(wx, wy, wf, tmp, m1, 1.0, 0.0, -(x0 + 1.0), -1, wx, wy, wf, used)
            if m2 > 0:
                n_rec = _record(recs, n_rec, used, m2, pieces[k, 2])
                used += m2
        else:
            if used + 4 > wx.shape[0]:
                return -1, 0
            for i, (px, py) in enumerate(((x0, y0), (x0 + 1.0, y0), (x0 + 1.0, y0 + 1.0), (x0, y0 + 1.0))):
                wx[used + i] = px
                wy[used + i] = py
                wf[used + i] = 1
            n_rec = _record(recs, n_rec, used, 4, pieces[plist[t], 2] if t < n_pl else BACKGROUND)
            used += 4
    return used, n_rec


@njit(cache=True)
def _integrate(sx, sy, sf, pieces, plist, n_pl, solid, x0, y0, planes, eps_z, ws):
    """Run the pixel integrator, growing the workspace until it fits.

    Returns the workspace (possibly grown) and the number of visible pieces in it.
    """
    wx, wy, wf, recs, litems, lists, stack, oi, of = ws
    while True:
        nv, n_init = _pixel_polygons(sx, sy, sf, pieces, plist, n_pl, solid, x0, y0, wx, wy, wf, recs)
        n_out = -1
        if nv >= 0:
            n_out = integrate_pixel(wx, wy, wf, recs, n_init, nv, planes, eps_z, litems, lists, stack, oi, of)
        if n_out >= 0:
            return (wx, wy, wf, recs, litems, lists, stack, oi, of), n_out
        wx, wy, wf = _grow_verts(wx, wy, wf, 2 * wx.shape[0])
        recs = _grow(recs, 2 * recs.shape[0])
        litems = _grow(litems, 2 * litems.shape[0])
        lists = _grow(lists, 2 * lists.shape[0])
        stack = _grow(stack, 2 * stack.shape[0])
        oi = _grow(oi, 2 * oi.shape[0])
        of = _grow(of, 2 * of.shape[0])


# --- the scanline algorithm -------------------------------------------------------


@njit(cache=True)
def _strip_coverage(xs, ys, start, n, row, c0, c1, cov, cov_off):
    """Exact area of a strip piece over each pixel column c0..c1 (-∫ y dx per column)."""
    for c in range(c1 - c0 + 1):
        cov[cov_off + c] = 0.0
    for i in range(start, start + n):
        j = i + 1 if i + 1 < start + n else start
        x0 = xs[i]
        x1 = xs[j]
        if x0 == x1:
            continue
        y0 = ys[i] - row
        y1 = ys[j] - row
        slope = (y1 - y0) / (x1 - x0)
        lo = min(x0, x1)
        hi = max(x0, x1)
        ca = max(int(np.floor(lo)), c0)
        cb = min(int(np.floor(hi)), c1)
        for col in range(ca, cb + 1):
            xa = min(max(x0, col), col + 1.0)
            xb = min(max(x1, col), col + 1.0)
            if xa == xb:
                continue
            ya = y0 + slope * (xa - x0)
            yb = y0 + slope * (xb - x0)
            cov[cov_off + col - c0] -= 0.5 * (xb - xa) * (ya + yb)


@njit(cache=True)
def _enter(vx0, vy0, start, n, y_top, out_x, out_y, out_f, at):
    """A polygon's part below ``y_top`` (all of it unless it starts above the image)."""
    lo = vy0[start:start + n].min()
    if lo >= y_top:
        for i in range(n):
            out_x[at + i] = vx0[start + i]
            out_y[at + i] = vy0[start + i]
            out_f[at + i] = 0
        return n
    flags = np.zeros(n, np.uint8)
    m = clip_side(vx0[start:start + n], vy0[start:start + n], flags, 0, n, 0.0, 1.0, -y_top, 1,
                  out_x, out_y, out_f, at)
    if m > 0 and signed_area(out_x, out_y, at, m) <= COV_EMPTY:
        return 0
    return m


@njit(cache=True)
def _irregular_centroid(sx, sy, sf, start, n, col, wx, wy, wf):
    """Area centroid of a strip piece within pixel column ``col`` (y is NaN if none is left)."""
    m1 = clip_side(sx, sy, sf, start, n, 1.0, 0.0, -float(col), 1, wx, wy, wf, 0)
    m2 = clip_side(wx, wy, wf, 0, m1, 1.0, 0.0, -float(col + 1), -1, wx, wy, wf, m1)
    if m2 == 0:
        return col + 0.5, np.nan
    _, cx, cy = area_centroid(wx, wy, m1, m2)
    return cx, cy


@njit(cache=True)
def catmull_fragments(width, height, pstart0, plen0, vx0, vy0, planes, eps_z, jagged, centroids):
    """Visible fragments of every pixel.

    Returns ``(pix, src, area, cx, cy)``: pixel index ``row * width + col``, source
    polygon (-1 for background), visible area, and its area centroid. With
    ``centroids`` false the fast paths skip finding centroids (flat colours need none)
    and report the pixel centre instead.
    """
    n_polys = pstart0.size
    # I. sort polygons on their first scanline
    ymin = np.empty(n_polys)
    ymax = np.empty(n_polys)
    for p in range(n_polys):
        ymin[p] = vy0[pstart0[p]:pstart0[p] + plen0[p]].min()
        ymax[p] = vy0[pstart0[p]:pstart0[p] + plen0[p]].max()
    y_order = np.argsort(ymin, kind="mergesort")
    next_in = 0

    # II. the active list: each polygon's remaining part (below the current scanline),
    # double-buffered as the strip is clipped off
    rx, ry, rf = _new_verts(1024)
    nx, ny, nf = _new_verts(1024)
    active = np.empty((n_polys, 3), np.int64)  # start, length, source
    n_act = 0
    rem_used = 0
    # this scanline's strip pieces, their columns (first, last, coverage offset), coverage
    sx, sy, sf = _new_verts(1024)
    pieces = np.empty((n_polys, 3), np.int64)
    span = np.empty((n_polys, 3), np.int64)
    cov = np.empty(1024)
    bucket_head = np.empty(width + 1, np.int64)
    bucket_items = np.empty(n_polys, np.int64)
    # the z-list, and a pixel's polygon list
    zl = np.empty(n_polys, np.int64)
    zdepth = np.empty(n_polys)
    plist = np.empty(n_polys + 1, np.int64)
    # the integrator's workspace: vertices, records, lists, stack, visible pieces
    wx, wy, wf = _new_verts(4096)
    ws = (wx, wy, wf, np.empty((1024, 3), np.int64), np.empty(4096, np.int64), np.empty((1024, 2), np.int64),
          np.empty(1024, np.int64), np.empty(256, np.int64), np.empty((256, 3)))
    # fragments out: (pixel, source) and (area, cx, cy)
    n_frag = 0
    fi = np.empty((width * height + 16, 2), np.int64)
    ff = np.empty((width * height + 16, 3))

    for row in range(height):
        y_top = float(row)
        y_bot = y_top + 1.0
        # A. polygons entering on this scanline join the active list
        while next_in < n_polys and ymin[y_order[next_in]] < y_bot:
            p = y_order[next_in]
            next_in += 1
            if ymax[p] <= y_top:
                continue
            rx, ry, rf = _grow_verts(rx, ry, rf, rem_used + 2 * plen0[p] + 4)
            # the part above the image is cut away first (keep y >= row)
            m = _enter(vx0, vy0, pstart0[p], plen0[p], y_top, rx, ry, rf, rem_used)
            if m > 0:
                n_act = _record(active, n_act, rem_used, m, p)
                rem_used += m
        fi = _grow(fi, n_frag + width)
        ff = _grow(ff, n_frag + width)
        if n_act == 0 and next_in >= n_polys:
            for col in range(width):
                n_frag = _emit(fi, ff, n_frag, row * width + col, BACKGROUND, 1.0, col + 0.5, row + 0.5)
            continue

        # C. clip the strip piece off every active polygon; keep what remains below
        new_used = 0
        n_sp = 0
        sp_used = 0
        cov_used = 0
        keep = 0
        for k in range(n_act):
            s = active[k, 0]
            n = active[k, 1]
            sx, sy, sf = _grow_verts(sx, sy, sf, sp_used + 2 * n + 4)
            nx, ny, nf = _grow_verts(nx, ny, nf, new_used + 2 * n + 4)
            # the line y = row + 1: side A (y < row+1) is this scanline's piece
            m, m2 = clip_split(rx, ry, rf, s, n, 0.0, 1.0, -y_bot, True, True,
                               sx, sy, sf, sp_used, nx, ny, nf, new_used)
            if m > 0 and signed_area(sx, sy, sp_used, m) > COV_EMPTY:
                c0 = max(int(np.floor(sx[sp_used:sp_used + m].min())), 0)
                c1 = min(int(np.ceil(sx[sp_used:sp_used + m].max())) - 1, width - 1)
                if c1 >= c0:
                    # C.3 exact coverage of every column: solid runs and irregular ends
                    cov = _grow(cov, cov_used + c1 - c0 + 1)
                    _strip_coverage(sx, sy, sp_used, m, y_top, c0, c1, cov, cov_used)
                    span[n_sp, 0] = c0
                    span[n_sp, 1] = c1
                    span[n_sp, 2] = cov_used
                    n_sp = _record(pieces, n_sp, sp_used, m, active[k, 2])
                    cov_used += c1 - c0 + 1
                    sp_used += m
            if m2 > 0 and signed_area(nx, ny, new_used, m2) > COV_EMPTY:
                keep = _record(active, keep, new_used, m2, active[k, 2])
                new_used += m2
        n_act = keep
        rx, nx = nx, rx
        ry, ny = ny, ry
        rf, nf = nf, rf
        rem_used = new_used

        # C.4 the x-bucket: pieces listed under their leftmost pixel
        bucket_head[:] = 0
        for k in range(n_sp):
            bucket_head[span[k, 0] + 1] += 1
        for col in range(width):
            bucket_head[col + 1] += bucket_head[col]
        fill = bucket_head[:width].copy()
        for k in range(n_sp):
            bucket_items[fill[span[k, 0]]] = k
            fill[span[k, 0]] += 1

        # D./E. sweep the pixels with a z-list
        n_zl = 0
        for col in range(width):
            # E.1 entries of the x-bucket at this pixel enter the z-list; pieces that
            # ended to the left leave it
            for t in range(bucket_head[col], bucket_head[col + 1]):
                zl[n_zl] = bucket_items[t]
                n_zl += 1
            w = 0
            for t in range(n_zl):
                if span[zl[t], 1] >= col:
                    zl[w] = zl[t]
                    w += 1
            n_zl = w
            xc = col + 0.5
            yc = row + 0.5
            # keep the z-list sorted front to back (depth at the pixel centre);
            # insertion sort is linear while the order holds from pixel to pixel
            for t in range(n_zl):
                zdepth[t] = _depth(planes, pieces[zl[t], 2], xc, yc)
            for t in range(1, n_zl):
                kz = zl[t]
                dz = zdepth[t]
                u = t - 1
                while u >= 0 and (zdepth[u] > dz or (zdepth[u] == dz and pieces[zl[u], 2] < pieces[kz, 2])):
                    zl[u + 1] = zl[u]
                    zdepth[u + 1] = zdepth[u]
                    u -= 1
                zl[u + 1] = kz
                zdepth[u + 1] = dz
            pix = row * width + col

            # E.2 the pixel's polygon list: front to back up to a solid piece, and
            # anything behind it that is not hidden everywhere in the pixel
            n_pl = 0
            solid = -1
            for t in range(n_zl):
                k = zl[t]
                cv = cov[span[k, 2] + col - span[k, 0]]
                if cv <= COV_EMPTY:
                    continue
                if solid >= 0 and _in_front_on_square(planes, pieces[solid, 2], pieces[k, 2], float(col), y_top, eps_z):
                    continue
                plist[n_pl] = k
                n_pl += 1
                if solid < 0 and cv >= COV_SOLID:
                    solid = k

            fi = _grow(fi, n_frag + 2)
            ff = _grow(ff, n_frag + 2)
            if n_pl == 0:
                n_frag = _emit(fi, ff, n_frag, pix, BACKGROUND, 1.0, xc, yc)
                continue
            first = plist[0]
            if jagged or (n_pl == 1 and first == solid):
                # a. a solid piece in front (or, with the integrator switched off, the
                # nearest piece colours the whole pixel)
                n_frag = _emit(fi, ff, n_frag, pix, pieces[first, 2], 1.0, xc, yc)
                continue
            # a. one irregular piece in front of a solid one (or of the background)
            behind = -2
            if n_pl == 1:
                behind = BACKGROUND
            elif n_pl == 2 and plist[1] == solid and _in_front_on_square(
                    planes, pieces[first, 2], pieces[solid, 2], float(col), y_top, eps_z):
                behind = pieces[solid, 2]
            if behind != -2:
                cv = cov[span[first, 2] + col - span[first, 0]]
                icx = xc
                icy = yc
                if centroids:
                    wx, wy, wf = _grow_verts(ws[0], ws[1], ws[2], 6 * pieces[first, 1] + 16)
                    ws = (wx, wy, wf) + ws[3:]
                    icx, icy = _irregular_centroid(sx, sy, sf, pieces[first, 0], pieces[first, 1], col, wx, wy, wf)
                    if np.isnan(icy):
                        icy = yc
                n_frag = _emit(fi, ff, n_frag, pix, pieces[first, 2], cv, icx, icy)
                rest = 1.0 - cv
                if rest > 0.0:
                    n_frag = _emit(fi, ff, n_frag, pix, behind, rest, (xc - cv * icx) / rest, (yc - cv * icy) / rest)
                continue

            # b. the pixel integrator; then one fragment per polygon (its pieces merged:
            # one shade per polygon per pixel)
            ws, n_out = _integrate(sx, sy, sf, pieces, plist, n_pl, solid, float(col), y_top, planes, eps_z, ws)
            oi = ws[7]
            of = ws[8]
            fi = _grow(fi, n_frag + n_out)
            ff = _grow(ff, n_frag + n_out)
            first_frag = n_frag
            for o in range(n_out):
                g = first_frag
                while g < n_frag and fi[g, 1] != oi[o]:
                    g += 1
                if g == n_frag:
                    n_frag = _emit(fi, ff, n_frag, pix, oi[o], of[o, 0], of[o, 1], of[o, 2])
                else:
                    total = ff[g, 0] + of[o, 0]
                    if total > 0.0:
                        ff[g, 1] = (ff[g, 1] * ff[g, 0] + of[o, 1] * of[o, 0]) / total
                        ff[g, 2] = (ff[g, 2] * ff[g, 0] + of[o, 2] * of[o, 0]) / total
                    ff[g, 0] = total
    return fi[:n_frag, 0], fi[:n_frag, 1], ff[:n_frag, 0], ff[:n_frag, 1], ff[:n_frag, 2]
