// Every directed edge adds, to each pixel of a row it crosses, the signed area between the
// edge and the pixel's right side, and the height it spans to every pixel farther right.
// Both go into one array of differences along the row (the area to the pixel and, less
// that area, the height to the next one, as font-rs and FreeType's smooth rasterizer
// accumulate coverage), and a running sum per row settles it. Summed over a closed contour
// this is the contour's area inside each pixel, holes included; parts left of the image
// count as if on its left border and parts right of it not at all.
#include "raster.hpp"

#include <cmath>
#include <vector>

namespace wa {

namespace {

// One row's differences: (w + 1, k), cell c's channels from c * k.
struct RowDiff {
    std::vector<double> d;
    i64 k;
    double* at(i64 c) { return d.data() + c * k; }
};

// First and last cell [c, c + 1), 0 <= c < n, that the interval lo < hi overlaps (an end
// out of int64's range is INT64_MIN by to_int, and top wraps: both fall outside the clamp).
inline void unit_cells(double lo, double hi, i64 n, i64& c0, i64& c1) {
    c0 = std::max<i64>(to_int(std::floor(lo)), 0);
    i64 top = (i64)((std::uint64_t)to_int(std::ceil(hi)) - 1u);
    c1 = std::min<i64>(top, n - 1);
}

// Cell c gets `area`, every cell right of it `height`: as differences, area at c and the
// rest of the height at c + 1, in every channel.
inline void add_cell(RowDiff& diff, i64 c, const double* weight, double area, double height) {
    double* a = diff.at(c);
    double* b = diff.at(c + 1);
    for (i64 q = 0; q < diff.k; ++q) {
        a[q] += weight[q] * area;
        b[q] += weight[q] * (height - area);
    }
}

// A segment spanning height dy (signed) of the row, from x = xa to xb.
inline void row_segment(double xa, double xb, double dy, i64 w, const double* weight, RowDiff& diff) {
    if (xa == xb) {
        double x = xa;
        if (x <= 0.0) {
            double* a = diff.at(0);
            for (i64 q = 0; q < diff.k; ++q) a[q] += weight[q] * dy;
        } else if (x < w) {
            i64 c = to_int(std::floor(x));
            add_cell(diff, c, weight, dy * ((double)(c + 1) - x), dy);
        }
        return;
    }
    double lo = pmin(xa, xb), hi = pmax(xa, xb);
    double per_x = dy / (hi - lo);  // height per unit of x
    if (lo < 0.0) {
        double* a = diff.at(0);
        for (i64 q = 0; q < diff.k; ++q) a[q] += weight[q] * (per_x * (pmin(hi, 0.0) - lo));
    }
    i64 c0, c1;
    unit_cells(lo, hi, w, c0, c1);
    for (i64 c = c0; c <= c1; ++c) {
        double u = pmax(lo, (double)c), v = pmin(hi, (double)(c + 1));
        double hh = per_x * (v - u);
        add_cell(diff, c, weight, hh * ((double)(c + 1) - 0.5 * (u + v)), hh);
    }
}

// A directed edge clamped to the image's rows: its y range there, x per unit of y, which
// way it runs and the rows it touches (r0 > r1: none).
struct Edge {
    double x0, y0, ylo, yhi, dxdy, sign;
    i64 r0, r1;
};

inline Edge edge_between(double x0, double y0, double x1, double y1, i64 h) {
    Edge e{x0, y0, 0.0, 0.0, 0.0, 0.0, 0, -1};
    if (y0 == y1) return e;
    e.ylo = pmax(pmin(y0, y1), 0.0);
    e.yhi = pmin(pmax(y0, y1), (double)h);
    if (e.ylo >= e.yhi) return e;
    e.dxdy = (x1 - x0) / (y1 - y0);
    e.sign = y1 > y0 ? 1.0 : -1.0;
    unit_cells(e.ylo, e.yhi, h, e.r0, e.r1);
    return e;
}

// Vertex i's edge (to the next vertex of its ring), clamped to the image's rows.
inline Edge ring_edge(const double* xs, const double* ys, i64 s, i64 n, i64 i, i64 h) {
    const i64 j = s + (i + 1) % n;
    return edge_between(xs[s + i], ys[s + i], xs[j], ys[j], h);
}

// The coverage of the rings, row by row: finish(r, sums) gets row r's running sums of the
// differences (sums[c * k + q]: cell c's in channel q; add_coverage says what they are).
template <class Finish>
void coverage_rows(const double* xs, const double* ys, const i64* starts, i64 nrings, const double* weights, i64 h,
                   i64 w, i64 k, Finish finish) {
    // The edges touching each row, in ring and edge order (counted, then placed): every
    // cell then takes its edges' terms in the order a pass over the rings would give, from
    // one row of differences instead of a whole image of them (6 MB at 512 x 512, each
    // render's pages newly mapped, zeroed and read back).
    const i64 n_vertices = nrings > 0 ? starts[nrings] : 0;
    std::vector<Edge> edges((size_t)n_vertices);
    std::vector<i64> row_start((size_t)(h + 1), 0), ring_of((size_t)n_vertices);
    for (i64 ring = 0; ring < nrings; ++ring) {
        const i64 s = starts[ring], n = starts[ring + 1] - s;
        for (i64 i = 0; i < n; ++i) {
            ring_of[(size_t)(s + i)] = ring;
            const Edge& e = edges[(size_t)(s + i)] = ring_edge(xs, ys, s, n, i, h);
            for (i64 r = e.r0; r <= e.r1; ++r) ++row_start[(size_t)(r + 1)];
        }
    }
    for (i64 r = 0; r < h; ++r) row_start[(size_t)(r + 1)] += row_start[(size_t)r];
    std::vector<i64> row_edges((size_t)row_start[(size_t)h]);
    std::vector<i64> fill(row_start.begin(), row_start.end() - 1);
    for (i64 v = 0; v < n_vertices; ++v)
        for (i64 r = edges[(size_t)v].r0; r <= edges[(size_t)v].r1; ++r) row_edges[(size_t)fill[(size_t)r]++] = v;
    RowDiff diff{std::vector<double>((size_t)((w + 1) * k)), k};
    std::vector<double> run(k), sums((size_t)(w * k));
    for (i64 r = 0; r < h; ++r) {
        std::fill(diff.d.begin(), diff.d.end(), 0.0);
        for (i64 t = row_start[(size_t)r]; t < row_start[(size_t)(r + 1)]; ++t) {
            const i64 v = row_edges[(size_t)t];
            const Edge& e = edges[(size_t)v];
            const i64 ring = ring_of[(size_t)v];
            double ya = pmax(e.ylo, (double)r), yb = pmin(e.yhi, (double)(r + 1));
            double xa = e.x0 + (ya - e.y0) * e.dxdy, xb = e.x0 + (yb - e.y0) * e.dxdy;
            row_segment(xa, xb, e.sign * (yb - ya), w, weights + ring * k, diff);
        }
        // each cell's total: the running sum of the differences along its row
        std::fill(run.begin(), run.end(), 0.0);
        for (i64 c = 0; c < w; ++c) {
            const double* d = diff.at(c);
            for (i64 q = 0; q < k; ++q) {
                run[q] += d[q];
                sums[(size_t)(c * k + q)] = run[q];
            }
        }
        finish(r, sums.data());
    }
}

}  // namespace

// The running sums are negated into out: the accumulated area lies right of each edge, and
// a positive contour's edges going down (y growing) bound its interior from the right.
void add_coverage(const double* xs, const double* ys, const i64* starts, i64 nrings, const double* weights,
                  double* out, i64 h, i64 w, i64 k) {
    coverage_rows(xs, ys, starts, nrings, weights, h, w, k, [&](i64 r, const double* sums) {
        double* o = out + r * w * k;
        for (i64 t = 0; t < w * k; ++t) o[t] -= sums[t];
    });
}

void coverage_over(const double* xs, const double* ys, const i64* starts, i64 nrings, const double* weights,
                   const double* base, double* out, i64 h, i64 w, i64 k) {
    coverage_rows(xs, ys, starts, nrings, weights, h, w, k, [&](i64 r, const double* sums) {
        double* o = out + r * w * k;
        for (i64 c = 0; c < w; ++c)
            for (i64 q = 0; q < k; ++q) o[c * k + q] = base[q] - sums[c * k + q];
    });
}

}  // namespace wa
