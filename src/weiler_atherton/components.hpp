// Connected components of a graph by union-find (path halving): the near-tie groups, and
// the scene checks' and importers' groups of touching rings.
#pragma once

#include <vector>

#include "shape.hpp"

namespace wa {

// Per node of the graph on n nodes with edges a[e] - b[e] (e < m): the smallest node of its
// component.
inline std::vector<i64> components(i64 n, const i64* a, const i64* b, i64 m) {
    std::vector<i64> parent(n);
    for (i64 i = 0; i < n; ++i) parent[i] = i;
    auto find = [&](i64 x) {
        while (parent[x] != x) {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        return x;
    };
    for (i64 e = 0; e < m; ++e) {
        i64 ra = find(a[e]), rb = find(b[e]);
        if (ra < rb) parent[rb] = ra;
        else if (rb < ra) parent[ra] = rb;
    }
    for (i64 i = 0; i < n; ++i) parent[i] = find(i);
    return parent;
}

}  // namespace wa
