"""Catmull 1978 scanline hidden-surface algorithm with the pixel integrator (numba).

The kernel is a chain of small stages, each a compiled function (``_jit.kernel``: ``njit``, cached) with a named
workspace (a numba structref whose fields are read by name). Data flow, one scanline (a
strip one pixel high) at a time, following the paper's "Hidden-surface Algorithm":

``sort_polygons``   I. the input polygons with their y range, in order of first scanline
    -> :class:`Polygons`
``enter_polygons``  III.A polygons whose first scanline is this one join the active list
    (the part above the image cut away) -> :class:`ActiveList`
``clip_to_strip``   III.C the strip piece is clipped off every active polygon, which keeps
    what remains below; ``strip_coverage`` finds each piece's exact area over every pixel
    column it spans (-∫ y dx per column), which splits it into solid runs and irregular
    ends -> :class:`Strip` (pieces, their column span, coverage)
``bucket_by_x``     III.C.4 pieces listed under their leftmost pixel (a counting sort)
    -> ``Strip.bucket_head`` / ``Strip.bucket_items``
``sweep_row``       III.D/E the pixels of the row, left to right:
    ``update_zlist``   pieces enter from the x-bucket, leave past their last column, and
                       stay sorted front to back at the pixel centre -> :class:`ZList`
    ``pixel_list``     the pixel's polygon list: front to back up to the first solid
                       piece, and what behind it is not hidden everywhere in the pixel
    (then, by case) no piece: the background up to the next piece (``emit_run``); a
                       solid piece in front: its whole run while it stays alone in front
                       (``solid_run``, ``emit_run``); one irregular piece in front of a
                       solid one or of the background: that piece (``emit_strip_piece``,
                       or ``emit_area`` without centroids) and the rest of the pixel
                       (``emit_rest``); otherwise ``integrate``
``integrate``       the pixel integrator: ``pixel_polygons`` clips the listed pieces to
    the pixel (a solid piece becomes the pixel square, the background square goes last),
    ``integrate_pixel`` resolves them (recursive clipping along the front polygon's
    unclipped edges and along the lines where depth planes cross), then every visible
    piece goes to ``emit_piece`` with its vertices -> :class:`PixelWork`

Every result leaves through a *sink*: a structref with five methods, ``emit_pixel``
(the whole pixel square), ``emit_piece`` (a visible piece inside a pixel, as its polygon
vertices), ``emit_area`` (an area without its shape, only with ``centroids=False``) and
``emit_rest`` (the pixel square minus what was already emitted for that pixel), and two
optional ones: ``emit_strip_piece`` (a strip piece alone in front, with the exact area
the strip coverage already gave; sinks without it get ``emit_piece``) and ``emit_run``
(``count`` whole pixels of one row, all one polygon; sinks without it get ``emit_pixel``
per pixel).
:class:`FragmentSink` turns them into fragments: per pixel, each visible polygon's area and
area centroid (its pieces merged), so flat colours and per-piece shading are resolved
outside. Another sink type (for instance one accumulating polynomial moments of each
piece for an exact filter) runs through the same stages via :func:`scanline`, which is
compiled once per sink type.

The rows are run in fixed bands of ``BAND_ROWS`` (``scan_rows(polys, width, row0, row1,
...)``; ``scanline`` runs them all in turn), each started at its top row, so bands are independent: ``band_fragments`` and
``band_colors`` (flat colours straight into the image through :class:`ColorSink`) run
without the GIL on any number of threads, with the same result.

Workspaces grow by doubling; the integrator reports a too-small workspace with -1 and is
rerun after growing it.
"""

from __future__ import annotations

import numpy as np
from numba import njit, types
from numba.experimental import structref
from numba.extending import overload, overload_method

from aaeval._jit import KERNEL_OPTIONS, kernel
from aaeval.renderers._clip import EPS_LINE, area_centroid, clip_side, clip_split, clip_to_column, signed_area

# Coverage within this of 1 is a solid piece; below COV_EMPTY a piece is absent.
COV_SOLID = 1.0 - 1e-12
COV_EMPTY = 1e-15
# Pieces of smaller area are dropped inside the integrator (slivers from rounding).
AREA_EMPTY = 1e-15
# A front polygon with no edge left to clip along that falls short of its list's region
# by more than 1e-9 of it AND by more than this area is a rounding remnant (_is_sliver):
# a band EPS_LINE wide along a unit edge, far above the area that rounding of a vertex
# moves, far below what the tests resolve (a wrong "not a remnant" loses at most this).
SLIVER_SLACK = EPS_LINE
# Safety bound on integrator steps for one pixel; never reached on valid scenes.
MAX_STEPS = 100_000
BACKGROUND = -1


# --- named workspaces -------------------------------------------------------------
# A polygon lives in vertex buffers (x, y, clip flag) as a record (start, length, source).


class _Workspace(types.StructRef):
    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


def define_workspace(proxy, struct_type, fields):
    """Constructor and by-name fields in compiled code, read-only properties in Python
    (for tests and inspection; compiled on first use, not cached)."""
    structref.define_proxy(proxy, struct_type, fields)
    for name in fields:
        getter = njit(eval(f"lambda s: s.{name}"))  # numba reads attributes by literal name only
        setattr(proxy, name, property(lambda self, get=getter: get(self)))


@structref.register
class PolygonsType(_Workspace):
    pass


class Polygons(structref.StructRefProxy):
    """The input polygons: ``x, y[start[p] : start[p] + length[p]]``, depth ``planes[p]``
    (z = a x + b y + c), y range ``ymin, ymax``, and ``order``: indices sorted on ymin."""


define_workspace(Polygons, PolygonsType, ["start", "length", "x", "y", "planes", "ymin", "ymax", "order"])


@structref.register
class ActiveListType(_Workspace):
    pass


class ActiveList(structref.StructRefProxy):
    """The active polygons' remaining parts (below the current scanline).

    ``recs[:n]`` are records into the vertex buffers ``x, y, f`` (``used`` entries
    taken); ``spare_*`` is the second buffer the next remainders are written to.
    ``next_in`` counts the polygons of ``Polygons.order`` that have entered.
    """


define_workspace(ActiveList, ActiveListType,
                       ["x", "y", "f", "spare_x", "spare_y", "spare_f", "recs", "n", "used", "next_in"])


@structref.register
class StripType(_Workspace):
    pass


class Strip(structref.StructRefProxy):
    """This scanline's strip pieces.

    ``pieces[:n]`` are records into ``x, y, f``; ``span[k] = (first column, last column,
    offset into cov)``; ``cov[span[k, 2] + c - span[k, 0]]`` is piece k's exact area in
    column c. The x-bucket: pieces ``bucket_items[bucket_head[c] : bucket_head[c + 1]]``
    have leftmost column c.
    """


