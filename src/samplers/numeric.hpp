// Scalar rules the samplers share, spelled the way the former numba kernels computed them
// so that the native images keep their bits (issue 20):
//  - min/max of floats are Python's: min(acc, v) is v only when v < acc (max: v > acc),
//    so NaN and signed zeros fall the same way;
//  - int(x) of a float truncates; a NaN or out-of-range value gives INT64_MIN, as x86-64's
//    cvttsd2si (what numba's fptosi compiled to) does, instead of C++'s undefined behaviour;
//  - integer + and - wrap (numba's int64 arithmetic) instead of overflowing.
#pragma once

#include <cstdint>

namespace aaeval::samplers {

inline double py_min(double acc, double v) { return v < acc ? v : acc; }
inline double py_max(double acc, double v) { return v > acc ? v : acc; }
inline double py_min(double a, double b, double c) { return py_min(py_min(a, b), c); }
inline double py_max(double a, double b, double c) { return py_max(py_max(a, b), c); }
inline int64_t imin(int64_t a, int64_t b) { return b < a ? b : a; }
inline int64_t imax(int64_t a, int64_t b) { return b > a ? b : a; }

inline int64_t to_i64(double x) {
  if (x >= -9223372036854775808.0 && x < 9223372036854775808.0) return static_cast<int64_t>(x);
  return INT64_MIN;
}

inline int64_t wrap_add(int64_t a, int64_t b) {
  return static_cast<int64_t>(static_cast<uint64_t>(a) + static_cast<uint64_t>(b));
}

}  // namespace aaeval::samplers
