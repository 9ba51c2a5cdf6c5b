// Exact box filter of non-overlapping polygons: each pixel gets the area of every piece
// over its square, accumulated edge by edge (aaeval.weiler_atherton.raster is the API).
#pragma once

#include "shape.hpp"

namespace wa {

// out (h, w, k), C order, += per-pixel sum of weights[ring] (k a ring) * area of ring
// over the pixel; ring r is vertices starts[r]..starts[r + 1] - 1 (signed: holes negative).
void add_coverage(const double* xs, const double* ys, const i64* starts, i64 nrings, const double* weights,
                  double* out, i64 h, i64 w, i64 k);

}  // namespace wa