define_workspace(Strip, StripType,
                       ["x", "y", "f", "pieces", "span", "cov", "n", "used", "cov_used", "bucket_head", "bucket_items"])


@structref.register
class ZListType(_Workspace):
    pass


class ZList(structref.StructRefProxy):
    """The z-list (strip pieces over the current pixel, front to back, ``depth`` at the
    pixel centre) and ``pixel``, the current pixel's polygon list."""


define_workspace(ZList, ZListType, ["items", "depth", "pixel"])


@structref.register
class PixelWorkType(_Workspace):
    """The pixel integrator's workspace."""


class PixelWork(structref.StructRefProxy):
    """The pixel integrator's workspace.

    Polygons are records ``recs[j] = (start, length, source)`` into ``x, y, f`` with
    their signed area ``areas[j]`` (found once, when the polygon is made);
    ``items`` holds the lists' members, ``lists[L] = (first item, count)``, ``stack`` the
    lists still to resolve, ``visible`` the records of the visible pieces found.
    """


define_workspace(PixelWork, PixelWorkType, ["x", "y", "f", "recs", "areas", "items", "lists", "stack", "visible"])


@structref.register
class FragmentSinkType(_Workspace):
    pass


class FragmentSink(structref.StructRefProxy):
    """Fragments ``[:n]``: pixel, source polygon (-1: background), area, area centroid."""


define_workspace(FragmentSink, FragmentSinkType, ["pix", "src", "area", "cx", "cy", "n"])


# --- growable buffers -------------------------------------------------------------


@kernel
def _grow(a, n):
    """``a`` with room for at least ``n`` entries along its first axis (contents kept)."""
    if n <= a.shape[0]:
        return a
    b = np.empty((max(n, 2 * a.shape[0]),) + a.shape[1:], a.dtype)
    b[: a.shape[0]] = a
    return b


@kernel
def _grow_verts(x, y, f, n):
    return _grow(x, n), _grow(y, n), _grow(f, n)


@kernel
def _new_verts(n):
    return np.empty(n), np.empty(n), np.zeros(n, np.uint8)


@kernel(inline="always")
def _record(recs, k, start, length, src):
    recs[k, 0] = start
    recs[k, 1] = length
    recs[k, 2] = src
    return k + 1


@kernel
def new_active_list(n_polys):
    x, y, f = _new_verts(1024)
    sx, sy, sf = _new_verts(1024)
    return ActiveList(x, y, f, sx, sy, sf, np.empty((n_polys, 3), np.int64), 0, 0, 0)


@kernel
def new_strip(n_polys, width):
    x, y, f = _new_verts(1024)
    return Strip(x, y, f, np.empty((n_polys, 3), np.int64), np.empty((n_polys, 3), np.int64), np.empty(1024),
                 0, 0, 0, np.zeros(width + 1, np.int64), np.empty(n_polys, np.int64))


@kernel
def new_zlist(n_polys):
    return ZList(np.empty(n_polys, np.int64), np.empty(n_polys), np.empty(n_polys + 1, np.int64))


@kernel
def new_pixel_work():
    x, y, f = _new_verts(4096)
    return PixelWork(x, y, f, np.empty((1024, 3), np.int64), np.empty(1024), np.empty(4096, np.int64),
                     np.empty((1024, 2), np.int64), np.empty(1024, np.int64), np.empty(256, np.int64))


@kernel
def grow_pixel_work(work):
    """Double every buffer of the integrator's workspace."""
    work.x, work.y, work.f = _grow_verts(work.x, work.y, work.f, 2 * work.x.shape[0])
    work.recs = _grow(work.recs, 2 * work.recs.shape[0])
    work.areas = _grow(work.areas, 2 * work.areas.shape[0])
    work.items = _grow(work.items, 2 * work.items.shape[0])
    work.lists = _grow(work.lists, 2 * work.lists.shape[0])
    work.stack = _grow(work.stack, 2 * work.stack.shape[0])
    work.visible = _grow(work.visible, 2 * work.visible.shape[0])


@kernel
def new_fragment_sink(capacity):
    return FragmentSink(np.empty(capacity, np.int64), np.empty(capacity, np.int64), np.empty(capacity),
                        np.empty(capacity), np.empty(capacity), 0)


# --- the fragment sink ------------------------------------------------------------


@kernel(inline="always")
def _append(out, pix, src, area, cx, cy):
    n = out.n
    if n >= out.pix.shape[0]:
        _grow_sink(out, n + 1)
    out.pix[n] = pix
    out.src[n] = src
    out.area[n] = area
    out.cx[n] = cx
    out.cy[n] = cy
    out.n = n + 1


@kernel
def _grow_sink(out, n):
    out.pix = _grow(out.pix, n)
    out.src = _grow(out.src, n)
    out.area = _grow(out.area, n)
    out.cx = _grow(out.cx, n)
    out.cy = _grow(out.cy, n)


@overload_method(FragmentSinkType, "emit_pixel", jit_options=KERNEL_OPTIONS)
def _emit_pixel(out, pix, src, x0, y0):
    """The whole pixel square ``[x0, x0+1] x [y0, y0+1]`` is polygon ``src``."""
    def impl(out, pix, src, x0, y0):
        _append(out, pix, src, 1.0, x0 + 0.5, y0 + 0.5)
    return impl


@overload_method(FragmentSinkType, "emit_area", jit_options=KERNEL_OPTIONS)
def _emit_area(out, pix, src, area, x0, y0):
    """``area`` of the pixel is polygon ``src``; its shape is not known (centre used)."""
    def impl(out, pix, src, area, x0, y0):
        _append(out, pix, src, area, x0 + 0.5, y0 + 0.5)
    return impl


@overload_method(FragmentSinkType, "emit_piece", jit_options=KERNEL_OPTIONS)
def _emit_piece(out, pix, src, xs, ys, start, n):
    """A visible piece of polygon ``src`` in the pixel: the polygon ``xs, ys[start:start+n]``.

    Pieces of one polygon in one pixel merge into one fragment (area-weighted centroid).
    """
    def impl(out, pix, src, xs, ys, start, n):
        area, cx, cy = area_centroid(xs, ys, start, n)
        g = out.n - 1
        while g >= 0 and out.pix[g] == pix and out.src[g] != src:
            g -= 1
        if g < 0 or out.pix[g] != pix:
            _append(out, pix, src, area, cx, cy)
            return
        total = out.area[g] + area
        if total > 0.0:
            out.cx[g] = (out.cx[g] * out.area[g] + cx * area) / total
            out.cy[g] = (out.cy[g] * out.area[g] + cy * area) / total
        out.area[g] = total
    return impl


