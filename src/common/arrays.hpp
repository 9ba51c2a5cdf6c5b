// The checks every binding makes on an array before a kernel reads it: dtype, dimensions,
// C order, extents, finite values. A failed check is a one-line ValueError that names the
// array, prefixed with the module's name where `who` is not empty; the kernels behind the
// bindings trust their inputs.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <string>
#include <type_traits>

namespace aaeval::arrays {

[[noreturn]] inline void refuse(const char* who, const std::string& msg) {
    const std::string text = who[0] ? std::string(who) + ": " + msg : msg;
    throw nanobind::value_error(text.c_str());
}

template <class T>
const char* dtype_name() {
    return std::is_same_v<std::remove_const_t<T>, double> ? "float64" : "int64";
}

inline std::string shape_text(size_t ndim, const int64_t* shape) {
    std::string s = "(";
    for (size_t i = 0; i < ndim; ++i) s += std::to_string(shape[i]) + (ndim == 1 || i + 1 < ndim ? "," : "");
    return s + ")";
}

// The array's data as T* after checking its dtype, its ndim dimensions and C order; its
// extent along axis d must equal dims[d] where that is given and >= 0.
template <class T, class A>
T* checked(const char* who, A& a, const std::string& name, size_t ndim, std::initializer_list<int64_t> dims = {}) {
    const std::string want = name + " must be a C-contiguous " + dtype_name<T>() + " array with " +
                             std::to_string(ndim) + " dimension" + (ndim == 1 ? "" : "s");
    if (a.dtype() != nanobind::dtype<std::remove_const_t<T>>()) refuse(who, want + " (got another dtype)");
    if (a.ndim() != ndim) refuse(who, want + " (got " + std::to_string(a.ndim()) + ")");
    size_t d = 0;
    for (int64_t extent : dims) {
        if (extent >= 0 && int64_t(a.shape(d)) != extent)
            refuse(who, name + " has shape " + shape_text(a.ndim(), a.shape_ptr()) + ", expected " +
                            std::to_string(extent) + " entries along axis " + std::to_string(d));
        ++d;
    }
    if (a.size() > 0) {  // an empty array is contiguous whatever its strides
        int64_t expect = 1;
        for (size_t k = ndim; k-- > 0;) {
            if (a.shape(k) > 1 && a.stride(k) != expect) refuse(who, want + " (got a strided view)");
            expect *= int64_t(a.shape(k));
        }
    }
    return static_cast<T*>(a.data());
}

// Every value finite and, where a limit is given (`limit_text` its spelling for the
// message), at most that in magnitude.
inline void check_finite(const char* who, const double* v, size_t n, const std::string& name,
                         double limit = std::numeric_limits<double>::max(), const char* limit_text = nullptr) {
    for (size_t i = 0; i < n; ++i)
        if (!(std::fabs(v[i]) <= limit))
            refuse(who, name + "[" + std::to_string(i) + "] is " + std::to_string(v[i]) + ": values must be finite" +
                            (limit_text ? std::string(" and at most ") + limit_text + " in magnitude" : std::string()));
}

}  // namespace aaeval::arrays
