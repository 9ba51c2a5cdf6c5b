// Exact box filter of non-overlapping polygons: each pixel gets the area of every piece
// over its square, accumulated edge by edge (aaeval.weiler_atherton.raster is the API).
#pragma once

#include "shape.hpp"

namespace wa {

// out (h, w, k), C order, += per-pixel sum of weights[ring] (k a ring) * area of ring
// over the pixel; ring r is vertices starts[r]..starts[r + 1] - 1 (signed: holes negative).
void add_coverage(const double* xs, const double* ys, const i64* starts, i64 nrings, const double* weights,
                  double* out, i64 h, i64 w, i64 k);

// out (h, w, k), C order, written whole: base (k values) plus the same sum, with the bits
// of add_coverage on an out filled with base.
void coverage_over(const double* xs, const double* ys, const i64* starts, i64 nrings, const double* weights,
                   const double* base, double* out, i64 h, i64 w, i64 k);

}  // namespace wa