@overload_method(FragmentSinkType, "emit_strip_piece", jit_options=KERNEL_OPTIONS)
def _emit_strip_piece(out, pix, src, area, xs, ys, start, n):
    """Strip piece of polygon ``src`` clipped to the pixel, ``xs, ys[start:start+n]``, whose
    exact area ``area`` is known from the strip coverage (the first fragment of its pixel).

    The coverage's area is kept, so fragments with and without centroids agree exactly.
    """
    def impl(out, pix, src, area, xs, ys, start, n):
        _, cx, cy = area_centroid(xs, ys, start, n)
        _append(out, pix, src, area, cx, cy)
    return impl


@overload_method(FragmentSinkType, "emit_rest", jit_options=KERNEL_OPTIONS)
def _emit_rest(out, pix, src, x0, y0):
    """Polygon ``src`` covers the rest of the pixel: the square minus what was emitted
    for this pixel so far (the sink's last fragments)."""
    def impl(out, pix, src, x0, y0):
        first = out.n
        while first > 0 and out.pix[first - 1] == pix:
            first -= 1
        covered = 0.0
        mx = 0.0
        my = 0.0
        for g in range(first, out.n):
            covered += out.area[g]
            mx += out.area[g] * out.cx[g]
            my += out.area[g] * out.cy[g]
        rest = 1.0 - covered
        if rest > 0.0:
            _append(out, pix, src, rest, (x0 + 0.5 - mx) / rest, (y0 + 0.5 - my) / rest)
    return impl


def emit_strip_piece(out, pix, src, area, xs, ys, start, n):
    """``out.emit_strip_piece(...)`` where the sink has that method, else ``out.emit_piece``
    with the vertices (the method is optional: it only lets a sink keep the strip
    coverage's area)."""
    raise NotImplementedError("compiled code only")


def _has_method(sink_type, name):
    """Whether a sink type defines the optional method ``name`` (at compile time)."""
    from numba.core.registry import cpu_target

    return cpu_target.typing_context.resolve_getattr(sink_type, name) is not None


@overload(emit_strip_piece, jit_options=KERNEL_OPTIONS)
def _emit_strip_piece_or_piece(out, pix, src, area, xs, ys, start, n):
    if _has_method(out, "emit_strip_piece"):
        def impl(out, pix, src, area, xs, ys, start, n):
            out.emit_strip_piece(pix, src, area, xs, ys, start, n)
    else:
        def impl(out, pix, src, area, xs, ys, start, n):
            out.emit_piece(pix, src, xs, ys, start, n)
    return impl


def emit_run(out, row, width, c0, c1, src):
    """The whole pixels ``c0 .. c1`` of ``row`` are polygon ``src``: ``out.emit_run`` where
    the sink has that method (one call for the run), else ``out.emit_pixel`` per pixel."""
    raise NotImplementedError("compiled code only")


@overload(emit_run, jit_options=KERNEL_OPTIONS)
def _emit_run_or_pixels(out, row, width, c0, c1, src):
    if _has_method(out, "emit_run"):
        def impl(out, row, width, c0, c1, src):
            if c1 >= c0:
                out.emit_run(row * width + c0, c1 - c0 + 1, src, float(c0), float(row))
    else:
        def impl(out, row, width, c0, c1, src):
            for c in range(c0, c1 + 1):
                out.emit_pixel(row * width + c, src, float(c), float(row))
    return impl


# --- depth relations --------------------------------------------------------------


@kernel(inline="always")
def _depth(planes, p, x, y):
    return planes[p, 0] * x + planes[p, 1] * y + planes[p, 2]


@kernel(inline="always")
def in_front_on_square(planes, p, q, x0, y0, eps_z):
    """Whether polygon p hides polygon q everywhere over the square [x0,x0+1]x[y0,y0+1].

    Depth differences are linear, so the four corners decide. On one shared plane the
    one later in the file is in front (the scene format's rule).
    """
    # (one exit only, as every inlined helper with array arguments: see _first_clip_edge)
    hides = q == BACKGROUND
    if q != BACKGROUND and p != BACKGROUND:
        lo = np.inf
        hi = -np.inf
        for cx in (x0, x0 + 1.0):
            for cy in (y0, y0 + 1.0):
                d = _depth(planes, p, cx, cy) - _depth(planes, q, cx, cy)
                lo = min(lo, d)
                hi = max(hi, d)
        hides = p > q if hi <= eps_z and lo >= -eps_z else hi <= eps_z
    return hides


@kernel(inline="always")
def depth_relation(planes, q, f, xs, ys, start, n, eps_z):
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


# --- I. and III.A: polygons enter the active list ---------------------------------


@kernel
def sort_polygons(start, length, x, y, planes):
    """The input polygons with their y range, ordered on their first scanline."""
    n_polys = start.size
    ymin = np.empty(n_polys)
    ymax = np.empty(n_polys)
    for p in range(n_polys):
        ymin[p] = y[start[p]:start[p] + length[p]].min()
        ymax[p] = y[start[p]:start[p] + length[p]].max()
    return Polygons(start, length, x, y, planes, ymin, ymax, np.argsort(ymin, kind="mergesort"))


@kernel
def _below(vx0, vy0, start, n, y_top, out_x, out_y, out_f, at):
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


@kernel
def enter_polygons(polys, active, row):
    """Polygons whose first scanline is ``row`` join the active list (their part y >= row)."""
    y_top = float(row)
    y_bot = y_top + 1.0
    order = polys.order
    n_polys = order.size
    next_in = active.next_in
    while next_in < n_polys and polys.ymin[order[next_in]] < y_bot:
        p = order[next_in]
        next_in += 1
        if polys.ymax[p] <= y_top:
            continue
        n = polys.length[p]
        active.x, active.y, active.f = _grow_verts(active.x, active.y, active.f, active.used + 2 * n + 4)
        m = _below(polys.x, polys.y, polys.start[p], n, y_top, active.x, active.y, active.f, active.used)
        if m > 0:
            active.n = _record(active.recs, active.n, active.used, m, p)
            active.used += m
    active.next_in = next_in


# --- III.C: the strip pieces ------------------------------------------------------


@kernel
def strip_coverage(xs, ys, start, n, row, c0, c1, cov, cov_off):
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
        if y0 == y1 and cb - ca > 1:
            # a level edge (the strip's top or bottom): the columns it fully crosses get
            # -y0 per unit of x (the same bits as the general formula below); only its
            # two end columns need that formula
            _edge_coverage(x0, y0, x1, slope, ca, ca, c0, cov, cov_off)
            full = y0 if x1 > x0 else -y0
            for col in range(ca + 1, cb):
                cov[cov_off + col - c0] -= full
            _edge_coverage(x0, y0, x1, slope, cb, cb, c0, cov, cov_off)
        else:
            _edge_coverage(x0, y0, x1, slope, ca, cb, c0, cov, cov_off)


