// The Catmull kernel's two hot clips as geometry::split_by (common/geometry.hpp) with distances
// of their own: the integrator's split of a polygon that whole_side found straddling (its
// distances to the line already computed there) and the clip of a strip piece to a pixel
// column (a vertical line, a = 1, b = 0). Each gives clip_split's outputs bit for bit: the
// same distances in the same rounding, so the same side tests and intersections.
#pragma once

#include <cstdint>

#include "common/geometry.hpp"

namespace aaeval::catmull {

using geometry::SplitCounts;

// geometry::clip_split(..., a, b, c, true, true, ...) with d[k] = a * xs[start + k] +
// b * ys[start + k] + c given (the expression clip_split evaluates, so the same doubles).
AAEVAL_INLINE SplitCounts split_by_distances(const double* xs, const double* ys, const uint8_t* fs, int64_t start,
                                             int64_t n, const double* d, double a, double b, double c, double* oxs,
                                             double* oys, uint8_t* ofs, int64_t astart, int64_t bstart) {
    return geometry::split_by(
        xs, ys, fs, start, n, [d, start](int64_t i) { return d[i - start]; }, a, b, c, true, true, oxs, oys, ofs,
        astart, oxs, oys, ofs, bstart);
}

// geometry::clip_side(xs, ys, fs, start, n, 1.0, 0.0, c, KEEP, ...): the part of a polygon
// on side KEEP of the vertical line x + c = 0. clip_split's distance there is
// (1.0 * x + 0.0 * y) + c; for finite y it is x + c exactly, but for the sign of a zero
// (x = -0 or c = -0 alone), and a zero classifies as side 0 either way and never enters an
// intersection (only strict crossings do).
template <int KEEP>
AAEVAL_INLINE int64_t clip_vertical(const double* xs, const double* ys, const uint8_t* fs, int64_t start, int64_t n,
                                    double c, double* oxs, double* oys, uint8_t* ofs, int64_t ostart) {
    const SplitCounts m = geometry::split_by(
        xs, ys, fs, start, n, [xs, c](int64_t i) { return xs[i] + c; }, 1.0, 0.0, c, KEEP < 0, KEEP > 0, oxs, oys,
        ofs, ostart, oxs, oys, ofs, ostart);
    return KEEP < 0 ? m.a : m.b;
}

// geometry::clip_to_column through clip_vertical: the part of a polygon in the pixel column
// x0 <= x <= x0 + 1, written at `at`, the first clip going to `tmp` (2 n + 4 entries each).
AAEVAL_INLINE int64_t column_clip(const double* xs, const double* ys, const uint8_t* fs, int64_t start, int64_t n,
                                  double x0, double* oxs, double* oys, uint8_t* ofs, int64_t at, int64_t tmp) {
    const int64_t m1 = clip_vertical<1>(xs, ys, fs, start, n, -x0, oxs, oys, ofs, tmp);
    return clip_vertical<-1>(oxs, oys, ofs, tmp, m1, -(x0 + 1.0), oxs, oys, ofs, at);
}

}  // namespace aaeval::catmull
