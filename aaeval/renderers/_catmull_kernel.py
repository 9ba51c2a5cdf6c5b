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


@njit(cache=True)
def _grow(a, n):
    if n <= a.size:
        return a
    b = np.empty(max(n, 2 * a.size), a.dtype)
    b[: a.size] = a
    return b


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
def integrate_pixel(ws_x, ws_y, ws_f, pstart, plen, psrc, n_init, planes, eps_z,
                    litems, lstart, llen, stack, out_src, out_area, out_cx, out_cy, n_vert):
    """Resolve the polygon list ``0..n_init-1`` (front to back, background last).

    Polygon records ``j`` are ``ws_*[pstart[j]:pstart[j]+plen[j]]`` with source
    ``psrc[j]``. Writes visible pieces to ``out_*`` and returns their count, or -1 if a
    work array was too small (the caller grows them and calls again).
    """
    n_poly = n_init
    n_items = n_init
    for j in range(n_init):
        litems[j] = j
    lstart[0] = 0
    llen[0] = n_init
    n_lists = 1
    stack[0] = 0
    top = 1
    n_out = 0
    steps = 0
    while top > 0:
        steps += 1
        if steps > MAX_STEPS:
            break
        top -= 1
        L = stack[top]
        s0 = lstart[L]
        cnt = llen[L]
        f = litems[s0]
        fs = pstart[f]
        fn = plen[f]
        # 2. the first unclipped (and not degenerate) edge of the front polygon
        clip = False
        a = 0.0
        b = 0.0
        c = 0.0
        if cnt > 1:
            for k in range(fn):
                if ws_f[fs + k] == 0:
                    k2 = fs + (k + 1) % fn
                    ex = ws_x[k2] - ws_x[fs + k]
                    ey = ws_y[k2] - ws_y[fs + k]
                    norm = np.sqrt(ex * ex + ey * ey)
                    if norm > EPS_LINE:
                        a = ey / norm
                        b = -ex / norm
                        c = -(a * ws_x[fs + k] + b * ws_y[fs + k])
                        clip = True
                        break
        if cnt > 1 and not clip:
            # F is clipped on all sides, so it covers its list's region: check depth
            front = -1
            src_f = psrc[f]
            for i in range(1, cnt):
                q = litems[s0 + i]
                sq = psrc[q]
                if sq == BACKGROUND:
                    continue
                rel = _relation(planes, sq, src_f, ws_x, ws_y, pstart[q], plen[q], eps_z)
                if rel == 0:
                    continue
                if rel == 1:
                    front = i
                    break
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
            if n_out >= out_src.size:
                return -1
            area, cx, cy = area_centroid(ws_x, ws_y, fs, fn)
            out_src[n_out] = psrc[f]
            out_area[n_out] = area
            out_cx[n_out] = cx
            out_cy[n_out] = cy
            n_out += 1
            continue
        # 3. clip every polygon in the list against the line into two lists
        if n_lists + 2 > lstart.size or top + 2 > stack.size or n_items + 2 * cnt > litems.size \
                or n_poly + 2 * cnt > pstart.size:
            return -1
        a_start = n_items
        b_start = n_items + cnt
        a_cnt = 0
        b_cnt = 0
        for i in range(cnt):
            p = litems[s0 + i]
            n = plen[p]
            at_b = n_vert + 2 * n + 2
            if at_b + 2 * n + 2 > ws_x.size:
                return -1
            ma, mb = clip_split(ws_x, ws_y, ws_f, pstart[p], n, a, b, c, True, True,
                                ws_x, ws_y, ws_f, n_vert, ws_x, ws_y, ws_f, at_b)
            if ma > 0 and signed_area(ws_x, ws_y, n_vert, ma) > AREA_EMPTY:
                pstart[n_poly] = n_vert
                plen[n_poly] = ma
                psrc[n_poly] = psrc[p]
                litems[a_start + a_cnt] = n_poly
                a_cnt += 1
                n_poly += 1
            if mb > 0 and signed_area(ws_x, ws_y, at_b, mb) > AREA_EMPTY:
                pstart[n_poly] = at_b
                plen[n_poly] = mb
                psrc[n_poly] = psrc[p]
                litems[b_start + b_cnt] = n_poly
                b_cnt += 1
                n_poly += 1
            n_vert = at_b + mb
        n_items += 2 * cnt
        # 4. reenter the algorithm for each of the two lists
        for new_start, new_cnt in ((a_start, a_cnt), (b_start, b_cnt)):
            if new_cnt > 0:
                lstart[n_lists] = new_start
                llen[n_lists] = new_cnt
                stack[top] = n_lists
                top += 1
                n_lists += 1
    return n_out


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

    # the active list: each polygon's remaining part (below the current scanline)
    cap = 1024
    rem_x = np.empty(cap)
    rem_y = np.empty(cap)
    rem_f = np.zeros(cap, np.uint8)
    new_x = np.empty(cap)
    new_y = np.empty(cap)
    new_f = np.zeros(cap, np.uint8)
    act_src = np.empty(n_polys, np.int64)
    act_start = np.empty(n_polys, np.int64)
    act_len = np.empty(n_polys, np.int64)
    n_act = 0
    rem_used = 0

    # strip pieces of the current scanline
    sp_x = np.empty(cap)
    sp_y = np.empty(cap)
    sp_f = np.zeros(cap, np.uint8)
    sp_src = np.empty(n_polys, np.int64)
    sp_start = np.empty(n_polys, np.int64)
    sp_len = np.empty(n_polys, np.int64)
    sp_c0 = np.empty(n_polys, np.int64)
    sp_c1 = np.empty(n_polys, np.int64)
    sp_cov = np.empty(n_polys + 1, np.int64)
    cov = np.empty(cap)
    bucket_head = np.empty(width + 1, np.int64)
    bucket_items = np.empty(n_polys, np.int64)

    # the z-list and a pixel's polygon list
    zl = np.empty(n_polys, np.int64)
    zdepth = np.empty(n_polys)
    plist = np.empty(n_polys + 1, np.int64)

    # integrator workspace
    ws_x = np.empty(4096)
    ws_y = np.empty(4096)
    ws_f = np.zeros(4096, np.uint8)
    w_pstart = np.empty(1024, np.int64)
    w_plen = np.empty(1024, np.int64)
    w_psrc = np.empty(1024, np.int64)
    litems = np.empty(4096, np.int64)
    lstart = np.empty(1024, np.int64)
    llen = np.empty(1024, np.int64)
    stack = np.empty(1024, np.int64)
    o_src = np.empty(256, np.int64)
    o_area = np.empty(256)
    o_cx = np.empty(256)
    o_cy = np.empty(256)

    # output fragments
    n_frag = 0
    f_pix = np.empty(width * height + 16, np.int64)
    f_src = np.empty(width * height + 16, np.int64)
    f_area = np.empty(width * height + 16)
    f_cx = np.empty(width * height + 16)
    f_cy = np.empty(width * height + 16)

    for row in range(height):
        y_top = float(row)
        y_bot = y_top + 1.0
        # A. polygons entering on this scanline join the active list
        while next_in < n_polys and ymin[y_order[next_in]] < y_bot:
            p = y_order[next_in]
            next_in += 1
            if ymax[p] <= y_top:
                continue
            need = rem_used + 2 * plen0[p] + 4
            if need > rem_x.size:
                rem_x = _grow(rem_x, need)
                rem_y = _grow(rem_y, need)
                rem_f = _grow(rem_f, need)
            # the part above the image is cut away first (keep y >= row)
            m = _enter(vx0, vy0, pstart0[p], plen0[p], y_top, rem_x, rem_y, rem_f, rem_used)
            if m > 0:
                act_src[n_act] = p
                act_start[n_act] = rem_used
                act_len[n_act] = m
                rem_used += m
                n_act += 1
        if n_act == 0 and next_in >= n_polys:
            if n_frag + width > f_pix.size:
                f_pix = _grow(f_pix, n_frag + width)
                f_src = _grow(f_src, n_frag + width)
                f_area = _grow(f_area, n_frag + width)
                f_cx = _grow(f_cx, n_frag + width)
                f_cy = _grow(f_cy, n_frag + width)
            for col in range(width):
                f_pix[n_frag] = row * width + col
                f_src[n_frag] = BACKGROUND
                f_area[n_frag] = 1.0
                f_cx[n_frag] = col + 0.5
                f_cy[n_frag] = row + 0.5
                n_frag += 1
            continue

        # C. clip the strip piece off every active polygon; keep what remains below
        new_used = 0
        n_sp = 0
        sp_used = 0
        cov_used = 0
        keep = 0
        for k in range(n_act):
            s = act_start[k]
            n = act_len[k]
            need = 2 * n + 4
            if sp_used + need > sp_x.size:
                sp_x = _grow(sp_x, sp_used + need)
                sp_y = _grow(sp_y, sp_used + need)
                sp_f = _grow(sp_f, sp_used + need)
            if new_used + need > new_x.size:
                new_x = _grow(new_x, new_used + need)
                new_y = _grow(new_y, new_used + need)
                new_f = _grow(new_f, new_used + need)
            # the line y = row + 1: side A (y < row+1) is this scanline's piece
            m, m2 = clip_split(rem_x, rem_y, rem_f, s, n, 0.0, 1.0, -y_bot, True, True,
                               sp_x, sp_y, sp_f, sp_used, new_x, new_y, new_f, new_used)
            if m > 0 and signed_area(sp_x, sp_y, sp_used, m) > COV_EMPTY:
                p = act_src[k]
                lo = sp_x[sp_used:sp_used + m].min()
                hi = sp_x[sp_used:sp_used + m].max()
                c0 = max(int(np.floor(lo)), 0)
                c1 = min(int(np.ceil(hi)) - 1, width - 1)
                if c1 >= c0:
                    sp_src[n_sp] = p
                    sp_start[n_sp] = sp_used
                    sp_len[n_sp] = m
                    sp_c0[n_sp] = c0
                    sp_c1[n_sp] = c1
                    if cov_used + c1 - c0 + 1 > cov.size:
                        cov = _grow(cov, cov_used + c1 - c0 + 1)
                    sp_cov[n_sp] = cov_used
                    _strip_coverage(sp_x, sp_y, sp_used, m, y_top, c0, c1, cov, cov_used)
                    cov_used += c1 - c0 + 1
                    sp_used += m
                    n_sp += 1
            if m2 > 0 and signed_area(new_x, new_y, new_used, m2) > COV_EMPTY:
                act_src[keep] = act_src[k]
                act_start[keep] = new_used
                act_len[keep] = m2
                new_used += m2
                keep += 1
        n_act = keep
        rem_x, new_x = new_x, rem_x
        rem_y, new_y = new_y, rem_y
        rem_f, new_f = new_f, rem_f
        rem_used = new_used

        # C.4 the x-bucket: pieces listed under their leftmost pixel
        bucket_head[:] = 0
        for k in range(n_sp):
            bucket_head[sp_c0[k] + 1] += 1
        for col in range(width):
            bucket_head[col + 1] += bucket_head[col]
        fill = bucket_head[:width].copy()
        for k in range(n_sp):
            bucket_items[fill[sp_c0[k]]] = k
            fill[sp_c0[k]] += 1

        # D./E. sweep the pixels with a z-list
        n_zl = 0
        for col in range(width):
            # E.1 entries of the x-bucket at this pixel enter the z-list
            for t in range(bucket_head[col], bucket_head[col + 1]):
                zl[n_zl] = bucket_items[t]
                n_zl += 1
            # pieces that ended to the left leave it
            w = 0
            for t in range(n_zl):
                if sp_c1[zl[t]] >= col:
                    zl[w] = zl[t]
                    w += 1
            n_zl = w
            xc = col + 0.5
            yc = row + 0.5
            # keep the z-list sorted front to back (depth at the pixel centre);
            # insertion sort is linear while the order holds from pixel to pixel
            for t in range(n_zl):
                zdepth[t] = _depth(planes, sp_src[zl[t]], xc, yc)
            for t in range(1, n_zl):
                kz = zl[t]
                dz = zdepth[t]
                u = t - 1
                while u >= 0 and (zdepth[u] > dz or (zdepth[u] == dz and sp_src[zl[u]] < sp_src[kz])):
                    zl[u + 1] = zl[u]
                    zdepth[u + 1] = zdepth[u]
                    u -= 1
                zl[u + 1] = kz
                zdepth[u + 1] = dz

            if n_frag + 64 > f_pix.size:
                f_pix = _grow(f_pix, n_frag + 64)
                f_src = _grow(f_src, n_frag + 64)
                f_area = _grow(f_area, n_frag + 64)
                f_cx = _grow(f_cx, n_frag + 64)
                f_cy = _grow(f_cy, n_frag + 64)
            pix = row * width + col

            # E.2 the pixel's polygon list: front to back up to a solid piece, and
            # anything behind it that is not hidden everywhere in the pixel
            n_pl = 0
            solid = -1
            for t in range(n_zl):
                k = zl[t]
                cv = cov[sp_cov[k] + col - sp_c0[k]]
                if cv <= COV_EMPTY:
                    continue
                if solid >= 0 and _in_front_on_square(planes, sp_src[solid], sp_src[k], float(col), y_top, eps_z):
                    continue
                plist[n_pl] = k
                n_pl += 1
                if solid < 0 and cv >= COV_SOLID:
                    solid = k

            if n_pl == 0:
                f_pix[n_frag] = pix
                f_src[n_frag] = BACKGROUND
                f_area[n_frag] = 1.0
                f_cx[n_frag] = xc
                f_cy[n_frag] = yc
                n_frag += 1
                continue
            first = plist[0]
            if jagged:
                # integrator switched off: the nearest piece colours the whole pixel
                f_pix[n_frag] = pix
                f_src[n_frag] = sp_src[first]
                f_area[n_frag] = 1.0
                f_cx[n_frag] = xc
                f_cy[n_frag] = yc
                n_frag += 1
                continue
            # a. a solid piece in front
            if n_pl == 1 and first == solid:
                f_pix[n_frag] = pix
                f_src[n_frag] = sp_src[first]
                f_area[n_frag] = 1.0
                f_cx[n_frag] = xc
                f_cy[n_frag] = yc
                n_frag += 1
                continue
            # a. one irregular piece in front of a solid one (or of the background)
            behind = -2
            if n_pl == 1:
                behind = BACKGROUND
            elif n_pl == 2 and plist[1] == solid and _in_front_on_square(
                    planes, sp_src[first], sp_src[solid], float(col), y_top, eps_z):
                behind = sp_src[solid]
            if behind != -2:
                cv = cov[sp_cov[first] + col - sp_c0[first]]
                icx = xc
                icy = yc
                if centroids:
                    # the irregular piece's centroid: clip it to the pixel column
                    need = 6 * sp_len[first] + 16  # two half-plane clips: up to 2n, then 4n
                    if need > ws_x.size:
                        ws_x = _grow(ws_x, need)
                        ws_y = _grow(ws_y, need)
                        ws_f = _grow(ws_f, need)
                    m1 = clip_side(sp_x, sp_y, sp_f, sp_start[first], sp_len[first], 1.0, 0.0, -float(col), 1,
                                   ws_x, ws_y, ws_f, 0)
                    m2 = clip_side(ws_x, ws_y, ws_f, 0, m1, 1.0, 0.0, -float(col + 1), -1,
                                   ws_x, ws_y, ws_f, m1)
                    if m2 > 0:
                        _, icx, icy = area_centroid(ws_x, ws_y, m1, m2)
                f_pix[n_frag] = pix
                f_src[n_frag] = sp_src[first]
                f_area[n_frag] = cv
                f_cx[n_frag] = icx
                f_cy[n_frag] = icy
                n_frag += 1
                rest = 1.0 - cv
                if rest > 0.0:
                    f_pix[n_frag] = pix
                    f_src[n_frag] = behind
                    f_area[n_frag] = rest
                    f_cx[n_frag] = (xc - cv * icx) / rest
                    f_cy[n_frag] = (yc - cv * icy) / rest
                    n_frag += 1
                continue

            # b. the pixel integrator
            while True:
                nv, n_init = _pixel_polygons(sp_x, sp_y, sp_f, sp_start, sp_len, sp_src, plist, n_pl, solid,
                                     float(col), y_top, ws_x, ws_y, ws_f, w_pstart, w_plen, w_psrc)
                if nv < 0:
                    ws_x = _grow(ws_x, 2 * ws_x.size)
                    ws_y = _grow(ws_y, 2 * ws_y.size)
                    ws_f = _grow(ws_f, 2 * ws_f.size)
                    w_pstart = _grow(w_pstart, 2 * w_pstart.size)
                    w_plen = _grow(w_plen, 2 * w_plen.size)
                    w_psrc = _grow(w_psrc, 2 * w_psrc.size)
                    continue
                n_out = integrate_pixel(ws_x, ws_y, ws_f, w_pstart, w_plen, w_psrc, n_init, planes, eps_z,
                                        litems, lstart, llen, stack, o_src, o_area, o_cx, o_cy, nv)
                if n_out >= 0:
                    break
                ws_x = _grow(ws_x, 2 * ws_x.size)
                ws_y = _grow(ws_y, 2 * ws_y.size)
                ws_f = _grow(ws_f, 2 * ws_f.size)
                w_pstart = _grow(w_pstart, 2 * w_pstart.size)
                w_plen = _grow(w_plen, 2 * w_plen.size)
                w_psrc = _grow(w_psrc, 2 * w_psrc.size)
                litems = _grow(litems, 2 * litems.size)
                lstart = _grow(lstart, 2 * lstart.size)
                llen = _grow(llen, 2 * llen.size)
                stack = _grow(stack, 2 * stack.size)
                o_src = _grow(o_src, 2 * o_src.size)
                o_area = _grow(o_area, 2 * o_area.size)
                o_cx = _grow(o_cx, 2 * o_cx.size)
                o_cy = _grow(o_cy, 2 * o_cy.size)
            # merge the pieces of each polygon: one shade per polygon per pixel
            if n_frag + n_out > f_pix.size:
                f_pix = _grow(f_pix, n_frag + n_out)
                f_src = _grow(f_src, n_frag + n_out)
                f_area = _grow(f_area, n_frag + n_out)
                f_cx = _grow(f_cx, n_frag + n_out)
                f_cy = _grow(f_cy, n_frag + n_out)
            first_frag = n_frag
            for o in range(n_out):
                merged = False
                for g in range(first_frag, n_frag):
                    if f_src[g] == o_src[o]:
                        tot = f_area[g] + o_area[o]
                        if tot > 0.0:
                            f_cx[g] = (f_cx[g] * f_area[g] + o_cx[o] * o_area[o]) / tot
                            f_cy[g] = (f_cy[g] * f_area[g] + o_cy[o] * o_area[o]) / tot
                        f_area[g] = tot
                        merged = True
                        break
                if not merged:
                    f_pix[n_frag] = pix
                    f_src[n_frag] = o_src[o]
                    f_area[n_frag] = o_area[o]
                    f_cx[n_frag] = o_cx[o]
                    f_cy[n_frag] = o_cy[o]
                    n_frag += 1
    return f_pix[:n_frag], f_src[:n_frag], f_area[:n_frag], f_cx[:n_frag], f_cy[:n_frag]


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
def _pixel_polygons(sp_x, sp_y, sp_f, sp_start, sp_len, sp_src, plist, n_pl, solid, x0, y0,
                    ws_x, ws_y, ws_f, w_pstart, w_plen, w_psrc):
    """Clip each listed strip piece to the pixel; a solid piece becomes the pixel square.

    Writes polygon records 0..n-1 (background square last when no piece is solid) and
    returns ``(vertices used, records)``, or ``(-1, 0)`` if the workspace is too small.
    """
    used = 0
    n_out = 0
    n_rec = n_pl + (1 if solid < 0 else 0)
    if n_rec > w_pstart.size:
        return -1, 0
    for t in range(n_rec):
        if t < n_pl and plist[t] != solid:
            k = plist[t]
            n = sp_len[k]
            # a half-plane clip at most doubles the vertex count: the first clip goes
            # above the space the second one (up to 4n) writes into
            tmp = used + 4 * n + 8
            if tmp + 2 * n + 4 > ws_x.size:
                return -1, 0
            # the pixel column: x >= x0 (side B of x - x0), then x <= x0+1 (side A)
            m1 = clip_side(sp_x, sp_y, sp_f, sp_start[k], n, 1.0, 0.0, -x0, 1, ws_x, ws_y, ws_f, tmp)
            m2 = clip_side(ws_x, ws_y, ws_f, tmp, m1, 1.0, 0.0, -(x0 + 1.0), -1, ws_x, ws_y, ws_f, used)
            if m2 == 0:
                continue
            w_pstart[n_out] = used
            w_plen[n_out] = m2
            w_psrc[n_out] = sp_src[k]
            n_out += 1
            used += m2
        else:
            # the pixel square, every edge on the pixel boundary
            if used + 4 > ws_x.size:
                return -1, 0
            ws_x[used] = x0
            ws_y[used] = y0
            ws_x[used + 1] = x0 + 1.0
            ws_y[used + 1] = y0
            ws_x[used + 2] = x0 + 1.0
            ws_y[used + 2] = y0 + 1.0
            ws_x[used + 3] = x0
            ws_y[used + 3] = y0 + 1.0
            for i in range(4):
                ws_f[used + i] = 1
            w_pstart[n_out] = used
            w_plen[n_out] = 4
            w_psrc[n_out] = sp_src[plist[t]] if t < n_pl else BACKGROUND
            n_out += 1
            used += 4
    return used, n_out
