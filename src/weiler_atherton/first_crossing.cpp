#include <algorithm>
#include <vector>

#include "clipper.hpp"
#include "segments.hpp"

namespace wa {

std::pair<i64, i64> first_crossing(const double* xs, const double* ys, i64 n, const i64* starts, i64 nst,
                                   double eps) {
    // edges sorted by their left end: only edges whose x ranges overlap are compared
    std::vector<i64> e0(n), e1(n), order(n);
    std::vector<double> lo(n);
    for (i64 r = 0; r + 1 < nst; ++r) {
        i64 a = starts[r], b = starts[r + 1];
        for (i64 v = a; v < b; ++v) {
            i64 w = next_in_ring(v, a, b);
            e0[v] = v;
            e1[v] = w;
            lo[v] = pmin(xs[v], xs[w]);
        }
    }
    for (i64 i = 0; i < n; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](i64 a, i64 b) { return lo[a] < lo[b]; });
    for (i64 i = 0; i < n; ++i) {
        i64 u = order[i], a0 = e0[u], a1 = e1[u];
        double hi = pmax(xs[a0], xs[a1]);
        for (i64 j = i + 1; j < n; ++j) {
            i64 w = order[j];
            if (lo[w] > hi + eps) break;
            i64 b0 = e0[w], b1 = e1[w];
            if (pmax(ys[b0], ys[b1]) < pmin(ys[a0], ys[a1]) - eps || pmin(ys[b0], ys[b1]) > pmax(ys[a0], ys[a1]) + eps)
                continue;
            if (proper_crossing(xs[a0], ys[a0], xs[a1], ys[a1], xs[b0], ys[b0], xs[b1], ys[b1], eps).hit)
                return {std::min(u, w), std::max(u, w)};
        }
    }
    return {-1, -1};
}

}  // namespace wa
