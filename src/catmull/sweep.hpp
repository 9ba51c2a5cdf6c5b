// III.D/E of Catmull 1978: the row sweep. The pixels of a row left to right, each by the
// cheapest case that applies (see sweep_row), and a band of rows from its own first row
// (scan_rows): bands are independent, so they run on any number of threads with the same
// bits.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "common/geometry.hpp"
#include "catmull/buckets.hpp"
#include "catmull/integrator.hpp"
#include "catmull/strips.hpp"

namespace aaeval::catmull {

// a turn the other way by less than this (pixel area units) is rounding
inline constexpr double CONVEX_SLACK = 1e-12;

// The z-list (strip pieces over the current pixel, front to back, depth at the pixel
// centre) and `pixel`, the current pixel's polygon list. Each holds a strip piece at most
// once: room for the scanline's pieces (fit) is enough.
struct ZList {
    std::vector<int64_t> items = std::vector<int64_t>(256);
    std::vector<double> depth = std::vector<double>(256);
    std::vector<int64_t> pixel = std::vector<int64_t>(256);
    void fit(int64_t n_pieces) {
        grow(items, n_pieces);
        grow(depth, n_pieces);
        grow(pixel, n_pieces + 1);
    }
};

// Move the z-list to column col; returns its new length. Pieces of the x-bucket at this
// column enter, pieces that ended to the left leave, and the list is sorted front to back on
// depth at the pixel centre (ties: the later polygon first); insertion sort is linear while
// the order holds from pixel to pixel.
inline int64_t update_zlist(int64_t* zl, double* zdepth, int64_t n_zl, const Strip& S, const double* planes,
                            int64_t col, int64_t row) {
    for (int64_t t = S.bucket_head[size_t(col)]; t < S.bucket_head[size_t(col + 1)]; ++t)
        zl[n_zl++] = S.bucket_items[size_t(t)];
    int64_t w = 0;
    for (int64_t t = 0; t < n_zl; ++t)
        if (S.span[zl[t]][1] >= col) zl[w++] = zl[t];
    n_zl = w;
    if (n_zl < 2) return n_zl;  // nothing to order
    const double xc = double(col) + 0.5;
    const double yc = double(row) + 0.5;
    for (int64_t t = 0; t < n_zl; ++t) zdepth[t] = depth(planes, S.pieces[zl[t]][2], xc, yc);
    for (int64_t t = 1; t < n_zl; ++t) {
        const int64_t kz = zl[t];
        const double dz = zdepth[t];
        int64_t u = t - 1;
        while (u >= 0 && (zdepth[u] > dz || (zdepth[u] == dz && S.pieces[zl[u]][2] < S.pieces[kz][2]))) {
            zl[u + 1] = zl[u];
            zdepth[u + 1] = zdepth[u];
            --u;
        }
        zl[u + 1] = kz;
        zdepth[u + 1] = dz;
    }
    return n_zl;
}

AAEVAL_INLINE double coverage(const Strip& S, int64_t k, int64_t col) {
    return S.cov[size_t(S.span[k][2] + col - S.span[k][0])];
}

struct PixelList {
    int64_t n, solid;
};

// The pixel's polygon list: front to back up to the first solid piece, and anything behind
// it not hidden by it everywhere in the pixel. solid: the strip piece covering the whole
// pixel (-1 if none).
inline PixelList pixel_list(const int64_t* zl, int64_t n_zl, int64_t* plist, const Strip& S, const double* planes,
                            int64_t col, int64_t row, double eps_z) {
    int64_t n_pl = 0, solid = -1;
    for (int64_t t = 0; t < n_zl; ++t) {
        const int64_t k = zl[t];
        const double cv = coverage(S, k, col);
        if (cv <= COV_EMPTY) continue;
        if (solid >= 0 &&
            in_front_on_square(planes, S.pieces[solid][2], S.pieces[k][2], double(col), double(row), eps_z))
            continue;
        plist[n_pl++] = k;
        if (solid < 0 && cv >= COV_SOLID) solid = k;
    }
    return {n_pl, solid};
}

// Emit strip piece k's part in pixel column col with its shape (its area alone if clipping
// leaves nothing), or the piece uncut to a sink that integrates column parts itself
// (emit_column_part). W has room for 6 n + 16 vertices (n: the piece's).
template <class Sink>
inline void emit_front_piece(const Strip& S, int64_t k, int64_t pix, int64_t col, int64_t row, PixelWork& W,
                             Sink& out) {
    const double cv = coverage(S, k, col);
    const int64_t src = S.pieces[k][2];
    const int64_t n = S.pieces[k][1];
    if constexpr (Sink::COLUMN_PARTS)
        if (out.emit_column_part(pix, src, S.v.x.data(), S.v.y.data(), S.pieces[k][0], n, col)) return;
    const int64_t m = geometry::clip_to_column(S.v.x.data(), S.v.y.data(), S.v.f.data(), S.pieces[k][0], n, double(col),
                                               W.v.x.data(), W.v.y.data(), W.v.f.data(), 0, 4 * n + 8);
    if (m > 0)
        out.emit_strip_piece(pix, src, cv, W.v.x.data(), W.v.y.data(), 0, m);
    else
        out.emit_area(pix, src, cv, double(col), double(row));
}

// The last column in col .. end up to which polygon p hides polygon q over every pixel square
// by a safe margin (col - 1 if it does not at col). z_p - z_q is linear, so its largest corner
// value on a square is linear in x0: the bound in closed form, then checked.
inline int64_t hidden_until(const double* planes, int64_t p, int64_t q, int64_t col, int64_t end, int64_t row,
                            int64_t width) {
    const double* P = planes + 3 * p;
    const double* Q = planes + 3 * q;
    const double da = P[0] - Q[0];
    const double db = P[1] - Q[1];
    const double dc = P[2] - Q[2];
    const double y0 = double(row);
    const double margin =
        1e-9 * ((std::fabs(P[0]) + std::fabs(Q[0]) + std::fabs(P[1]) + std::fabs(Q[1])) * (double(width) + y0 + 2.0) +
                std::fabs(P[2]) + std::fabs(Q[2]) + 1.0);
    const double rest = pymax(da, 0.0) + db * y0 + pymax(db, 0.0) + dc;
    int64_t last;
    if (da * double(col) + rest >= -margin) {
        last = col - 1;
    } else if (da <= 0.0 || da * double(end) + rest < -margin) {
        last = end;
    } else {
        last = pymin(to_index(std::floor((-margin - rest) / da)), end);
        while (last >= col && da * double(last) + rest >= -margin) --last;
    }
    return last;
}

struct Run {
    int64_t end, n_zl;
};

// How far strip piece k, alone and solid in front at col, stays so without per-pixel work:
// (last column, z-list length). Pieces entering the z-list inside the run are added to it
// (the run stops before one that k does not hide), so the z-list is as the per-pixel sweep
// would have it.
inline Run solid_run(int64_t k, int64_t* zl, int64_t n_zl, const Strip& S, const double* planes, int64_t col,
                     int64_t row, int64_t width) {
    const int64_t p = S.pieces[k][2];
    int64_t end = pymin(S.span[k][1], width - 1);
    int64_t c = col + 1;
    while (c <= end && coverage(S, k, c) >= COV_SOLID) ++c;
    end = c - 1;
    for (int64_t t = 0; t < n_zl; ++t) {
        if (end <= col) return {col, n_zl};
        if (zl[t] != k) end = pymin(end, hidden_until(planes, p, S.pieces[zl[t]][2], col + 1, end, row, width));
    }
    c = col + 1;
    while (c <= end) {
        for (int64_t t = S.bucket_head[size_t(c)]; t < S.bucket_head[size_t(c + 1)]; ++t) {
            const int64_t q = S.bucket_items[size_t(t)];
            const int64_t last = hidden_until(planes, p, S.pieces[q][2], c, end, row, width);
            if (last < c) return {c - 1, n_zl};  // q enters at c visible: the per-pixel sweep takes over
            end = pymin(end, last);
        }
        for (int64_t t = S.bucket_head[size_t(c)]; t < S.bucket_head[size_t(c + 1)]; ++t)
            zl[n_zl++] = S.bucket_items[size_t(t)];
        ++c;
    }
    return {end, n_zl};
}

// Strip pieces ka (in front) and kb clipped to pixel column x0, and kb's part overlapping
// ka's: each a polygon in the scratch space (wx, wy from 0: ka's, ma vertices; from at_b:
// kb's, mb; from at_o: the overlap, mo, none when mo < 3), and the overlap's area, or -1.0
// if ka's part is not convex there (or the scratch space, `cap_w` vertices, is smaller than
// two_layer_room: the caller grows it first).
// For a pixel whose visible pieces are ka over kb over what both hide the visible parts
// follow without the integrator. The overlap is kb's part clipped by each of ka's own edges
// in turn.
struct TwoLayer {
    double overlap;
    int64_t ma, at_b, mb, at_o, mo;
};

// the scratch space two_layer_parts needs for pieces of na and nb vertices: ka's and kb's
// clipped parts, then two halves for the overlap's clips (each clip adds at most one vertex
// per edge)
inline int64_t two_layer_room(int64_t na, int64_t nb) {
    const int64_t tmp = (2 * na + 4) + (2 * nb + 4);
    const int64_t cap = 2 * nb + 2 * na + 8;
    return tmp + 2 * cap + 2 * nb + 8;
}

inline TwoLayer two_layer_parts(const Strip& S, int64_t ka, int64_t kb, double x0, double* wx, double* wy, uint8_t* wf,
                                int64_t cap_w) {
    const double* sx = S.v.x.data();
    const double* sy = S.v.y.data();
    const uint8_t* sf = S.v.f.data();
    const int64_t na = S.pieces[ka][1];
    const int64_t nb = S.pieces[kb][1];
    const int64_t at_b = 2 * na + 4;
    const int64_t tmp = at_b + 2 * nb + 4;
    const int64_t cap = 2 * nb + 2 * na + 8;
    TwoLayer t{-1.0, 0, at_b, 0, at_b, 0};
    if (tmp + 2 * cap + 2 * nb + 8 <= cap_w) {
        int64_t ma = geometry::clip_to_column(sx, sy, sf, S.pieces[ka][0], na, x0, wx, wy, wf, 0, tmp);
        int64_t mb = geometry::clip_to_column(sx, sy, sf, S.pieces[kb][0], nb, x0, wx, wy, wf, at_b, tmp);
        bool convex = true;
        if (ma < 3 || mb < 3) {
            ma = 0;
            mb = 0;
        }
        for (int64_t i = 0; i < ma; ++i) {
            const int64_t j = i + 1 < ma ? i + 1 : i + 1 - ma;  // (i + 1) % ma without a division
            const int64_t k = i + 2 < ma ? i + 2 : i + 2 - ma;
            const double turn = (wx[j] - wx[i]) * (wy[k] - wy[j]) - (wy[j] - wy[i]) * (wx[k] - wx[j]);
            convex = convex && turn >= -CONVEX_SLACK;
        }
        if (convex) {
            // kb's part is left in place (the clips write into the two halves from tmp)
            int64_t cur = at_b, m = mb, spare = tmp;
            for (int64_t i = 0; i < ma; ++i) {
                const int64_t j = i + 1 < ma ? i + 1 : 0;
                const double ex = wx[j] - wx[i];
                const double ey = wy[j] - wy[i];
                const double norm = geometry::sqrt_ieee(ex * ex + ey * ey);
                if (wf[i] == 0 && norm > EPS_LINE && m > 0) {
                    const double a = ey / norm;
                    const double b = -ex / norm;
                    m = geometry::clip_side(wx, wy, wf, cur, m, a, b, -(a * wx[i] + b * wy[i]), -1, wx, wy, wf, spare);
                    const int64_t next_spare = spare == tmp ? tmp + cap : tmp;
                    cur = spare;
                    spare = next_spare;
                }
            }
            const double area = m >= 3 ? geometry::signed_area(wx, wy, cur, m) : 0.0;
            t = {pymax(area, 0.0), ma, at_b, mb, cur, m >= 3 ? m : 0};
        }
    }
    return t;
}

// The area of two_layer_parts' overlap (-1.0: not this case).
inline double two_layer_overlap(const Strip& S, int64_t ka, int64_t kb, double x0, double* wx, double* wy, uint8_t* wf,
                                int64_t cap_w) {
    return two_layer_parts(S, ka, kb, x0, wx, wy, wf, cap_w).overlap;
}

// The two-layer case with shapes: the front piece, the second piece, less their overlap, and
// the rest of the pixel to what both hide. Only for sinks that take signed pieces.
template <class Sink>
inline void emit_two_layer(const Strip& S, int64_t first, int64_t second, int64_t back, const TwoLayer& tl, int64_t pix,
                           double x0, double y0, PixelWork& W, Sink& out) {
    if constexpr (Sink::SIGNED_PIECES) {
        const double* wx = W.v.x.data();
        const double* wy = W.v.y.data();
        if (tl.ma >= 3) out.emit_signed_piece(pix, S.pieces[first][2], 1.0, wx, wy, 0, tl.ma);
        if (tl.mb >= 3) out.emit_signed_piece(pix, S.pieces[second][2], 1.0, wx, wy, tl.at_b, tl.mb);
        if (tl.mo >= 3) out.emit_signed_piece(pix, S.pieces[second][2], -1.0, wx, wy, tl.at_o, tl.mo);
        out.emit_rest(pix, back, x0, y0);
    }
}

// One band's workspaces.
struct Scan {
    ActiveList active;
    Strip strip;
    ZList zlist;
    PixelWork work;
    std::vector<uint8_t> flags;
    std::vector<int64_t> fill;
    explicit Scan(int64_t width) : strip(width) {}
};

// Sweep the pixels of row left to right, emitting each pixel's visible pieces by the
// cheapest case that applies:
// - no piece: the background, up to the next piece's column (emit_run);
// - a solid piece alone in front: its whole solid run (solid_run, emit_run);
// - with the integrator switched off (jagged): the nearest piece, whole pixel;
// - one irregular piece over what it hides: that piece (emit_front_piece with its shape, or
//   emit_area without centroids) and the rest of the pixel (emit_rest);
// - two irregular pieces over what both hide, the front one convex in the pixel
//   (two_layer_parts): by areas with centroids off, or by shapes (the second piece less the
//   overlap, emit_two_layer) for a sink that takes signed pieces;
// - otherwise the pixel integrator (integrate).
template <class Sink>
inline void sweep_row(Scan& sc, Sink& out, const double* planes, int64_t row, int64_t width, double eps_z, bool jagged,
                      bool centroids) {
    const Strip& S = sc.strip;
    PixelWork& W = sc.work;
    int64_t* zl = sc.zlist.items.data();
    double* zdepth = sc.zlist.depth.data();
    int64_t* plist = sc.zlist.pixel.data();
    const std::vector<int64_t>& head = S.bucket_head;
    constexpr bool signed_two_layer = Sink::SIGNED_PIECES;
    const double y0 = double(row);
    int64_t n_zl = 0;
    int64_t col = 0;
    while (col < width) {
        n_zl = update_zlist(zl, zdepth, n_zl, S, planes, col, row);
        const PixelList pl = pixel_list(zl, n_zl, plist, S, planes, col, row, eps_z);
        const int64_t n_pl = pl.n, solid = pl.solid;
        const int64_t pix = row * width + col;
        const double x0 = double(col);
        if (n_pl == 0) {
            int64_t end = col;
            if (n_zl == 0)
                while (end + 1 < width && head[size_t(end + 1)] == head[size_t(end + 2)]) ++end;
            out.emit_run(row, width, col, end, BACKGROUND);
            col = end + 1;
            continue;
        }
        const int64_t first = plist[0];
        if (n_pl == 1 && first == solid) {
            const Run r = solid_run(solid, zl, n_zl, S, planes, col, row, width);
            n_zl = r.n_zl;
            out.emit_run(row, width, col, r.end, S.pieces[solid][2]);
            col = r.end + 1;
            continue;
        }
        if (jagged) {
            out.emit_pixel(pix, S.pieces[first][2], x0, y0);
        } else {
            // one irregular piece in front of all that is left, which it hides: the
            // background, or a solid piece behind it over the whole square (-2: neither)
            int64_t behind = -2;
            if (n_pl == 1)
                behind = BACKGROUND;
            else if (n_pl == 2 && plist[1] == solid &&
                     in_front_on_square(planes, S.pieces[first][2], S.pieces[solid][2], x0, y0, eps_z))
                behind = S.pieces[solid][2];
            // two irregular pieces over what both hide, the front one convex in the pixel: by
            // areas (centroids off), or by shapes for a sink that takes signed pieces (the
            // second's visible part as its piece less the overlap); tl.overlap -1.0: not this case
            TwoLayer tl{-1.0, 0, 0, 0, 0, 0};
            int64_t back = BACKGROUND, second = -1;
            if (behind == -2 && (!centroids || signed_two_layer) &&
                ((n_pl == 2 && solid < 0) || (n_pl == 3 && plist[2] == solid))) {
                back = n_pl == 2 ? BACKGROUND : S.pieces[solid][2];
                second = plist[1];
                if (in_front_on_square(planes, S.pieces[first][2], S.pieces[second][2], x0, y0, eps_z) &&
                    (n_pl == 2 || (in_front_on_square(planes, S.pieces[second][2], back, x0, y0, eps_z) &&
                                   in_front_on_square(planes, S.pieces[first][2], back, x0, y0, eps_z)))) {
                    const int64_t room = two_layer_room(S.pieces[first][1], S.pieces[second][1]);
                    if (W.v.size() < room) W.v.grow_to(room);
                    tl = two_layer_parts(S, first, second, x0, W.v.x.data(), W.v.y.data(), W.v.f.data(), W.v.size());
                }
            }
            if (behind != -2) {
                if (centroids) {
                    if (W.v.size() < 6 * S.pieces[first][1] + 16) W.v.grow_to(6 * S.pieces[first][1] + 16);
                    emit_front_piece(S, first, pix, col, row, W, out);
                } else {
                    out.emit_area(pix, S.pieces[first][2], coverage(S, first, col), x0, y0);
                }
                out.emit_rest(pix, behind, x0, y0);
            } else if (tl.overlap >= 0.0 && !centroids) {
                out.emit_area(pix, S.pieces[first][2], coverage(S, first, col), x0, y0);
                const double second_visible = coverage(S, second, col) - tl.overlap;
                if (second_visible > 0.0) out.emit_area(pix, S.pieces[second][2], second_visible, x0, y0);
                out.emit_rest(pix, back, x0, y0);
            } else if (tl.overlap >= 0.0) {
                emit_two_layer(S, first, second, back, tl, pix, x0, y0, W, out);
            } else {
                integrate(S, plist, n_pl, solid, x0, y0, planes, eps_z, pix, W, out);
            }
        }
        ++col;
    }
}

// Rows row0 .. row1-1 into the sink, from the band's own first row (the polygons reaching into
// it cut at its top).
template <class Sink>
inline void scan_rows(const SortedPolygons& P, int64_t width, int64_t row0, int64_t row1, double eps_z, bool jagged,
                      bool centroids, Sink& out) {
    Scan sc(width);
    for (int64_t row = row0; row < row1; ++row) {
        enter_polygons(P, sc.active, row, sc.flags);
        if (sc.active.n == 0 && sc.active.next_in >= P.n) {
            out.emit_run(row, width, 0, width - 1, BACKGROUND);
            continue;
        }
        clip_to_strip(sc.active, sc.strip, row, width);
        sc.zlist.fit(sc.strip.n);
        bucket_by_x(sc.strip, width, sc.fill);
        sweep_row(sc, out, P.planes, row, width, eps_z, jagged, centroids);
    }
}

}  // namespace aaeval::catmull
