// Catmull-only forms of geometry::clip_split (common/geometry.hpp) for the two places the
// kernel clips most: the integrator's split of a polygon that whole_side found straddling
// (its distances to the line already computed there) and the clip of a strip piece to a
// pixel column (a vertical line, a = 1, b = 0). Each gives clip_split's outputs bit for bit:
// the same distances in the same rounding, the same side tests, the same intersections in
// the same order of operations.
#pragma once

#include <cstdint>

#include "common/geometry.hpp"

namespace aaeval::catmull {

using geometry::EPS_LINE;
using geometry::side;
using geometry::SplitCounts;

// geometry::settle_flags done as the part is written, instead of in a second pass over it:
// each vertex's flag is settled when the next vertex's raw flag is known, the last one's
// against the first's, with settle_flags' own expression. Only the flags of a part of 3 or
// more vertices are settled (its count is 0 otherwise and no one reads them, as there).
struct Settler {
    uint8_t* f;  // the part's flags
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

// geometry::clip_split(..., a, b, c, true, true, ...) with d[k] = a * xs[start + k] +
// b * ys[start + k] + c given (the expression clip_split evaluates, so the same doubles).
AAEVAL_INLINE SplitCounts split_by_distances(const double* xs, const double* ys, const uint8_t* fs, int64_t start,
                                             int64_t n, const double* d, double a, double b, double c, double* oxs,
                                             double* oys, uint8_t* ofs, int64_t astart, int64_t bstart) {
    int64_t ma = 0, mb = 0;
    Settler sa{ofs + astart}, sb{ofs + bstart};
    if (n > 0) {
        int64_t prev = start + n - 1;
        double dp = d[n - 1];
        int sp = side(dp);
        for (int64_t k = 0; k < n; ++k) {
            const int64_t i = start + k;
            const double di = d[k];
            const int s = side(di);
            if (sp * s < 0) {
                const double t = dp / (dp - di);
                double x = xs[prev] + t * (xs[i] - xs[prev]);
                double y = ys[prev] + t * (ys[i] - ys[prev]);
                if (b == 0.0) {
                    x = -c / a;
                } else if (a == 0.0) {
                    y = -c / b;
                }
                const uint8_t fl = uint8_t(2 + fs[prev]);
                oxs[astart + ma] = x;
                oys[astart + ma] = y;
                sa.push(fl);
                ++ma;
                oxs[bstart + mb] = x;
                oys[bstart + mb] = y;
                sb.push(fl);
                ++mb;
            }
            const int on = s == 0 ? 2 : 0;
            if (s <= 0) {
                oxs[astart + ma] = xs[i];
                oys[astart + ma] = ys[i];
                sa.push(uint8_t(on + fs[i]));
                ++ma;
            }
            if (s >= 0) {
                oxs[bstart + mb] = xs[i];
                oys[bstart + mb] = ys[i];
                sb.push(uint8_t(on + fs[i]));
                ++mb;
            }
            prev = i;
            dp = di;
            sp = s;
        }
    }
    const int64_t ra = sa.finish();
    const int64_t rb = sb.finish();
    return {ra, rb};
}

// geometry::clip_side(xs, ys, fs, start, n, 1.0, 0.0, c, KEEP, ...): the part of a polygon
// on side KEEP of the vertical line x + c = 0. clip_split's distance there is
// (1.0 * x + 0.0 * y) + c; for finite y it is x + c exactly, but for the sign of a zero
// (x = -0 or c = -0 alone), and a zero classifies as side 0 either way and never enters an
// intersection (only strict crossings do). The crossing's x is clip_split's -c / a = -c.
template <int KEEP>
AAEVAL_INLINE int64_t clip_vertical(const double* xs, const double* ys, const uint8_t* fs, int64_t start, int64_t n,
                                    double c, double* oxs, double* oys, uint8_t* ofs, int64_t ostart) {
    int64_t m = 0;
    Settler st{ofs + ostart};
    if (n > 0) {
        int64_t prev = start + n - 1;
        double dp = xs[prev] + c;
        int sp = side(dp);
        const double xc = -c;
        for (int64_t i = start; i < start + n; ++i) {
            const double d = xs[i] + c;
            const int s = side(d);
            if (sp * s < 0) {
                const double t = dp / (dp - d);
                oxs[ostart + m] = xc;
                oys[ostart + m] = ys[prev] + t * (ys[i] - ys[prev]);
                st.push(uint8_t(2 + fs[prev]));
                ++m;
            }
            if (KEEP < 0 ? s <= 0 : s >= 0) {
                oxs[ostart + m] = xs[i];
                oys[ostart + m] = ys[i];
                st.push(uint8_t((s == 0 ? 2 : 0) + fs[i]));
                ++m;
            }
            prev = i;
            dp = d;
            sp = s;
        }
    }
    return st.finish();
}

// geometry::clip_to_column through clip_vertical: the part of a polygon in the pixel column
// x0 <= x <= x0 + 1, written at `at`, the first clip going to `tmp` (2 n + 4 entries each).
AAEVAL_INLINE int64_t column_clip(const double* xs, const double* ys, const uint8_t* fs, int64_t start, int64_t n,
                                  double x0, double* oxs, double* oys, uint8_t* ofs, int64_t at, int64_t tmp) {
    const int64_t m1 = clip_vertical<1>(xs, ys, fs, start, n, -x0, oxs, oys, ofs, tmp);
    return clip_vertical<-1>(oxs, oys, ofs, tmp, m1, -(x0 + 1.0), oxs, oys, ofs, at);
}

}  // namespace aaeval::catmull