@kernel(inline="always")
def _edge_coverage(x0, y0, x1, slope, ca, cb, c0, cov, cov_off):
    """Add -∫ y dx of the edge from x0 to x1 over each column ca..cb."""
    for col in range(ca, cb + 1):
        xa = min(max(x0, col), col + 1.0)
        xb = min(max(x1, col), col + 1.0)
        if xa == xb:
            continue
        ya = y0 + slope * (xa - x0)
        yb = y0 + slope * (xb - x0)
        cov[cov_off + col - c0] -= 0.5 * (xb - xa) * (ya + yb)


@kernel(inline="always")
def _column_span(xs, start, m, width):
    """The pixel columns a piece's x range reaches, clamped to the image."""
    lo = xs[start]
    hi = xs[start]
    for i in range(start + 1, start + m):
        lo = min(lo, xs[i])
        hi = max(hi, xs[i])
    return max(int(np.floor(lo)), 0), min(int(np.ceil(hi)) - 1, width - 1)


@kernel
def clip_to_strip(active, strip, row, width):
    """Clip this scanline's piece off every active polygon into ``strip``; keep the rest.

    The line y = row + 1 splits each polygon: side A (above) is the strip piece, with
    its coverage of every column; side B replaces the polygon in the active list. A
    piece is kept if it covers a column. (Every workspace field is read once into a
    local and written back at the end: a structref field read costs a reference count.)
    """
    y_bot = float(row) + 1.0
    rx = active.x
    ry = active.y
    rf = active.f
    nx = active.spare_x
    ny = active.spare_y
    nf = active.spare_f
    recs = active.recs
    sx = strip.x
    sy = strip.y
    sf = strip.f
    pieces = strip.pieces
    span = strip.span
    cov = strip.cov
    used = 0
    n_pieces = 0
    cov_used = 0
    new_used = 0
    keep = 0
    for k in range(active.n):
        s = recs[k, 0]
        n = recs[k, 1]
        src = recs[k, 2]
        if used + 2 * n + 4 > sx.shape[0]:
            sx, sy, sf = _grow_verts(sx, sy, sf, used + 2 * n + 4)
        if new_used + 2 * n + 4 > nx.shape[0]:
            nx, ny, nf = _grow_verts(nx, ny, nf, new_used + 2 * n + 4)
        m, m2 = clip_split(rx, ry, rf, s, n, 0.0, 1.0, -y_bot, True, True,
                           sx, sy, sf, used, nx, ny, nf, new_used)
        if m > 0 and signed_area(sx, sy, used, m) > COV_EMPTY:
            c0, c1 = _column_span(sx, used, m, width)
            if c1 >= c0:
                if cov_used + c1 - c0 + 1 > cov.shape[0]:
                    cov = _grow(cov, cov_used + c1 - c0 + 1)
                strip_coverage(sx, sy, used, m, float(row), c0, c1, cov, cov_used)
                span[n_pieces, 0] = c0
                span[n_pieces, 1] = c1
                span[n_pieces, 2] = cov_used
                n_pieces = _record(pieces, n_pieces, used, m, src)
                cov_used += c1 - c0 + 1
                used += m
        if m2 > 0 and signed_area(nx, ny, new_used, m2) > COV_EMPTY:
            keep = _record(recs, keep, new_used, m2, src)
            new_used += m2
    strip.x = sx
    strip.y = sy
    strip.f = sf
    strip.cov = cov
    strip.n = n_pieces
    strip.used = used
    strip.cov_used = cov_used
    active.n = keep
    active.used = new_used
    # the remainders' buffer becomes the active one
    active.x, active.spare_x = nx, rx
    active.y, active.spare_y = ny, ry
    active.f, active.spare_f = nf, rf


@kernel
def bucket_by_x(strip, width):
    """The x-bucket: list the strip pieces under their leftmost column (counting sort)."""
    head = strip.bucket_head
    items = strip.bucket_items
    span = strip.span
    head[:] = 0
    for k in range(strip.n):
        head[span[k, 0] + 1] += 1
    for col in range(width):
        head[col + 1] += head[col]
    fill = head[:width].copy()
    for k in range(strip.n):
        items[fill[span[k, 0]]] = k
        fill[span[k, 0]] += 1


# --- III.D/E: sweeping the row ----------------------------------------------------


@kernel(inline="always")
def update_zlist(zl, zdepth, n_zl, bucket_head, bucket_items, span, pieces, planes, col, row):
    """Move the z-list to column ``col``; returns its new length.

    Pieces of the x-bucket at this column enter, pieces that ended to the left leave,
    and the list is sorted front to back on depth at the pixel centre (ties: the later
    polygon first). Insertion sort is linear while the order holds from pixel to pixel.
    """
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
    return n_zl


@kernel(inline="always")
def pixel_list(zl, n_zl, plist, pieces, span, cov, planes, col, row, eps_z):
    """The pixel's polygon list ``plist``: front to back up to the first solid piece, and
    anything behind that piece not hidden by it everywhere in the pixel.

    Returns ``(length, solid)``, ``solid`` the strip piece covering the whole pixel
    (-1 if none).
    """
    n_pl = 0
    solid = -1
    for t in range(n_zl):
        k = zl[t]
        cv = cov[span[k, 2] + col - span[k, 0]]
        if cv <= COV_EMPTY:
            continue
        if solid >= 0 and in_front_on_square(planes, pieces[solid, 2], pieces[k, 2], float(col), float(row), eps_z):
            continue
        plist[n_pl] = k
        n_pl += 1
        if solid < 0 and cv >= COV_SOLID:
            solid = k
    return n_pl, solid


@kernel
def emit_front_piece(strip, k, pix, col, row, work, out):
    """Emit strip piece k's part in pixel column ``col`` with its shape (its area alone
    if clipping leaves nothing). ``work`` has room for ``6 n + 16`` vertices (n: the
    piece's); the caller grows it (``front_piece_room``)."""
    cv = strip.cov[strip.span[k, 2] + col - strip.span[k, 0]]
    src = strip.pieces[k, 2]
    n = strip.pieces[k, 1]
    m = clip_to_column(strip.x, strip.y, strip.f, strip.pieces[k, 0], n, float(col),
                       work.x, work.y, work.f, 0, 4 * n + 8)
    if m > 0:
        emit_strip_piece(out, pix, src, cv, work.x, work.y, 0, m)
    else:
        out.emit_area(pix, src, cv, float(col), float(row))


