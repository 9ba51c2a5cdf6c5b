#include "holed_outline.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "solver.hpp"

namespace wa {

namespace {

using Edge = std::array<double, 4>;  // x0, y0, x1, y1

Edge reversed(const Edge& e) { return Edge{e[2], e[3], e[0], e[1]}; }

}  // namespace

Outline holed_outline(const double* ox, const double* oy, const i64* ost, const std::vector<i64>& parts) {
    std::vector<Edge> edges;
    for (i64 p : parts)
        for (i64 v = ost[p]; v < ost[p + 1]; ++v) {
            i64 u = next_in_ring(v, ost[p], ost[p + 1]);
            edges.push_back(Edge{ox[v], oy[v], ox[u], oy[u]});
        }
    std::sort(edges.begin(), edges.end());
    // an edge shared by two parts is walked once each way: both go
    std::vector<char> gone(edges.size(), 0);
    for (size_t i = 0; i < edges.size(); ++i) {
        if (gone[i]) continue;
        Edge r = reversed(edges[i]);
        for (auto it = std::lower_bound(edges.begin(), edges.end(), r); it != edges.end() && *it == r; ++it) {
            size_t k = (size_t)(it - edges.begin());
            if (!gone[k] && k != i) {
                gone[i] = gone[k] = 1;
                break;
            }
        }
    }
    // the rest linked into rings: from each edge's end, the first edge left that starts there
    Outline o;
    o.st.push_back(0);
    for (size_t i = 0; i < edges.size(); ++i) {
        if (gone[i]) continue;
        size_t e = i;
        while (true) {
            gone[e] = 1;
            o.x.push_back(edges[e][0]);
            o.y.push_back(edges[e][1]);
            Edge from{edges[e][2], edges[e][3], -INFINITY, -INFINITY};
            auto it = std::lower_bound(edges.begin(), edges.end(), from);
            while (it != edges.end() && (*it)[0] == from[0] && (*it)[1] == from[1] && gone[it - edges.begin()]) ++it;
            if (it == edges.end() || (*it)[0] != from[0] || (*it)[1] != from[1]) break;  // back at the ring's start
            e = (size_t)(it - edges.begin());
        }
        o.st.push_back((i64)o.x.size());
    }
    i64 n = (i64)o.x.size();
    o.lab.assign(n, EDGE_CUT);
    o.len.resize(n);
    for (size_t r = 0; r + 1 < o.st.size(); ++r)
        for (i64 v = o.st[r]; v < o.st[r + 1]; ++v) {
            i64 u = next_in_ring(v, o.st[r], o.st[r + 1]);
            o.len[v] = std::hypot(o.x[u] - o.x[v], o.y[u] - o.y[v]);
        }
    return o;
}

HoledOutlines::HoledOutlines(const double* ox_, const double* oy_, const i64* ost_, const i64* group_, i64 npoly,
                             double eps_)
    : ox(ox_), oy(oy_), ost(ost_), group(group_), eps(eps_) {
    if (!group) return;
    parts.resize(npoly);
    outline.resize(npoly);
    built.assign(npoly, 0);
    for (i64 p = 0; p < npoly; ++p)
        if (ost[p + 1] > ost[p]) parts[group[p]].push_back(p);
}

const Outline& HoledOutlines::of(i64 g) {
    if (!built[g]) {
        outline[g] = holed_outline(ox, oy, ost, parts[g]);
        outline[g].clean = self_clean(outline[g].view(), eps, scratch);
        index_chunks(outline[g]);
        built[g] = 1;
    }
    return outline[g];
}

}  // namespace wa
