// Steps 3-4 of the Weiler-Atherton clipper: the classified directed edges linked into the
// inside and outside contours (clip_stages.hpp declares trace).
#include <cmath>

#include "clip_stages.hpp"

namespace wa {

namespace {

constexpr double TWO_PI = 2.0 * 3.141592653589793;

// The clockwise turn from the way the walk came (angle back) onto edge f leaving point v,
// in (0, 2 pi].
double turn(double back, i64 f, const std::vector<i64>& eb, const std::vector<double>& ux,
            const std::vector<double>& uy, i64 v) {
    double t = pmod(back - std::atan2(uy[eb[f]] - uy[v], ux[eb[f]] - ux[v]), TWO_PI);
    return t == 0.0 ? TWO_PI : t;
}

}  // namespace

// Link directed edges into closed contours, turning at shared vertices onto the first
// edge clockwise from the way the walk came (keeps contours free of crossings); drop the
// zero-area leftovers of degenerate contact.
void trace(const Edges& edges, const std::vector<double>& ux, const std::vector<double>& uy, double eps,
           ClipScratch::Arrays& w, Shape& out) {
    const std::vector<i64>& ea = edges.from;
    const std::vector<i64>& eb = edges.to;
    i64 m = (i64)ea.size(), nu = (i64)ux.size();
    std::vector<i64>& head = w.head;
    std::vector<i64>& out_edges = w.out_edges;
    // where every point starts one edge at most (as on the clean road), the walk's next
    // edge is that one, found in one array; else the edges are grouped by start
    std::vector<i64>& exit = w.exit;
    exit.assign(nu, -1);
    bool single = true;
    for (i64 e = 0; e < m && single; ++e) {
        single = exit[ea[e]] < 0;
        exit[ea[e]] = e;
    }
    if (!single) grouped(ea.data(), m, nu, head, out_edges);
    std::vector<char>& used = w.used;
    used.assign(m, 0);
    out.x.resize(m);
    out.y.resize(m);
    out.lab.resize(m);
    out.st.clear();
    i64 n = 0;
    for (i64 e0 = 0; e0 < m; ++e0) {
        if (used[e0]) continue;
        i64 first = n, e = e0;
        while (true) {
            used[e] = 1;
            out.x[n] = ux[ea[e]];
            out.y[n] = uy[ea[e]];
            out.lab[n] = edges.lab[e];
            ++n;
            i64 v = eb[e], best = -1, count = 0;
            double best_turn = 0.0, back = 0.0;
            if (single) {
                best = exit[v] >= 0 && !used[exit[v]] ? exit[v] : -1;
                if (best < 0) break;
                e = best;
                continue;
            }
            for (i64 k = head[v]; k < head[v + 1]; ++k) {
                i64 f = out_edges[k];
                if (used[f]) continue;
                ++count;
                if (count == 1) {
                    best = f;
                    continue;
                }
                if (count == 2) {
                    back = std::atan2(uy[ea[e]] - uy[v], ux[ea[e]] - ux[v]);
                    best_turn = turn(back, best, eb, ux, uy, v);
                }
                double t = turn(back, f, eb, ux, uy, v);
                if (t < best_turn) {
                    best_turn = t;
                    best = f;
                }
            }
            if (best < 0) break;
            e = best;
        }
        if (n - first >= 3 && std::fabs(ring_area_of(out.x.data(), out.y.data(), first, n)) > eps * eps)
            out.st.push_back(first);
        else
            n = first;  // too short or zero area: dropped
    }
    out.st.push_back(n);
    out.x.resize(n);
    out.y.resize(n);
    out.lab.resize(n);
}


}  // namespace wa