@kernel(inline="always")
def _hidden_until(planes, p, q, col, end, row, width):
    """The last column in ``col .. end`` up to which polygon p hides polygon q over every
    pixel square by a safe margin (``col - 1`` if it does not at ``col``).

    z_p - z_q = da x + db y + dc is linear, so its largest corner value on the square
    [x0, x0+1] x [y0, y0+1] is linear in x0: the bound is found in closed form, then
    checked. The margin is far above the rounding of any depth evaluation, so where this
    holds the per-pixel tests (``update_zlist``, ``in_front_on_square``) agree.
    """
    da = planes[p, 0] - planes[q, 0]
    db = planes[p, 1] - planes[q, 1]
    dc = planes[p, 2] - planes[q, 2]
    y0 = float(row)
    margin = 1e-9 * ((abs(planes[p, 0]) + abs(planes[q, 0]) + abs(planes[p, 1]) + abs(planes[q, 1]))
                     * (width + y0 + 2.0) + abs(planes[p, 2]) + abs(planes[q, 2]) + 1.0)
    rest = max(da, 0.0) + db * y0 + max(db, 0.0) + dc
    # (one exit only, as every inlined helper with array arguments: see _first_clip_edge)
    if da * col + rest >= -margin:
        last = col - 1
    elif da <= 0.0 or da * end + rest < -margin:
        last = end
    else:
        last = min(int(np.floor((-margin - rest) / da)), end)
        while last >= col and da * last + rest >= -margin:
            last -= 1
    return last


@kernel
def solid_run(k, zl, n_zl, bucket_head, bucket_items, span, pieces, cov, planes, col, row, width):
    """How far strip piece k, alone and solid in front at ``col``, stays so without any
    per-pixel work: returns ``(last column, z-list length)``.

    The run goes on while k covers whole pixels and hides every other piece of the
    z-list over the whole pixel square; pieces entering the z-list inside the run are
    added to it (the run stops before one that k does not hide), so the z-list is as
    the per-pixel sweep would have it. Within the run every pixel is k's.
    """
    p = pieces[k, 2]
    end = min(span[k, 1], width - 1)
    c = col + 1
    while c <= end and cov[span[k, 2] + c - span[k, 0]] >= COV_SOLID:
        c += 1
    end = c - 1
    for t in range(n_zl):
        if end <= col:
            return col, n_zl
        if zl[t] != k:
            end = min(end, _hidden_until(planes, p, pieces[zl[t], 2], col + 1, end, row, width))
    c = col + 1
    while c <= end:
        for t in range(bucket_head[c], bucket_head[c + 1]):
            q = bucket_items[t]
            last = _hidden_until(planes, p, pieces[q, 2], c, end, row, width)
            if last < c:
                return c - 1, n_zl  # q enters at c visible: the per-pixel sweep takes over
            end = min(end, last)
        for t in range(bucket_head[c], bucket_head[c + 1]):
            zl[n_zl] = bucket_items[t]
            n_zl += 1
        c += 1
    return end, n_zl


CONVEX_SLACK = 1e-12  # a turn the other way by less than this (pixel area units) is rounding


@kernel
def two_layer_overlap(sx, sy, sf, pieces, ka, kb, x0, wx, wy, wf):
    """Area of strip piece ka's part in pixel column ``x0`` overlapping piece kb's, or -1.0
    if ka's part is not convex there (or the scratch space ``wx, wy, wf`` is too small).

    For a pixel whose visible pieces are ka in front of kb in front of what both hide,
    the areas are ka's coverage, kb's coverage minus this overlap, and the rest: no
    integrator needed (areas only: no shapes). The overlap is kb's pixel part clipped by
    each of ka's own edges in turn (for a convex part, the intersection of their
    half-planes); ka's clipped edges lie on the pixel's boundary lines, inside which
    kb's part already is.
    """
    na = pieces[ka, 1]
    nb = pieces[kb, 1]
    at_b = 2 * na + 4  # each clip's output (a clip adds at most one vertex per edge)
    tmp = at_b + 2 * nb + 4  # scratch of the column clips, then the overlap clips
    cap = 2 * nb + 2 * na + 8  # the overlap is kb's part cut by at most na lines
    result = -1.0
    if tmp + 2 * cap + 2 * nb + 8 <= wx.shape[0]:
        ma = clip_to_column(sx, sy, sf, pieces[ka, 0], na, x0, wx, wy, wf, 0, tmp)
        mb = clip_to_column(sx, sy, sf, pieces[kb, 0], nb, x0, wx, wy, wf, at_b, tmp)
        convex = True  # (and with no part of ka or kb here, the overlap is empty)
        if ma < 3 or mb < 3:
            ma = 0
            mb = 0
        for i in range(ma):
            j = (i + 1) % ma
            k = (i + 2) % ma
            turn = (wx[j] - wx[i]) * (wy[k] - wy[j]) - (wy[j] - wy[i]) * (wx[k] - wx[j])
            convex = convex and turn >= -CONVEX_SLACK
        if convex:
            cur = at_b
            m = mb
            spare = tmp
            for i in range(ma):
                j = (i + 1) % ma
                ex = wx[j] - wx[i]
                ey = wy[j] - wy[i]
                norm = np.sqrt(ex * ex + ey * ey)
                if wf[i] == 0 and norm > EPS_LINE and m > 0:
                    a = ey / norm
                    b = -ex / norm
                    m = clip_side(wx, wy, wf, cur, m, a, b, -(a * wx[i] + b * wy[i]), -1, wx, wy, wf, spare)
                    cur, spare = spare, (tmp + cap if spare == tmp else tmp)
            result = signed_area(wx, wy, cur, m) if m >= 3 else 0.0
            result = max(result, 0.0)
    return result


