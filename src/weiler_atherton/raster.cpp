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

struct Diff {
    std::vector<double> d;  // (h, w + 1, k)
    i64 w1, k;
    double* at(i64 r, i64 c) { return d.data() + (r * w1 + c) * k; }
};

// First and last cell [c, c + 1), 0 <= c < n, that the interval lo < hi overlaps (an end
// out of int64's range is INT64_MIN by to_int, and top wraps: both fall outside the clamp).
inline void unit_cells(double lo, double hi, i64 n, i64& c0, i64& c1) {
    c0 = std::max<i64>(to_int(std::floor(lo)), 0);
    i64 top = (i64)((std::uint64_t)to_int(std::ceil(hi)) - 1u);
    c1 = std::min<i64>(top, n - 1);
}

// Cell (r, c) gets `area`, every cell right of it `height`: as differences, area at c and
// the rest of the height at c + 1, in every channel.
inline void add_cell(Diff& diff, i64 r, i64 c, const double* weight, double area, double height) {
    double* a = diff.at(r, c);
    double* b = diff.at(r, c + 1);
    for (i64 q = 0; q < diff.k; ++q) {
        a[q] += weight[q] * area;
        b[q] += weight[q] * (height - area);
    }
}

// A segment spanning height dy (signed) of row r, from x = xa to xb.
inline void row_segment(i64 r, double xa, double xb, double dy, i64 w, const double* weight, Diff& diff) {
    if (xa == xb) {
        double x = xa;
        if (x <= 0.0) {
            double* a = diff.at(r, 0);
            for (i64 q = 0; q < diff.k; ++q) a[q] += weight[q] * dy;
        } else if (x < w) {
            i64 c = to_int(std::floor(x));
            add_cell(diff, r, c, weight, dy * ((double)(c + 1) - x), dy);
        }
        return;
    }
    double lo = pmin(xa, xb), hi = pmax(xa, xb);
    double per_x = dy / (hi - lo);  // height per unit of x
    if (lo < 0.0) {
        double* a = diff.at(r, 0);
        for (i64 q = 0; q < diff.k; ++q) a[q] += weight[q] * (per_x * (pmin(hi, 0.0) - lo));
    }
    i64 c0, c1;
    unit_cells(lo, hi, w, c0, c1);
    for (i64 c = c0; c <= c1; ++c) {
        double u = pmax(lo, (double)c), v = pmin(hi, (double)(c + 1));
        double hh = per_x * (v - u);
        add_cell(diff, r, c, weight, hh * ((double)(c + 1) - 0.5 * (u + v)), hh);
    }
}

}  // namespace

void add_coverage(const double* xs, const double* ys, const i64* starts, i64 nrings, const double* weights,
                  double* out, i64 h, i64 w, i64 k) {
    Diff diff{std::vector<double>((size_t)(h * (w + 1) * k), 0.0), w + 1, k};
    for (i64 ring = 0; ring < nrings; ++ring) {
        i64 s = starts[ring], n = starts[ring + 1] - s;
        const double* wt = weights + ring * k;  // the contour's weight in every channel
        for (i64 i = 0; i < n; ++i) {
            double x0 = xs[s + i], y0 = ys[s + i];
            i64 j = s + (i + 1) % n;
            double x1 = xs[j], y1 = ys[j];
            if (y0 == y1) continue;
            double ylo = pmax(pmin(y0, y1), 0.0), yhi = pmin(pmax(y0, y1), (double)h);
            if (ylo >= yhi) continue;
            double dxdy = (x1 - x0) / (y1 - y0);
            double sign = y1 > y0 ? 1.0 : -1.0;
            i64 r0, r1;
            unit_cells(ylo, yhi, h, r0, r1);
            for (i64 r = r0; r <= r1; ++r) {
                double ya = pmax(ylo, (double)r), yb = pmin(yhi, (double)(r + 1));
                double xa = x0 + (ya - y0) * dxdy, xb = x0 + (yb - y0) * dxdy;
                row_segment(r, xa, xb, sign * (yb - ya), w, wt, diff);
            }
        }
    }
    // each cell's total: the running sum of the differences along its row, negated (the
    // accumulated area lies right of each edge; a positive contour's edges going down, y
    // growing, bound its interior from the right), added to out
    std::vector<double> run(k);
    for (i64 r = 0; r < h; ++r) {
        std::fill(run.begin(), run.end(), 0.0);
        for (i64 c = 0; c < w; ++c) {
            const double* d = diff.at(r, c);
            double* o = out + (r * w + c) * k;
            for (i64 q = 0; q < k; ++q) {
                run[q] += d[q];
                o[q] -= run[q];
            }
        }
    }
}

}  // namespace wa
