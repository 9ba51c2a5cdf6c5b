// Polygon geometry shared by the native kernels: half-plane clipping with Catmull's clip
// flags, the shoelace area and the area centroid (first moments), one definition for the
// Catmull kernel and its sinks.
//
// A polygon is a run of vertices xs[start .. start+n), ys[...] with a flag per vertex:
// flags[i] = 1 when the edge from vertex i to the next lies on a clipping line (or a pixel
// boundary) and so must never be chosen as a clipping edge again. Lines are a x + b y + c = 0
// with (a, b) a unit normal; side A is d < 0, side B d > 0 (Catmull 1978, "The Clipping
// Algorithm"), and points within EPS_LINE of the line belong to both sides, so no
// near-duplicate vertices are made.
//
// Every floating-point operation runs in a fixed order, with no contraction into FMAs
// (build with -ffp-contract=off), so the images' bits are the same on every machine (what
// the same-bits digests of tests/helpers/same_bits.py check).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "common/numeric.hpp"
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace aaeval::geometry {

// Distance (pixels) under which a point counts as lying on a clipping line: far above
// float64 rounding of pixel coordinates, far below any area the tests resolve.
inline constexpr double EPS_LINE = 1e-11;

// Python's min/max (common/numeric.hpp)
using numeric::pymax;
using numeric::pymin;

// The correctly rounded square root (IEEE), as one instruction: std::sqrt keeps a library
// call for errno on negative input, which the kernels never pass.
AAEVAL_INLINE double sqrt_ieee(double v) {
#if defined(__SSE2__)
    return _mm_cvtsd_f64(_mm_sqrt_sd(_mm_setzero_pd(), _mm_set_sd(v)));
#else
    return std::sqrt(v);
#endif
}

AAEVAL_INLINE int side(double d) {
    if (d < -EPS_LINE) return -1;
    if (d > EPS_LINE) return 1;
    return 0;
}

// An output edge lies on the line when both its ends do; else it keeps its flag. The flags
// are settled as a part is written: a vertex's raw flag (2 marks "on the line" until then)
// when the next one's is known, the last one's against the first's. finish() returns the
// vertex count, or 0 when fewer than 3 are left (their flags are then left unsettled: no
// one reads a part of count 0).
struct FlagSettler {
    uint8_t* f;  // the part's flags, from its first vertex
    int64_t m = 0;
    uint8_t first = 0, prev = 0;
    AAEVAL_INLINE static uint8_t settled(uint8_t cur, uint8_t next) {
        return (cur >= 2 && next >= 2) ? uint8_t(1) : uint8_t(cur & 1);
    }
    AAEVAL_INLINE void push(uint8_t raw) {
        if (m > 0)
            f[m - 1] = settled(prev, raw);
        else
            first = raw;
        prev = raw;
        ++m;
    }
    AAEVAL_INLINE int64_t finish() {
        if (m < 3) return 0;
        f[m - 1] = settled(prev, first);
        return m;
    }
};

struct SplitCounts {
    int64_t a, b;
};

// Split a polygon by a line into its side-A and side-B parts in one pass. Writes the wanted
// parts at astart / bstart and returns their vertex counts (0 for a part not wanted or with
// fewer than 3 vertices; the caller checks the area, since a part may also degenerate to a
// line). Edges lying on the line get flag 1; the others keep the flag of the edge they are
// part of. The outputs must not overlap the input (they may share its buffers). dist(i) is
// vertex i's signed distance a * xs[i] + b * ys[i] + c (clip_split), or a caller's own
// equal value (the Catmull kernel's: already computed, or exact on a vertical line).
template <class Dist>
AAEVAL_INLINE SplitCounts split_by(const double* xs, const double* ys, const uint8_t* fs, int64_t start, int64_t n,
                                   Dist dist, double a, double b, double c, bool want_a, bool want_b, double* axs,
                                   double* ays, uint8_t* afs, int64_t astart, double* bxs, double* bys, uint8_t* bfs,
                                   int64_t bstart) {
    int64_t ma = 0, mb = 0;
    FlagSettler sa{afs + astart}, sb{bfs + bstart};
    if (n > 0) {
        int64_t prev = start + n - 1;
        double dp = dist(prev);
        int sp = side(dp);
        for (int64_t i = start; i < start + n; ++i) {
            const double d = dist(i);
            const int s = side(d);
            if (sp * s < 0) {
                // strict crossing: the intersection belongs to both parts; the edge leaving it
                // continues the original edge prev->i (2 marks "on the line" until the end)
                const double t = dp / (dp - d);
                double x = xs[prev] + t * (xs[i] - xs[prev]);
                double y = ys[prev] + t * (ys[i] - ys[prev]);
                if (b == 0.0) {
                    x = -c / a;
                } else if (a == 0.0) {
                    y = -c / b;
                }
                if (want_a) {
                    axs[astart + ma] = x;
                    ays[astart + ma] = y;
                    sa.push(uint8_t(2 + fs[prev]));
                    ++ma;
                }
                if (want_b) {
                    bxs[bstart + mb] = x;
                    bys[bstart + mb] = y;
                    sb.push(uint8_t(2 + fs[prev]));
                    ++mb;
                }
            }
            const int on = s == 0 ? 2 : 0;
            if (want_a && s <= 0) {
                axs[astart + ma] = xs[i];
                ays[astart + ma] = ys[i];
                sa.push(uint8_t(on + fs[i]));
                ++ma;
            }
            if (want_b && s >= 0) {
                bxs[bstart + mb] = xs[i];
                bys[bstart + mb] = ys[i];
                sb.push(uint8_t(on + fs[i]));
                ++mb;
            }
            prev = i;
            dp = d;
            sp = s;
        }
    }
    // (both parts settled, in this order; with one part unwanted its count is 0)
    const int64_t ra = sa.finish();
    const int64_t rb = sb.finish();
    return {ra, rb};
}

AAEVAL_INLINE SplitCounts clip_split(const double* xs, const double* ys, const uint8_t* fs, int64_t start, int64_t n,
                                     double a, double b, double c, bool want_a, bool want_b, double* axs, double* ays,
                                     uint8_t* afs, int64_t astart, double* bxs, double* bys, uint8_t* bfs,
                                     int64_t bstart) {
    return split_by(
        xs, ys, fs, start, n, [&](int64_t i) { return a * xs[i] + b * ys[i] + c; }, a, b, c, want_a, want_b, axs, ays,
        afs, astart, bxs, bys, bfs, bstart);
}

// The part of a polygon on side keep (-1: A, +1: B) of a line, at ostart; its vertex count.
// A clip adds at most one vertex per edge: leave 2 n + 2 entries.
AAEVAL_INLINE int64_t clip_side(const double* xs, const double* ys, const uint8_t* fs, int64_t start, int64_t n,
                                double a, double b, double c, int keep, double* oxs, double* oys, uint8_t* ofs,
                                int64_t ostart) {
    const SplitCounts m =
        clip_split(xs, ys, fs, start, n, a, b, c, keep < 0, keep > 0, oxs, oys, ofs, ostart, oxs, oys, ofs, ostart);
    return keep < 0 ? m.a : m.b;
}

// clip_side for the vertical line x + c = 0 (a = 1, b = 0). The distance is x + c: clip_side's
// (1.0 x + 0.0 y) + c differs from it only in the sign of a zero (finite y), which side()
// classes alike and no intersection uses (only strict crossings do), so the outputs are
// clip_side's bit for bit.
AAEVAL_INLINE int64_t clip_vertical(const double* xs, const double* ys, const uint8_t* fs, int64_t start, int64_t n,
                                    double c, int keep, double* oxs, double* oys, uint8_t* ofs, int64_t ostart) {
    const SplitCounts m = split_by(
        xs, ys, fs, start, n, [xs, c](int64_t i) { return xs[i] + c; }, 1.0, 0.0, c, keep < 0, keep > 0, oxs, oys,
        ofs, ostart, oxs, oys, ofs, ostart);
    return keep < 0 ? m.a : m.b;
}

// The part of a polygon inside the pixel column x0 <= x <= x0 + 1, written at `at`. The first
// clip goes to the scratch space at `tmp`, which must not overlap the result: leave 2 n + 4
// entries from each. Returns the vertex count (0 if nothing is left).
inline int64_t clip_to_column(const double* xs, const double* ys, const uint8_t* fs, int64_t start, int64_t n,
                              double x0, double* oxs, double* oys, uint8_t* ofs, int64_t at, int64_t tmp) {
    const int64_t m1 = clip_vertical(xs, ys, fs, start, n, -x0, 1, oxs, oys, ofs, tmp);
    return clip_vertical(oxs, oys, ofs, tmp, m1, -(x0 + 1.0), -1, oxs, oys, ofs, at);
}

// Shoelace area (fan from the first vertex); positive for the orientation every polygon is
// normalised to (y down). 0 for fewer than 3 vertices.
AAEVAL_INLINE double signed_area(const double* xs, const double* ys, int64_t start, int64_t n) {
    double s = 0.0;
    const double x0 = xs[start];
    const double y0 = ys[start];
    for (int64_t i = start + 1; i < start + n - 1; ++i)
        s += (xs[i] - x0) * (ys[i + 1] - y0) - (xs[i + 1] - x0) * (ys[i] - y0);
    return 0.5 * s;
}

struct AreaCentroid {
    double area, cx, cy;
};

// Signed area and area centroid of a polygon (fan from its first vertex); the first vertex
// as the centroid of a polygon of zero area.
inline AreaCentroid area_centroid(const double* xs, const double* ys, int64_t start, int64_t n) {
    const double x0 = xs[start];
    const double y0 = ys[start];
    double s = 0.0, sx = 0.0, sy = 0.0;
    for (int64_t i = start + 1; i < start + n - 1; ++i) {
        const double ax = xs[i] - x0;
        const double ay = ys[i] - y0;
        const double bx = xs[i + 1] - x0;
        const double by = ys[i + 1] - y0;
        const double cross = ax * by - bx * ay;
        s += cross;
        sx += cross * (ax + bx);
        sy += cross * (ay + by);
    }
    if (s == 0.0) return {0.0, x0, y0};
    return {0.5 * s, x0 + sx / (3.0 * s), y0 + sy / (3.0 * s)};
}

// The part of polygon (x, y)[0 .. n) inside the window [x0, x1] x [y0, y1]: clip_side
// against its four sides in turn (inside: side A of -x + x0, x - x1, -y + y0, y - y1), as
// interleaved x, y; empty when nothing is left.
inline std::vector<double> clip_to_window(const double* x, const double* y, int64_t n, double x0, double y0,
                                          double x1, double y1) {
    const double lines[4][3] = {{-1.0, 0.0, x0}, {1.0, 0.0, -x1}, {0.0, -1.0, y0}, {0.0, 1.0, -y1}};
    std::vector<double> cx(x, x + n), cy(y, y + n);
    std::vector<uint8_t> cf(size_t(n), 0);
    int64_t m = n;
    for (const auto& l : lines) {
        const int64_t size = 2 * m + 4;
        std::vector<double> ox(static_cast<size_t>(size)), oy(static_cast<size_t>(size));
        std::vector<uint8_t> of(static_cast<size_t>(size));
        m = clip_side(cx.data(), cy.data(), cf.data(), 0, m, l[0], l[1], l[2], -1, ox.data(), oy.data(), of.data(), 0);
        if (m == 0) return {};
        cx.swap(ox);
        cy.swap(oy);
        cf.swap(of);
    }
    std::vector<double> out(size_t(2 * m));
    for (int64_t i = 0; i < m; ++i) {
        out[size_t(2 * i)] = cx[size_t(i)];
        out[size_t(2 * i + 1)] = cy[size_t(i)];
    }
    return out;
}

}  // namespace aaeval::geometry
