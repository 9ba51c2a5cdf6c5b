// Point sampling of polygon scenes: the scanline pieces the samplers and the A-buffer
// share, and the sampler itself (sampling.cpp).
//
// - row_buckets: every polygon listed on each pixel row its y extent meets, in file order;
// - strip_edges: a polygon's edges meeting a horizontal band, ordered by y, with the x
//   range they span there;
// - inside / crossings: crossing parity with the half-open rule (y0 <= y) != (y1 <= y)
//   and x < x_cross, the crossing computed from the edge's endpoints ordered by y, so two
//   polygons sharing an edge compute the same crossing;
// - depth: z = a x + b y + c, polygons visited in file order, a later one wins when
//   nearer_or_tied (depth.hpp).
// Every expression runs in a fixed order (no FMA contraction), so the images' bits are the
// same on every machine; the inputs are checked by the bindings (module.cpp) before any of
// this runs.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/numeric.hpp"
#include "common/polygons.hpp"

namespace aaeval::samplers {

using aaeval::Polygons;
using numeric::pymax;
using numeric::pymin;
using numeric::to_i64;
using numeric::wrap_add;

constexpr int64_t NO_POLYGON = -1;
constexpr double INF = std::numeric_limits<double>::infinity();

// Polygons per pixel row as CSR (row_start[height + 1], polys): polygon p is listed on rows
// floor(ymin) .. ceil(ymax) - 1 clipped to the image (it covers [ymin, ymax)).
inline void row_buckets(int64_t height, const Polygons& P, std::vector<int64_t>& row_start,
                        std::vector<int64_t>& polys) {
    std::vector<int64_t> r0(P.n), r1(P.n);
    row_start.assign(height + 1, 0);
    for (int64_t p = 0; p < P.n; ++p) {
        double ymin = INF, ymax = -INF;
        for (int64_t i = P.start[p]; i < P.start[p] + P.length[p]; ++i) {
            ymin = pymin(ymin, P.y[i]);
            ymax = pymax(ymax, P.y[i]);
        }
        int64_t a = pymax(int64_t(0), to_i64(std::floor(ymin)));
        int64_t b = pymin(height - 1, wrap_add(to_i64(std::ceil(ymax)), -1));
        r0[p] = a;
        r1[p] = b;
        for (int64_t r = a; r <= b; ++r) row_start[r + 1] += 1;
    }
    for (int64_t r = 0; r < height; ++r) row_start[r + 1] += row_start[r];
    std::vector<int64_t> fill(row_start.begin(), row_start.end() - 1);
    polys.resize(row_start[height]);
    for (int64_t p = 0; p < P.n; ++p)
        for (int64_t r = r0[p]; r <= r1[p]; ++r) polys[fill[r]++] = p;
}

// Scratch for one polygon's edges and crossings.
struct EdgeBuffers {
    std::vector<double> x0, y0, x1, y1, xc;
    explicit EdgeBuffers(const Polygons& P) {
        int64_t maxv = 3;
        for (int64_t p = 0; p < P.n; ++p) maxv = pymax(maxv, P.length[p]);
        x0.resize(maxv);
        y0.resize(maxv);
        x1.resize(maxv);
        y1.resize(maxv);
        xc.resize(maxv);
    }
};

// Edges of polygon p meeting the closed band ya <= y <= yb, endpoints ordered by y, into E;
// returns their count and the x range [xlo, xhi] they span inside the band. Horizontal
// edges are kept (they bound the A-buffer's z ranges; the inside test ignores them).
inline int64_t strip_edges(const Polygons& P, int64_t p, double ya, double yb, EdgeBuffers& E, double& xlo,
                           double& xhi) {
    int64_t m = 0;
    xlo = INF;
    xhi = -INF;
    const int64_t start = P.start[p], n = P.length[p];
    int64_t prev = start + n - 1;
    for (int64_t i = start; i < start + n; ++i) {
        double x0 = P.x[prev], y0 = P.y[prev], x1 = P.x[i], y1 = P.y[i];
        prev = i;
        if (y1 < y0) {
            std::swap(x0, x1);
            std::swap(y0, y1);
        }
        if (y0 > yb || y1 < ya) continue;
        E.x0[m] = x0;
        E.y0[m] = y0;
        E.x1[m] = x1;
        E.y1[m] = y1;
        ++m;
        double xa, xb;
        if (y1 > y0) {
            double ta = pymax(ya, y0);
            double tb = pymin(yb, y1);
            xa = x0 + (ta - y0) * (x1 - x0) / (y1 - y0);
            xb = x0 + (tb - y0) * (x1 - x0) / (y1 - y0);
        } else {
            xa = x0;
            xb = x1;
        }
        xlo = pymin(xlo, xa, xb);
        xhi = pymax(xhi, xa, xb);
    }
    return m;
}

// Crossing parity of (x, y) against m y-ordered edges (half-open rule).
inline bool inside(const EdgeBuffers& E, int64_t m, double x, double y) {
    bool odd = false;
    for (int64_t e = 0; e < m; ++e) {
        if (E.y0[e] <= y && y < E.y1[e]) {
            double xc = E.x0[e] + (y - E.y0[e]) * (E.x1[e] - E.x0[e]) / (E.y1[e] - E.y0[e]);
            if (x < xc) odd = !odd;
        }
    }
    return odd;
}

// Sorted x of the edges' crossings with the line at y (half-open rule) into E.xc; returns
// the count. (x, y) is inside exactly when xc[2t] <= x < xc[2t + 1] for some t.
inline int64_t crossings(EdgeBuffers& E, int64_t m, double y) {
    double* out = E.xc.data();
    int64_t nc = 0;
    for (int64_t e = 0; e < m; ++e) {
        if (E.y0[e] <= y && y < E.y1[e]) {
            double xc = E.x0[e] + (y - E.y0[e]) * (E.x1[e] - E.x0[e]) / (E.y1[e] - E.y0[e]);
            int64_t t = nc;
            while (t > 0 && out[t - 1] > xc) {
                out[t] = out[t - 1];
                --t;
            }
            out[t] = xc;
            ++nc;
        }
    }
    return nc;
}

// x of column g of the sample grid with k samples per pixel: (g + 1/2) / k.
inline double grid_x(int64_t g, int64_t k) { return (static_cast<double>(g) + 0.5) / static_cast<double>(k); }

// Grid columns g in [0, n) with xa <= grid_x(g, k) < xb, as [g0, g1).
inline void grid_range(double xa, double xb, int64_t k, int64_t n, int64_t& g0, int64_t& g1) {
    const double kd = static_cast<double>(k);
    const double lim = static_cast<double>(n) / kd + 1.0;
    xa = pymin(pymax(xa, -1.0), lim);
    xb = pymin(pymax(xb, -1.0), lim);
    g0 = pymax(int64_t(0), wrap_add(to_i64(std::ceil(xa * kd - 0.5)), -1));
    while (g0 < n && grid_x(g0, k) < xa) ++g0;
    g1 = pymin(n, pymax(g0, wrap_add(to_i64(std::ceil(xb * kd - 0.5)), 1)));
    while (g1 > g0 && grid_x(g1 - 1, k) >= xb) --g1;
}

// A filter's profile as the samplers evaluate it: kind 0 box (|t| <= 1/2, closed), 1
// polynomial pieces (rows of coefficients, Horner in t - (floor(t) + 1/2)), 2 Gaussian
// max(0, exp(alpha t^2) - bias); zero for |t| >= radius (box: outside [-1/2, 1/2]).
struct Profile {
    int64_t kind;
    double radius;
    const double* pieces;
    int64_t rows, cols;
    double alpha, bias;
};

constexpr int64_t KIND_BOX = 0;
constexpr int64_t KIND_POLYNOMIAL = 1;
constexpr int64_t KIND_GAUSSIAN = 2;

inline double profile_at(const Profile& f, double t) {
    if (f.kind == KIND_BOX) return std::fabs(t) <= 0.5 ? 1.0 : 0.0;
    if (std::fabs(t) >= f.radius) return 0.0;
    if (f.kind == KIND_GAUSSIAN) return pymax(0.0, std::exp(f.alpha * t * t) - f.bias);
    int64_t p = to_i64(std::floor(t));
    int64_t r = f.rows / 2;
    double s = t - (static_cast<double>(p) + 0.5);
    int64_t row = p + r;
    double value = 0.0;
    for (int64_t a = f.cols - 1; a >= 0; --a) value = value * s + f.pieces[row * f.cols + a];
    return value;
}

// k(t) of the profile at each of t[0 .. n), into out.
inline void profile_values(const Profile& f, const double* t, size_t n, double* out) {
    for (size_t i = 0; i < n; ++i) out[i] = profile_at(f, t[i]);
}

// The filtered image (height, width, 3) from k x k point samples per pixel into image
// (zeroed by the caller); returns false when a pixel's collected filter weight is zero
// (the binding raises ZeroDivisionError: a pixel without weight has no value).
bool sample_image(int64_t width, int64_t height, const Polygons& P, double eps_z, const double* colors,
                  const double* background, int64_t k, bool jitter, uint64_t seed, const Profile& filter,
                  double* image);

// A uniform number in [0, 1) fixed by (seed, row, col, sample, axis).
double jitter_uniform(uint64_t seed, int64_t row, int64_t col, int64_t sample, int64_t axis);

// The A-buffer image (height, width, 3) of the polygons (abuffer.cpp).
void abuffer_image(int64_t width, int64_t height, const Polygons& P, double eps_z, const double* colors,
                   const double* background, double* image);

// Shamos-Hoey sweep over the edges e = (a[e], b[e]) of pts (simplicity.cpp): two edges
// that meet, or (-1, -1). Returns false when the arrays are inconsistent.
bool sweep(int64_t n, const double* pts, const int64_t* a, const int64_t* b, const int64_t* order,
           const int64_t* incoming, int64_t& e_out, int64_t& f_out);

// The first pair of edges (e < f, in order of e, then f) that meet, or (-1, -1): every pair
// whose bounding boxes meet is tested (simplicity.cpp), for rings too small for the sweep to
// pay; the pair aaeval/scenes/simplicity.py's numpy reference (_brute_force) finds.
void first_meeting_pair(int64_t n, const double* pts, const int64_t* a, const int64_t* b, int64_t& e_out,
                        int64_t& f_out);

}  // namespace aaeval::samplers
