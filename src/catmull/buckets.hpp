// III.C.4 of Catmull 1978: the x-bucket, the strip pieces listed under their leftmost pixel
// column (a counting sort), so the row sweep meets each piece where it starts.
#pragma once

#include <cstdint>
#include <vector>

#include "catmull/strips.hpp"

namespace aaeval::catmull {

inline void bucket_by_x(Strip& S, int64_t width, std::vector<int64_t>& fill) {
    std::vector<int64_t>& head = S.bucket_head;
    std::fill(head.begin(), head.end(), int64_t(0));
    for (int64_t k = 0; k < S.n; ++k) head[size_t(S.span[k][0] + 1)] += 1;
    for (int64_t col = 0; col < width; ++col) head[size_t(col + 1)] += head[size_t(col)];
    fill.assign(head.begin(), head.begin() + width);
    for (int64_t k = 0; k < S.n; ++k) {
        const int64_t c = S.span[k][0];
        S.bucket_items[size_t(fill[size_t(c)])] = k;
        fill[size_t(c)] += 1;
    }
}

}  // namespace aaeval::catmull