@kernel
def sweep_row(strip, zlist, work, out, planes, row, width, eps_z, jagged, centroids):
    """Sweep the pixels of ``row`` left to right, emitting each pixel's visible pieces
    by the cheapest case that applies:

    - no piece: the background, up to the next piece's column (``emit_run``);
    - a solid piece alone in front: its whole solid run (``solid_run``, ``emit_run``);
      the per-pixel z-list and pixel-list work is skipped there;
    - with the integrator switched off (``jagged``): the nearest piece, whole pixel;
    - one irregular piece over what it hides: that piece
      (``emit_front_piece`` with its shape, or ``emit_area`` without centroids) and the
      rest of the pixel (``emit_rest``);
    - areas only (no centroids): two irregular pieces over what both hide, the front one
      convex in the pixel (``two_layer_overlap``): the front one's coverage, the back
      one's coverage minus the overlap, and the rest;
    - otherwise the pixel integrator (``integrate``).

    The cases are written out here, not in inlined helpers: an inlined function's array
    arguments are reference-counted copies where calls follow (two atomic operations
    each, per pixel).
    """
    zl = zlist.items
    zdepth = zlist.depth
    plist = zlist.pixel
    pieces = strip.pieces
    span = strip.span
    cov = strip.cov
    head = strip.bucket_head
    items = strip.bucket_items
    # the integrator's results, read once: these names are never reassigned (a variable
    # reassigned in the loop is reference-counted at every use). Once the workspace
    # grows they are stale, and the rest of the row goes through ``integrate`` (the
    # areas-only case only borrows them as scratch, checking their size itself).
    wx = work.x
    wy = work.y
    wf = work.f
    wrecs = work.recs
    wvis = work.visible
    grown = False
    y0 = float(row)
    n_zl = 0
    col = 0
    while col < width:
        n_zl = update_zlist(zl, zdepth, n_zl, head, items, span, pieces, planes, col, row)
        n_pl, solid = pixel_list(zl, n_zl, plist, pieces, span, cov, planes, col, row, eps_z)
        pix = row * width + col
        x0 = float(col)
        if n_pl == 0:
            end = col
            if n_zl == 0:
                while end + 1 < width and head[end + 1] == head[end + 2]:
                    end += 1
            emit_run(out, row, width, col, end, BACKGROUND)
            col = end + 1
            continue
        first = plist[0]
        if n_pl == 1 and first == solid:
            end, n_zl = solid_run(solid, zl, n_zl, head, items, span, pieces, cov, planes, col, row, width)
            emit_run(out, row, width, col, end, pieces[solid, 2])
            col = end + 1
            continue
        if jagged:
            out.emit_pixel(pix, pieces[first, 2], x0, y0)
        else:
            # one irregular piece in front of all that is left, which it hides: the
            # background, or a solid piece behind it over the whole square (-2: neither)
            behind = -2
            if n_pl == 1:
                behind = BACKGROUND
            elif n_pl == 2 and plist[1] == solid and in_front_on_square(planes, pieces[first, 2],
                                                                        pieces[solid, 2], x0, y0, eps_z):
                behind = pieces[solid, 2]
            # areas only: two irregular pieces over what both hide, the front one convex
            # in the pixel (two_layer_overlap; -1.0: not this case)
            overlap = -1.0
            if behind == -2 and not centroids and (n_pl == 2 and solid < 0 or n_pl == 3 and plist[2] == solid):
                back = BACKGROUND if n_pl == 2 else pieces[solid, 2]
                second = plist[1]
                if in_front_on_square(planes, pieces[first, 2], pieces[second, 2], x0, y0, eps_z) \
                        and (n_pl == 2 or in_front_on_square(planes, pieces[second, 2], back, x0, y0, eps_z)
                             and in_front_on_square(planes, pieces[first, 2], back, x0, y0, eps_z)):
                    overlap = two_layer_overlap(strip.x, strip.y, strip.f, pieces, first, second, x0, wx, wy, wf)
            if behind != -2:
                if centroids:
                    if work.x.shape[0] < 6 * pieces[first, 1] + 16:
                        work.x, work.y, work.f = _grow_verts(work.x, work.y, work.f, 6 * pieces[first, 1] + 16)
                        grown = True
                    emit_front_piece(strip, first, pix, col, row, work, out)
                else:
                    out.emit_area(pix, pieces[first, 2], cov[span[first, 2] + col - span[first, 0]], x0, y0)
                out.emit_rest(pix, behind, x0, y0)
            elif overlap >= 0.0:
                out.emit_area(pix, pieces[first, 2], cov[span[first, 2] + col - span[first, 0]], x0, y0)
                second_visible = cov[span[second, 2] + col - span[second, 0]] - overlap
                if second_visible > 0.0:
                    out.emit_area(pix, pieces[second, 2], second_visible, x0, y0)
                out.emit_rest(pix, back, x0, y0)
            else:
                if not grown:
                    n_out = integrate_visible(strip, plist, n_pl, solid, x0, y0, planes, eps_z, work)
                    grown = n_out < 0
                    for o in range(n_out):
                        r = wvis[o]
                        out.emit_piece(pix, wrecs[r, 2], wx, wy, wrecs[r, 0], wrecs[r, 1])
                if grown:
                    # the workspace is (or was) too small: integrate grows it and emits
                    integrate(strip, plist, n_pl, solid, x0, y0, planes, eps_z, pix, work, out)
        col += 1


# --- III.E.b: the pixel integrator ------------------------------------------------


@kernel(inline="always")
def pixel_polygons(strip, plist, n_pl, solid, x0, y0, work):
    """The pixel's polygon list as integrator records, background square last if needed.

    Each listed strip piece is clipped to the pixel column; a solid piece becomes the
    pixel square with every edge flagged. Returns ``(vertices used, records)``, or
    ``(-1, 0)`` if the workspace is too small.
    """
    wx = work.x
    wy = work.y
    wf = work.f
    recs = work.recs
    areas = work.areas
    pieces = strip.pieces
    sx = strip.x
    sy = strip.y
    sf = strip.f
    used = 0
    n_rec = 0
    total = n_pl + (1 if solid < 0 else 0)
    # one exit only (see _first_clip_edge): a full workspace sets used = -1 and ends the loop
    if total > recs.shape[0]:
        used = -1
    t = 0
    while t < total and used >= 0:
        if t < n_pl and plist[t] != solid:
            k = plist[t]
            n = pieces[k, 1]
            # the first clip goes above the space the second one (up to 4n) writes into
            tmp = used + 4 * n + 8
            if tmp + 2 * n + 4 > wx.shape[0]:
                used = -1
            else:
                m = clip_to_column(sx, sy, sf, pieces[k, 0], n, x0, wx, wy, wf, used, tmp)
                if m > 0:
                    areas[n_rec] = signed_area(wx, wy, used, m)
                    n_rec = _record(recs, n_rec, used, m, pieces[k, 2])
                    used += m
        elif used + 4 > wx.shape[0]:
            used = -1
        else:
            for i, (px, py) in enumerate(((x0, y0), (x0 + 1.0, y0), (x0 + 1.0, y0 + 1.0), (x0, y0 + 1.0))):
                wx[used + i] = px
                wy[used + i] = py
                wf[used + i] = 1
            areas[n_rec] = signed_area(wx, wy, used, 4)
            n_rec = _record(recs, n_rec, used, 4, pieces[plist[t], 2] if t < n_pl else BACKGROUND)
            used += 4
        t += 1
    return used, (n_rec if used >= 0 else 0)


@kernel(inline="always")
def _is_sliver(areas, litems, s0, cnt):
    """Whether the front polygon of a list is much smaller than the list's region.

    Every list holds a polygon spanning its whole region (the background or a solid
    piece, only ever clipped by the region's own lines), so the region's area is the
    largest area in the list. F and that polygon reach the region's corners through
    different clips, so their vertices may differ by rounding: a shortfall within
    ``SLIVER_SLACK`` (absolute) is rounding, not a remnant. Without it a tiny region
    (a thin wedge along two almost collinear edges, as where two polygons touch at one
    vertex) that F truly covers, compared on relative areas alone, was dropped and its
    area given to what lies behind (2e-8 off GEOS).
    """
    f = litems[s0]
    area_f = areas[f]
    region = area_f
    for i in range(1, cnt):
        q = litems[s0 + i]
        region = max(region, areas[q])
    shortfall = region - area_f
    return shortfall > region * 1e-9 and shortfall > SLIVER_SLACK


