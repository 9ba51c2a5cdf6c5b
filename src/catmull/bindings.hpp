// The argument checks of the catmull bindings (module.cpp, testing.cpp): every input is
// checked here, once, before any kernel runs (dtypes, shapes, C order, polygon records inside
// the vertex arrays, finite coordinates, sizes); a bad input is a one-line ValueError, never
// a read out of bounds. The kernels trust their inputs.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "common/arrays.hpp"
#include "common/polygon_arrays.hpp"
#include "catmull/filter_basis.hpp"
#include "catmull/strips.hpp"

namespace nb = nanobind;

namespace aaeval::catmull::bindings {

using In = nb::ndarray<nb::ro, nb::device::cpu>;
using Out = nb::ndarray<nb::device::cpu>;

using aaeval::arrays::MAX_MAGNITUDE;
// pixels (times channels, times basis functions) an image may have
constexpr int64_t MAX_ENTRIES = int64_t(1) << 34;

[[noreturn]] inline void fail(const std::string& msg) { throw nb::value_error(("catmull: " + msg).c_str()); }

// the array's data after checking dtype, dimensions, C order and (where >= 0) the shape
template <class T, class A>
T* data_of(A& a, const char* name, std::initializer_list<int64_t> shape) {
    return aaeval::arrays::checked<T>("catmull", a, name, shape.size(), shape);
}

inline void check_finite(const double* v, size_t n, const char* name) {
    aaeval::arrays::check_finite("catmull", v, n, name, MAX_MAGNITUDE, "1e100");
}

inline void check_size(int64_t width, int64_t height, int64_t per_pixel) {
    if (width < 0 || height < 0) fail("image size must not be negative");
    if (width > MAX_ENTRIES || height > MAX_ENTRIES || (width + 1) * (height + 1) > MAX_ENTRIES / per_pixel)
        fail("image too large: " + std::to_string(width) + " x " + std::to_string(height));
}

inline void check_threads(int64_t threads) {
    if (threads < 1 || threads > 4096) fail("threads must be between 1 and 4096");
}

// The kernel polygons, checked (common/polygon_arrays.hpp), to be sorted on their first row.
inline SortedPolygons polygons(In& start, In& length, In& x, In& y, In& planes) {
    return SortedPolygons{aaeval::arrays::checked_polygons("catmull", start, length, x, y, planes)};
}

inline double check_eps(double eps_z) {
    if (!(eps_z >= 0.0 && eps_z <= MAX_MAGNITUDE)) fail("eps_z must be finite and not negative");
    return eps_z;
}

inline const double* colors_of(In& colors, int64_t n_polys) {
    const double* c = data_of<const double>(colors, "colors", {n_polys + 1, 3});
    check_finite(c, size_t(3 * (n_polys + 1)), "colors");
    return c;
}

inline Filter filter_of(int64_t kind, int64_t radius, int64_t k, double alpha, double bias) {
    if (kind != KIND_POLYNOMIAL && kind != KIND_GAUSSIAN) fail("kind must be 1 (polynomial) or 2 (Gaussian)");
    if (k < 1 || k > 64) fail("k (basis functions per axis) must be between 1 and 64");
    if (radius < 0 || radius > 64) fail("radius must be between 0 and 64");
    if (!std::isfinite(bias) || !std::isfinite(alpha)) fail("alpha and bias must be finite");
    if (kind == KIND_GAUSSIAN && !(alpha < 0.0)) fail("a Gaussian's alpha must be negative");
    return {kind, radius, k, alpha, bias};
}

}  // namespace aaeval::catmull::bindings
