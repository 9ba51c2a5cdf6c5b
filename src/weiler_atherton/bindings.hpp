// The argument checks of the Weiler-Atherton bindings (module.cpp, testing.cpp): every input
// is checked once, before a kernel runs (dtype, dimensions, C order, consistent lengths,
// contour starts, indices in range, finite coordinates), and refused with a one-line
// ValueError; the kernels trust their inputs.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <string>
#include <vector>

#include "common/arrays.hpp"
#include "common/results.hpp"
#include "shape.hpp"

namespace nb = nanobind;

namespace wa::bindings {

using In = nb::ndarray<nb::ro, nb::device::cpu>;
using Out = nb::ndarray<nb::device::cpu>;

[[noreturn]] inline void refuse(const std::string& msg) { throw nb::value_error(msg.c_str()); }

// The array's data as T*, after checking its dtype, dimensions and C order; shape[d] must
// equal dims[d] where that is >= 0 (common/arrays.hpp).
template <class T, class A>
T* checked(A& a, const char* name, size_t ndim, std::initializer_list<i64> dims = {}) {
    return aaeval::arrays::checked<T>("", a, name, ndim, dims);
}

inline void check_finite(const double* p, i64 n, const char* name) { aaeval::arrays::check_finite("", p, size_t(n), name); }

// a tolerance: a number >= 0 (not NaN; infinite is allowed, as the kernels never index by it)
inline void check_scalar(double v, const char* name) {
    if (!(v >= 0)) refuse(std::string(name) + " must be a number >= 0");
}

// Contour starts into n vertices: 0 first, non-decreasing, n last; every contour holds at
// least `min_len` vertices. An empty array stands for no contours (n must be 0).
inline const i64* checked_starts(const In& a, const char* name, i64 n, i64& nst, i64 min_len = 1) {
    const i64* st = checked<const i64>(a, name, 1);
    nst = (i64)a.shape(0);
    if (nst == 0) {
        if (n != 0) refuse(std::string(name) + " is empty but there are vertices");
        return st;
    }
    if (st[0] != 0) refuse(std::string(name) + " must start at 0");
    for (i64 r = 0; r + 1 < nst; ++r)
        if (st[r + 1] - st[r] < min_len)
            refuse(std::string(name) + ": contour " + std::to_string(r) + " has " + std::to_string(st[r + 1] - st[r]) +
                   " vertices (at least " + std::to_string(min_len) + " needed; starts must not decrease)");
    if (st[nst - 1] != n)
        refuse(std::string(name) + " must end at the number of vertices (" + std::to_string(n) + "), not " +
               std::to_string(st[nst - 1]));
    return st;
}

// A shape's four arrays, checked.
inline wa::ShapeView shape(const In& xs, const In& ys, const In& labels, const In& starts, const char* name) {
    std::string nm(name);
    wa::ShapeView s;
    s.x = checked<const double>(xs, (nm + " xs").c_str(), 1);
    s.n = (i64)xs.shape(0);
    s.y = checked<const double>(ys, (nm + " ys").c_str(), 1, {s.n});
    s.lab = checked<const i64>(labels, (nm + " labels").c_str(), 1, {s.n});
    s.st = checked_starts(starts, (nm + " starts").c_str(), s.n, s.nst, s.n > 0 ? 1 : 0);
    check_finite(s.x, s.n, (nm + " xs").c_str());
    check_finite(s.y, s.n, (nm + " ys").c_str());
    return s;
}

// A new numpy array owning the vector's data (one dimension unless a shape is given).
template <class T>
nb::object numpy_of(std::vector<T>&& v, std::initializer_list<size_t> shape = {}) {
    const std::vector<size_t> dims = shape.size() ? std::vector<size_t>(shape) : std::vector<size_t>{v.size()};
    return nb::cast(aaeval::results::from_vector(std::move(v), dims));
}

inline nb::tuple shape_tuple(wa::Shape&& s) {
    return nb::make_tuple(numpy_of(std::move(s.x)), numpy_of(std::move(s.y)), numpy_of(std::move(s.lab)),
                          numpy_of(std::move(s.st)));
}

}  // namespace wa::bindings