@kernel(inline="always")
def _first_clip_edge(wx, wy, wf, fs, fn):
    """The line of the first unclipped, non-degenerate edge of a polygon: (found, a, b, c).

    One exit only: an inlined helper returning from inside its loop leaves its array
    arguments reference-counted at every call (two atomic operations each)."""
    found = False
    a = 0.0
    b = 0.0
    c = 0.0
    k = 0
    while k < fn and not found:
        if wf[fs + k] == 0:
            k2 = fs + (k + 1) % fn
            ex = wx[k2] - wx[fs + k]
            ey = wy[k2] - wy[fs + k]
            norm = np.sqrt(ex * ex + ey * ey)
            if norm > EPS_LINE:
                a = ey / norm
                b = -ex / norm
                c = -(a * wx[fs + k] + b * wy[fs + k])
                found = True
        k += 1
    return found, a, b, c


@kernel(inline="always")
def integrate_pixel(work, n_init, n_vert, planes, eps_z):
    """Resolve the polygon list ``work.recs[0:n_init]`` (front to back, background last).

    Vertices from ``n_vert`` on are free. Writes the records of the visible pieces to
    ``work.visible`` and returns their count, or -1 if a buffer was too small (the
    caller grows the workspace and calls again).
    """
    wx = work.x
    wy = work.y
    wf = work.f
    recs = work.recs
    areas = work.areas
    litems = work.items
    lists = work.lists
    stack = work.stack
    visible = work.visible
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
    moved_list = -1  # the list whose front was just replaced, and how many times in a row
    moves = 0
    while top > 0 and steps < MAX_STEPS:
        steps += 1
        top -= 1
        L = stack[top]
        s0 = lists[L, 0]
        cnt = lists[L, 1]
        if L != moved_list:
            moved_list = -1
            moves = 0
        f = litems[s0]
        src_f = recs[f, 2]
        # 2. the first unclipped (and not degenerate) edge of the front polygon
        clip = False
        a = 0.0
        b = 0.0
        c = 0.0
        if cnt > 1:
            clip, a, b, c = _first_clip_edge(wx, wy, wf, recs[f, 0], recs[f, 1])
        if cnt > 1 and not clip and _is_sliver(areas, litems, s0, cnt):
            # F has no edge left to clip along, so it should be the whole region; when it
            # is smaller it is a rounding remnant (a spike along two clip lines, or edges
            # too short to clip along): it is dropped and the list looked at again
            for i in range(cnt - 1):
                litems[s0 + i] = litems[s0 + i + 1]
            lists[L, 1] = cnt - 1
            stack[top] = L
            top += 1
            moved_list = -1
            continue
        if cnt > 1 and not clip and moves >= cnt:
            # more fronts than members: the move-to-front went round a cycle, which only
            # the shared-plane tolerance can close (A ties B, B ties C, A is in front of C
            # by more than eps_z: depth_relation is not transitive). Every polygon of the
            # cycle is within a few eps_z of the others here, below the depth resolution,
            # so F, which covers the region, stays in front: the region is covered exactly
            # and the list ends after at most cnt moves instead of MAX_STEPS.
            pass
        elif cnt > 1 and not clip:
            # F is clipped on all sides, so it covers its list's region: check depth
            front = -1
            for i in range(1, cnt):
                q = litems[s0 + i]
                sq = recs[q, 2]
                if sq == BACKGROUND:
                    continue
                rel = depth_relation(planes, sq, src_f, wx, wy, recs[q, 0], recs[q, 1], eps_z)
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
                moved_list = L
                moves += 1
                continue
        if not clip:
            # 2. the front polygon is visible over this whole region
            if n_out >= visible.shape[0]:
                return -1
            visible[n_out] = f
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
            area_a = 0.0
            if ma > 0:
                area_a = signed_area(wx, wy, n_vert, ma)
            if area_a > AREA_EMPTY:
                litems[a_start + a_cnt] = n_poly
                a_cnt += 1
                areas[n_poly] = area_a
                n_poly = _record(recs, n_poly, n_vert, ma, recs[p, 2])
            area_b = 0.0
            if mb > 0:
                area_b = signed_area(wx, wy, at_b, mb)
            if area_b > AREA_EMPTY:
                litems[b_start + b_cnt] = n_poly
                b_cnt += 1
                areas[n_poly] = area_b
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


@kernel
def integrate_visible(strip, plist, n_pl, solid, x0, y0, planes, eps_z, work):
    """``pixel_polygons`` then ``integrate_pixel``: the count of visible pieces, whose
    records are ``work.visible[:count]``, or -1 if the workspace is too small (grow it
    and call again). Nothing here calls out (both stages are inlined), so its arguments
    cost no reference counts; ``sweep_row`` emits the pieces itself."""
    nv, n_init = pixel_polygons(strip, plist, n_pl, solid, x0, y0, work)
    n_out = -1
    if nv >= 0:
        n_out = integrate_pixel(work, n_init, nv, planes, eps_z)
    return n_out


@kernel
def integrate(strip, plist, n_pl, solid, x0, y0, planes, eps_z, pix, work, out):
    """Run the pixel integrator (growing its workspace until it fits) and emit every
    visible piece with its vertices (in the order the integrator found them)."""
    n_out = integrate_visible(strip, plist, n_pl, solid, x0, y0, planes, eps_z, work)
    while n_out < 0:
        grow_pixel_work(work)
        n_out = integrate_visible(strip, plist, n_pl, solid, x0, y0, planes, eps_z, work)
    recs = work.recs
    visible = work.visible
    wx = work.x
    wy = work.y
    for o in range(n_out):
        r = visible[o]
        out.emit_piece(pix, recs[r, 2], wx, wy, recs[r, 0], recs[r, 1])


# --- the whole image ---------------------------------------------------------------
# The image is cut into bands of BAND_ROWS rows, each run from its own first row (the
# polygons reaching into it cut at its top), so bands are independent: they can run on
# any number of threads and the result is the same, bit for bit.

BAND_ROWS = 32


