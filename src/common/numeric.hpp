// Scalar rules every kernel family shares, one definition each, so that a kernel's bits do
// not depend on which family it is in:
//  - min/max are Python's: min(a, b) is b only when b < a (max: b > a), so a NaN or a signed
//    zero falls on the same side whatever the operand order of the caller's comparison;
//  - int(x) of a float truncates; a NaN or out-of-range value gives INT64_MIN, as x86-64's
//    cvttsd2si does, instead of C++'s undefined behaviour;
//  - integer + wraps instead of overflowing (undefined behaviour for int64_t).
#pragma once

#include <cstdint>

// hot helpers are inlined into every caller, where the constant lines (pixel columns) and
// the wanted sides fold away
#if defined(__GNUC__)
#define AAEVAL_INLINE inline __attribute__((always_inline))
#else
#define AAEVAL_INLINE inline
#endif

namespace aaeval::numeric {

template <class T>
AAEVAL_INLINE T pymin(T a, T b) {
    return b < a ? b : a;
}
template <class T>
AAEVAL_INLINE T pymax(T a, T b) {
    return b > a ? b : a;
}
template <class T>
AAEVAL_INLINE T pymin(T a, T b, T c) {
    return pymin(pymin(a, b), c);
}
template <class T>
AAEVAL_INLINE T pymax(T a, T b, T c) {
    return pymax(pymax(a, b), c);
}

inline int64_t to_i64(double x) {
    if (x >= -9223372036854775808.0 && x < 9223372036854775808.0) return static_cast<int64_t>(x);
    return INT64_MIN;
}

inline int64_t wrap_add(int64_t a, int64_t b) {
    return static_cast<int64_t>(static_cast<uint64_t>(a) + static_cast<uint64_t>(b));
}

}  // namespace aaeval::numeric
