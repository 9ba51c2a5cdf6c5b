// The scene's polygons as every kernel family reads them: flat arrays borrowed from the
// caller, polygon p being vertices start[p] .. start[p] + length[p] - 1 of x and y with the
// depth plane z = a x + b y + c in planes[3p .. 3p + 2]. The bindings check them with
// common/polygon_arrays.hpp; the kernels trust them.
#pragma once

#include <cstdint>

namespace aaeval {

struct Polygons {
    int64_t n = 0;
    const int64_t* start = nullptr;
    const int64_t* length = nullptr;
    const double* x = nullptr;
    const double* y = nullptr;
    const double* planes = nullptr;  // n x 3
};

}  // namespace aaeval
