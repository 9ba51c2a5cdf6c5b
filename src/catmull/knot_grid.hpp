// Rings of any size cut on the knot grid: clip_box (a ring cut to a box) and
// accumulate_rings (every ring's integrals per cell, holes subtracting).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "catmull/edge_integrals.hpp"

namespace aaeval::catmull {

// Scratch for clip_box: two halves of 16 n + 16 vertices each (a line clip adds at most one
// vertex per edge: 4 clips stay below 16 n).
struct BoxBuffers {
    std::vector<double> x, y;
    std::vector<uint8_t> f, flags;
    int64_t half = 0;
    void reserve_for(int64_t n) {
        if (half < 16 * n + 16) {
            half = 16 * n + 16;
            x.resize(size_t(2 * half));
            y.resize(size_t(2 * half));
            f.resize(size_t(2 * half));
        }
    }
};

struct Ring {
    int64_t start, n;
};

// Sutherland-Hodgman clip of one ring to [x0, x1] x [y0, y1]; (start, count) in the buffers,
// count 0 when less than a polygon is left. A concave ring may come back with zero-width
// bridges along the box's sides; they bound no area and cancel in every edge integral.
inline Ring clip_box(const double* xs, const double* ys, int64_t start, int64_t n, double x0, double x1, double y0,
                     double y1, BoxBuffers& B) {
    B.reserve_for(n);
    const int64_t half = B.half;
    double* bx = B.x.data();
    double* by = B.y.data();
    uint8_t* bf = B.f.data();
    B.flags.assign(size_t(n), 0);
    int64_t m = geometry::clip_side(xs + start, ys + start, B.flags.data(), 0, n, 1.0, 0.0, -x0, 1, bx, by, bf, 0);
    if (m < 3) return {0, 0};
    m = geometry::clip_side(bx, by, bf, 0, m, 1.0, 0.0, -x1, -1, bx, by, bf, half);
    if (m < 3) return {0, 0};
    m = geometry::clip_side(bx, by, bf, half, m, 0.0, 1.0, -y0, 1, bx, by, bf, 0);
    if (m < 3) return {0, 0};
    m = geometry::clip_side(bx, by, bf, 0, m, 0.0, 1.0, -y1, -1, bx, by, bf, half);
    if (m < 3) return {0, 0};
    return {half, m};
}

inline int64_t floor_index(double v) {
    const double f = std::floor(v);
    if (!(f > -4.0e18)) return -int64_t(4000000000000000000LL);
    if (f > 4.0e18) return int64_t(4000000000000000000LL);
    return int64_t(f);
}

// Cut every ring on the knot grid (inside the image) and accumulate its integrals per cell:
// acc[n, m, a, b, c] += weights[r, c] * integrals[a, b] of ring r's part in cell (m, n)
// (acc of shape (H + 1, W + 1, k, k, nch)). Rings are signed: holes subtract.
inline void accumulate_rings(const double* xs, const double* ys, const int64_t* starts, const int64_t* lengths,
                             int64_t n_rings, const double* weights, int64_t nch, int64_t width, int64_t height,
                             const Filter& F, double* acc) {
    const int64_t k = F.k;
    std::vector<double> out(static_cast<size_t>(k * k)), phi(static_cast<size_t>(k)), psi(static_cast<size_t>(k));
    BoxBuffers band, cell;
    for (int64_t r = 0; r < n_rings; ++r) {
        const int64_t s = starts[r];
        const int64_t n = lengths[r];
        if (n < 3) continue;
        double xmin = xs[s], xmax = xs[s], ymin = ys[s], ymax = ys[s];
        for (int64_t i = s + 1; i < s + n; ++i) {
            if (xs[i] < xmin) xmin = xs[i];
            if (xs[i] > xmax) xmax = xs[i];
            if (ys[i] < ymin) ymin = ys[i];
            if (ys[i] > ymax) ymax = ys[i];
        }
        const int64_t m0 = geometry::pymax(int64_t(0), floor_index(xmin + 0.5));
        const int64_t m1 = geometry::pymin(width, floor_index(xmax + 0.5));
        const int64_t n0 = geometry::pymax(int64_t(0), floor_index(ymin + 0.5));
        const int64_t n1 = geometry::pymin(height, floor_index(ymax + 0.5));
        for (int64_t row = n0; row <= n1; ++row) {
            const double y0 = geometry::pymax(double(row) - 0.5, 0.0);
            const double y1 = geometry::pymin(double(row) + 0.5, double(height));
            // the band of this cell row, then each cell of it
            const Ring b = clip_box(xs, ys, s, n, 0.0, double(width), y0, y1, band);
            if (b.n < 3) continue;
            const double* bx = band.x.data();
            double bmin = bx[b.start], bmax = bx[b.start];
            for (int64_t i = b.start + 1; i < b.start + b.n; ++i) {
                if (bx[i] < bmin) bmin = bx[i];
                if (bx[i] > bmax) bmax = bx[i];
            }
            const int64_t c0 = geometry::pymax(m0, floor_index(bmin + 0.5));
            const int64_t c1 = geometry::pymin(m1, floor_index(bmax + 0.5));
            for (int64_t col = c0; col <= c1; ++col) {
                const double x0 = geometry::pymax(double(col) - 0.5, 0.0);
                const double x1 = geometry::pymin(double(col) + 0.5, double(width));
                const Ring c = clip_box(band.x.data(), band.y.data(), b.start, b.n, x0, x1, y0, y1, cell);
                if (c.n < 3) continue;
                piece_integrals(cell.x.data(), cell.y.data(), c.start, c.n, double(col), double(row), F, out.data(),
                                phi.data(), psi.data());
                double* cellacc = acc + ((row * (width + 1) + col) * k * k) * nch;
                for (int64_t a = 0; a < k; ++a)
                    for (int64_t bb = 0; bb < k; ++bb)
                        for (int64_t ch = 0; ch < nch; ++ch)
                            cellacc[(a * k + bb) * nch + ch] += weights[r * nch + ch] * out[size_t(a * k + bb)];
            }
        }
    }
}

}  // namespace aaeval::catmull
