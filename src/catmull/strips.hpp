// I. / III.A / III.C of Catmull 1978: the input polygons in order of their first scanline,
// the active list (what remains of each polygon below the current scanline) and the strip:
// this scanline's piece of every active polygon, with its exact area over each pixel column
// (-∫ y dx per column), which splits a piece into solid runs and irregular ends.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "common/geometry.hpp"
#include "common/polygons.hpp"
#include "catmull/buffers.hpp"

namespace aaeval::catmull {

using geometry::pymax;
using geometry::pymin;

// Coverage within this of 1 is a solid piece; below COV_EMPTY a piece is absent.
inline constexpr double COV_SOLID = 1.0 - 1e-12;
inline constexpr double COV_EMPTY = 1e-15;
inline constexpr int64_t BACKGROUND = -1;

// The input polygons (common/polygons.hpp) with their y ranges and `order`: indices sorted
// (stably) on ymin, the order in which they join the active list.
struct SortedPolygons : Polygons {
    std::vector<double> ymin, ymax;
    std::vector<int64_t> order;
};

inline void sort_polygons(SortedPolygons& P) {
    P.ymin.resize(size_t(P.n));
    P.ymax.resize(size_t(P.n));
    for (int64_t p = 0; p < P.n; ++p) {
        const double* ys = P.y + P.start[p];
        double lo = ys[0], hi = ys[0];
        for (int64_t i = 1; i < P.length[p]; ++i) {
            if (ys[i] < lo) lo = ys[i];
            if (ys[i] > hi) hi = ys[i];
        }
        P.ymin[size_t(p)] = lo;
        P.ymax[size_t(p)] = hi;
    }
    P.order.resize(size_t(P.n));
    std::iota(P.order.begin(), P.order.end(), int64_t(0));
    std::stable_sort(P.order.begin(), P.order.end(),
                     [&](int64_t a, int64_t b) { return P.ymin[size_t(a)] < P.ymin[size_t(b)]; });
}

// The active polygons' remaining parts: recs[:n] are records (start, length, source) into
// the vertex buffer `v` (`used` entries taken); `spare` is the buffer the next remainders go
// to. next_in counts the polygons of SortedPolygons::order that have entered.
struct ActiveList {
    Verts v{1024}, spare{1024};
    Rows<int64_t, 3> recs{256};
    int64_t n = 0, used = 0, next_in = 0;
};

// This scanline's strip pieces: pieces[:n] are records into `v`; span[k] = (first column,
// last column, offset into cov); cov[span[k][2] + c - span[k][0]] is piece k's exact area in
// column c. The x-bucket: pieces bucket_items[bucket_head[c] .. bucket_head[c + 1]) have
// leftmost column c.
struct Strip {
    Verts v{1024};
    Rows<int64_t, 3> pieces{256}, span{256};
    std::vector<double> cov = std::vector<double>(1024);
    int64_t n = 0, used = 0, cov_used = 0;
    std::vector<int64_t> bucket_head, bucket_items = std::vector<int64_t>(256);
    explicit Strip(int64_t width) : bucket_head(size_t(width + 1), 0) {}
};

inline int64_t record(Rows<int64_t, 3>& recs, int64_t k, int64_t start, int64_t length, int64_t src) {
    int64_t* r = recs[k];
    r[0] = start;
    r[1] = length;
    r[2] = src;
    return k + 1;
}

// A polygon's part below y_top (all of it unless it starts above the image), written at `at`
// (room for 2 n + 2 from there).
inline int64_t below(const double* vx0, const double* vy0, int64_t start, int64_t n, double y_top, Verts& out,
                     int64_t at, std::vector<uint8_t>& flags) {
    double lo = vy0[start];
    for (int64_t i = 1; i < n; ++i)
        if (vy0[start + i] < lo) lo = vy0[start + i];
    if (lo >= y_top) {
        for (int64_t i = 0; i < n; ++i) {
            out.x[size_t(at + i)] = vx0[start + i];
            out.y[size_t(at + i)] = vy0[start + i];
            out.f[size_t(at + i)] = 0;
        }
        return n;
    }
    flags.assign(size_t(n), 0);
    const int64_t m = geometry::clip_side(vx0 + start, vy0 + start, flags.data(), 0, n, 0.0, 1.0, -y_top, 1,
                                          out.x.data(), out.y.data(), out.f.data(), at);
    if (m > 0 && geometry::signed_area(out.x.data(), out.y.data(), at, m) <= COV_EMPTY) return 0;
    return m;
}

// Polygons whose first scanline is `row` join the active list (their part y >= row).
inline void enter_polygons(const SortedPolygons& P, ActiveList& A, int64_t row, std::vector<uint8_t>& flags) {
    const double y_top = double(row);
    const double y_bot = y_top + 1.0;
    int64_t next_in = A.next_in;
    while (next_in < P.n && P.ymin[size_t(P.order[size_t(next_in)])] < y_bot) {
        const int64_t p = P.order[size_t(next_in)];
        ++next_in;
        if (P.ymax[size_t(p)] <= y_top) continue;
        const int64_t n = P.length[p];
        A.v.grow_to(A.used + 2 * n + 4);
        A.recs.grow_rows(A.n + 1);
        const int64_t m = below(P.x, P.y, P.start[p], n, y_top, A.v, A.used, flags);
        if (m > 0) {
            A.n = record(A.recs, A.n, A.used, m, p);
            A.used += m;
        }
    }
    A.next_in = next_in;
}

// Add -∫ y dx of the edge from x0 to x1 over each column ca..cb.
inline void edge_coverage(double x0, double y0, double x1, double slope, int64_t ca, int64_t cb, int64_t c0,
                          double* cov, int64_t cov_off) {
    for (int64_t col = ca; col <= cb; ++col) {
        const double xa = pymin(pymax(x0, double(col)), double(col) + 1.0);
        const double xb = pymin(pymax(x1, double(col)), double(col) + 1.0);
        if (xa == xb) continue;
        const double ya = y0 + slope * (xa - x0);
        const double yb = y0 + slope * (xb - x0);
        cov[cov_off + col - c0] -= 0.5 * (xb - xa) * (ya + yb);
    }
}

// Exact area of a strip piece over each pixel column c0..c1 (-∫ y dx per column).
inline void strip_coverage(const double* xs, const double* ys, int64_t start, int64_t n, double row, int64_t c0,
                           int64_t c1, double* cov, int64_t cov_off) {
    for (int64_t c = 0; c < c1 - c0 + 1; ++c) cov[cov_off + c] = 0.0;
    for (int64_t i = start; i < start + n; ++i) {
        const int64_t j = i + 1 < start + n ? i + 1 : start;
        const double x0 = xs[i];
        const double x1 = xs[j];
        if (x0 == x1) continue;
        const double y0 = ys[i] - row;
        const double y1 = ys[j] - row;
        const double slope = (y1 - y0) / (x1 - x0);
        const double lo = pymin(x0, x1);
        const double hi = pymax(x0, x1);
        const int64_t ca = pymax(to_index(std::floor(lo)), c0);
        const int64_t cb = pymin(to_index(std::floor(hi)), c1);
        if (y0 == y1 && cb - ca > 1) {
            // a level edge (the strip's top or bottom): the columns it fully crosses get -y0
            // per unit of x (the same bits as the general formula); only its two end columns
            // need that formula
            edge_coverage(x0, y0, x1, slope, ca, ca, c0, cov, cov_off);
            const double full = x1 > x0 ? y0 : -y0;
            for (int64_t col = ca + 1; col < cb; ++col) cov[cov_off + col - c0] -= full;
            edge_coverage(x0, y0, x1, slope, cb, cb, c0, cov, cov_off);
        } else {
            edge_coverage(x0, y0, x1, slope, ca, cb, c0, cov, cov_off);
        }
    }
}

// Clip this scanline's piece off every active polygon into the strip; keep the rest. The
// line y = row + 1 splits each polygon: side A (above) is the strip piece, with its coverage
// of every column; side B replaces the polygon in the active list. A piece is kept if it
// covers a column.
inline void clip_to_strip(ActiveList& A, Strip& S, int64_t row, int64_t width) {
    const double y_bot = double(row) + 1.0;
    // a piece per active polygon at most
    S.pieces.grow_rows(A.n);
    S.span.grow_rows(A.n);
    grow(S.bucket_items, A.n);
    int64_t used = 0, n_pieces = 0, cov_used = 0, new_used = 0, keep = 0;
    for (int64_t k = 0; k < A.n; ++k) {
        const int64_t s = A.recs[k][0];
        const int64_t n = A.recs[k][1];
        const int64_t src = A.recs[k][2];
        if (used + 2 * n + 4 > S.v.size()) S.v.grow_to(used + 2 * n + 4);
        if (new_used + 2 * n + 4 > A.spare.size()) A.spare.grow_to(new_used + 2 * n + 4);
        const geometry::SplitCounts m = geometry::clip_split(
            A.v.x.data(), A.v.y.data(), A.v.f.data(), s, n, 0.0, 1.0, -y_bot, true, true, S.v.x.data(), S.v.y.data(),
            S.v.f.data(), used, A.spare.x.data(), A.spare.y.data(), A.spare.f.data(), new_used);
        if (m.a > 0 && geometry::signed_area(S.v.x.data(), S.v.y.data(), used, m.a) > COV_EMPTY) {
            // the pixel columns the piece's x range reaches, clamped to the image
            const double* sx = S.v.x.data();
            double lo = sx[used], hi = sx[used];
            for (int64_t i = used + 1; i < used + m.a; ++i) {
                lo = pymin(lo, sx[i]);
                hi = pymax(hi, sx[i]);
            }
            const int64_t c0 = pymax(to_index(std::floor(lo)), int64_t(0));
            const int64_t c1 = pymin(to_index(std::ceil(hi)) - 1, width - 1);
            if (c1 >= c0) {
                if (cov_used + c1 - c0 + 1 > int64_t(S.cov.size())) grow(S.cov, cov_used + c1 - c0 + 1);
                strip_coverage(S.v.x.data(), S.v.y.data(), used, m.a, double(row), c0, c1, S.cov.data(), cov_used);
                int64_t* sp = S.span[n_pieces];
                sp[0] = c0;
                sp[1] = c1;
                sp[2] = cov_used;
                n_pieces = record(S.pieces, n_pieces, used, m.a, src);
                cov_used += c1 - c0 + 1;
                used += m.a;
            }
        }
        if (m.b > 0 && geometry::signed_area(A.spare.x.data(), A.spare.y.data(), new_used, m.b) > COV_EMPTY) {
            keep = record(A.recs, keep, new_used, m.b, src);
            new_used += m.b;
        }
    }
    S.n = n_pieces;
    S.used = used;
    S.cov_used = cov_used;
    A.n = keep;
    A.used = new_used;
    // the remainders' buffer becomes the active one
    A.v.swap(A.spare);
}

}  // namespace aaeval::catmull