@kernel
def scan_rows(polys, width, row0, row1, eps_z, jagged, centroids, out):
    """Run the scanline algorithm over the band of rows ``row0 .. row1-1``, emitting every
    pixel's visible pieces into the sink ``out`` (compiled once per sink type)."""
    n_polys = polys.order.size
    active = new_active_list(n_polys)
    strip = new_strip(n_polys, width)
    zlist = new_zlist(n_polys)
    work = new_pixel_work()
    for row in range(row0, row1):
        enter_polygons(polys, active, row)
        if active.n == 0 and active.next_in >= n_polys:
            emit_run(out, row, width, 0, width - 1, BACKGROUND)
            continue
        clip_to_strip(active, strip, row, width)
        bucket_by_x(strip, width)
        sweep_row(strip, zlist, work, out, polys.planes, row, width, eps_z, jagged, centroids)


@kernel
def scanline(polys, width, height, eps_z, jagged, centroids, out):
    """The whole image into the sink ``out``, band after band (the same pieces as
    running the bands on threads)."""
    for row0 in range(0, height, BAND_ROWS):
        scan_rows(polys, width, row0, min(row0 + BAND_ROWS, height), eps_z, jagged, centroids, out)


@kernel(nogil=True)
def band_fragments(polys, width, row0, row1, eps_z, jagged, centroids):
    """Fragments ``(pix, src, area, cx, cy)`` of rows ``row0 .. row1-1`` (runs without the GIL)."""
    out = new_fragment_sink((row1 - row0) * width + 16)
    scan_rows(polys, width, row0, row1, eps_z, jagged, centroids, out)
    n = out.n
    return out.pix[:n], out.src[:n], out.area[:n], out.cx[:n], out.cy[:n]


@kernel
def catmull_fragments(width, height, pstart0, plen0, vx0, vy0, planes, eps_z, jagged, centroids):
    """Visible fragments of every pixel, band after band.

    Returns ``(pix, src, area, cx, cy)``: pixel index ``row * width + col``, source
    polygon (-1 for background), visible area, and its area centroid. With
    ``centroids`` false the fast paths skip finding centroids (flat colours need none)
    and report the pixel centre instead.
    """
    polys = sort_polygons(pstart0, plen0, vx0, vy0, planes)
    out = new_fragment_sink(width * height + 16)
    scanline(polys, width, height, eps_z, jagged, centroids, out)
    n = out.n
    return out.pix[:n], out.src[:n], out.area[:n], out.cx[:n], out.cy[:n]


# --- flat colours straight into the image ---------------------------------------------


@structref.register
class ColorSinkType(_Workspace):
    pass


class ColorSink(structref.StructRefProxy):
    """Box-filtered flat colours written straight into ``image`` (pixels x 3).

    ``colors[src]`` is a polygon's colour (row -1: the background). The current pixel's
    fragments (``src, area``, pieces of one polygon merged, ``n`` of them) are summed
    into the image when the next pixel starts (``flush``), in the order a bincount over
    :class:`FragmentSink` fragments would add them, so both give the same bits.
    """


define_workspace(ColorSink, ColorSinkType, ["image", "colors", "pixel", "src", "area", "n"])


@kernel
def new_color_sink(image, colors):
    # room for every polygon and the background at once: a pixel never needs to grow it
    # (a growth call on the emit path would cost every emit its reference counts)
    return ColorSink(image, colors, -1, np.empty(colors.shape[0], np.int64), np.empty(colors.shape[0]), 0)


@kernel(inline="always")
def flush(out):
    """Write the pending pixel into the image."""
    if out.n == 0:
        return
    image = out.image
    colors = out.colors
    area = out.area
    src = out.src
    n = out.n
    pix = out.pixel
    for ch in range(3):
        acc = 0.0
        for g in range(n):
            acc += area[g] * colors[src[g], ch]
        image[pix, ch] = acc
    out.n = 0


@kernel(inline="always")
def _color_add(out, pix, src, area):
    """Add ``area`` of polygon ``src`` to pixel ``pix`` (merged with the same polygon)."""
    if pix != out.pixel:
        flush(out)
        out.pixel = pix
    n = out.n
    srcs = out.src
    areas = out.area
    g = 0
    while g < n and srcs[g] != src:
        g += 1
    if g < n:
        areas[g] = areas[g] + area
    else:
        srcs[n] = src
        areas[n] = area
        out.n = n + 1


@overload_method(ColorSinkType, "emit_pixel", jit_options=KERNEL_OPTIONS)
def _color_pixel(out, pix, src, x0, y0):
    def impl(out, pix, src, x0, y0):
        if out.n > 0:
            flush(out)
        out.pixel = pix
        # fields read once into locals: each structref read costs a reference count
        image = out.image
        colors = out.colors
        for ch in range(3):
            image[pix, ch] = 1.0 * colors[src, ch]
    return impl


@overload_method(ColorSinkType, "emit_run", jit_options=KERNEL_OPTIONS)
def _color_run(out, pix, count, src, x0, y0):
    """Pixels ``pix .. pix + count - 1`` (one row) are all polygon ``src``."""
    def impl(out, pix, count, src, x0, y0):
        if out.n > 0:
            flush(out)
        out.pixel = pix + count - 1
        image = out.image
        colors = out.colors
        r = 1.0 * colors[src, 0]
        g = 1.0 * colors[src, 1]
        b = 1.0 * colors[src, 2]
        for p in range(pix, pix + count):
            image[p, 0] = r
            image[p, 1] = g
            image[p, 2] = b
    return impl


@overload_method(ColorSinkType, "emit_piece", jit_options=KERNEL_OPTIONS)
def _color_piece(out, pix, src, xs, ys, start, n):
    def impl(out, pix, src, xs, ys, start, n):
        _color_add(out, pix, src, signed_area(xs, ys, start, n))
    return impl


@overload_method(ColorSinkType, "emit_strip_piece", jit_options=KERNEL_OPTIONS)
def _color_strip_piece(out, pix, src, area, xs, ys, start, n):
    def impl(out, pix, src, area, xs, ys, start, n):
        _color_add(out, pix, src, area)
    return impl


@overload_method(ColorSinkType, "emit_area", jit_options=KERNEL_OPTIONS)
def _color_area(out, pix, src, area, x0, y0):
    def impl(out, pix, src, area, x0, y0):
        _color_add(out, pix, src, area)
    return impl


@overload_method(ColorSinkType, "emit_rest", jit_options=KERNEL_OPTIONS)
def _color_rest(out, pix, src, x0, y0):
    def impl(out, pix, src, x0, y0):
        covered = 0.0
        if pix == out.pixel:
            for g in range(out.n):
                covered += out.area[g]
        rest = 1.0 - covered
        if rest > 0.0:
            _color_add(out, pix, src, rest)
    return impl


@kernel(nogil=True)
def band_colors(polys, width, row0, row1, eps_z, jagged, colors, image):
    """Write the flat-colour pixels of rows ``row0 .. row1-1`` into ``image`` (pixels x 3;
    runs without the GIL)."""
    out = new_color_sink(image, colors)
    scan_rows(polys, width, row0, row1, eps_z, jagged, False, out)
    flush(out)
