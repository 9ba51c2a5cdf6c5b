// Growable workspace buffers. Room for n gives max(n, 2 size) entries: doubling keeps the
// number of regrowths logarithmic in the largest pixel a render meets.
#pragma once

#include <cstdint>
#include <vector>

#include "common/geometry.hpp"

namespace aaeval::catmull {

template <class T>
inline void grow(std::vector<T>& a, int64_t n) {
    const int64_t size = int64_t(a.size());
    if (n <= size) return;
    a.resize(size_t(n > 2 * size ? n : 2 * size));
}

// rows of `width` entries (records (start, length, source), column spans, list heads)
template <class T, int W>
struct Rows {
    std::vector<T> data;
    explicit Rows(int64_t rows = 0) : data(size_t(rows * W)) {}
    int64_t rows() const { return int64_t(data.size()) / W; }
    T* operator[](int64_t r) { return data.data() + r * W; }
    const T* operator[](int64_t r) const { return data.data() + r * W; }
    void grow_rows(int64_t n) {
        const int64_t size = rows();
        if (n <= size) return;
        data.resize(size_t((n > 2 * size ? n : 2 * size) * W));
    }
};

// vertex buffers: x, y and the clip flag of the edge leaving each vertex
struct Verts {
    std::vector<double> x, y;
    std::vector<uint8_t> f;
    explicit Verts(int64_t n) : x(size_t(n)), y(size_t(n)), f(size_t(n), 0) {}
    int64_t size() const { return int64_t(x.size()); }
    void grow_to(int64_t n) {
        grow(x, n);
        grow(y, n);
        grow(f, n);
    }
    void swap(Verts& o) {
        x.swap(o.x);
        y.swap(o.y);
        f.swap(o.f);
    }
};

// a double's floor or ceil as an integer, clamped far outside any image (no overflow)
AAEVAL_INLINE int64_t to_index(double v) {
    constexpr double LIMIT = 4.0e18;
    if (!(v > -LIMIT)) return -int64_t(4000000000000000000LL);
    if (v > LIMIT) return int64_t(4000000000000000000LL);
    return int64_t(v);
}

}  // namespace aaeval::catmull
