// The Weiler-Atherton clipper's stages: snapping, crossings and point ids (step 1), the
// contours split at every point on them, the holding lists when no boundaries meet
// (step 2), the edges classified and traced into the inside and outside contours (steps
// 3-4). Inside clip_arrays every vertex is a point id: the index of its coordinates in
// the sorted list of distinct points of both shapes and their crossings, so shared
// vertices and edges are found by comparing integers.
#include "clipper.hpp"
#include "clip_stages.hpp"
#include "holding_lists.hpp"
#include "segments.hpp"

#include <algorithm>
#include <cmath>

namespace wa {

namespace {

using Scratch = ClipScratch::Arrays;

// The positions [first, end) of the sorted values within [lo, hi].
std::pair<i64, i64> positions_within(const std::vector<double>& sorted, double lo, double hi) {
    return {std::lower_bound(sorted.begin(), sorted.end(), lo) - sorted.begin(),
            std::upper_bound(sorted.begin(), sorted.end(), hi) - sorted.begin()};
}

// -- step 1: snapping, crossings, point ids

// Clip vertices with each one that coincides with a subject vertex replaced by it, so
// shared vertices are bitwise equal.
void snap(const ShapeView& s, const ShapeView& c, double eps, std::vector<double>& ox, std::vector<double>& oy) {
    ox.assign(c.x, c.x + c.n);
    oy.assign(c.y, c.y + c.n);
    // only a clip vertex within eps of the subject's box can snap (the same snaps)
    Box sb = shape_bbox(s.x, s.y, s.n);
    for (i64 j = 0; j < c.n; ++j) {
        double qx = c.x[j], qy = c.y[j];
        if (qx < sb.x0 - eps || qx > sb.x1 + eps || qy < sb.y0 - eps || qy > sb.y1 + eps) continue;
        bool exact = false;
        for (i64 i = 0; i < s.n; ++i)
            if (s.x[i] == qx && s.y[i] == qy) {
                exact = true;
                break;
            }
        if (exact) continue;
        for (i64 i = 0; i < s.n; ++i)
            if (std::fabs(s.x[i] - qx) <= eps && std::fabs(s.y[i] - qy) <= eps) {
                ox[j] = s.x[i];
                oy[j] = s.y[i];
                break;
            }
    }
}

// Every vertex of both shapes and every proper crossing of a subject edge with a clip
// edge (computed once, shared by both).
// edges: for each crossing the indices (into px) of its subject edge's ends, then its
// clip edge's.
void points(const ShapeView& s, const ShapeView& c, double eps, std::vector<double>& px, std::vector<double>& py,
            std::vector<i64>& near, std::vector<i64>& edges) {
    px.assign(s.x, s.x + s.n);
    py.assign(s.y, s.y + s.n);
    px.insert(px.end(), c.x, c.x + c.n);
    py.insert(py.end(), c.y, c.y + c.n);
    // only clip edges whose boxes meet the subject's (grown by eps) can cross it: the
    // same crossings, in the same order, without testing every pair of edges
    Box sb = shape_bbox(s.x, s.y, s.n);
    near.clear();
    edges.clear();
    for (i64 rc = 0; rc + 1 < c.nst; ++rc) {
        i64 ca = c.st[rc], cb = c.st[rc + 1];
        for (i64 u = ca; u < cb; ++u) {
            i64 z = next_in_ring(u, ca, cb);
            if (pmin(c.x[u], c.x[z]) > sb.x1 + eps || pmax(c.x[u], c.x[z]) < sb.x0 - eps) continue;
            if (pmin(c.y[u], c.y[z]) > sb.y1 + eps || pmax(c.y[u], c.y[z]) < sb.y0 - eps) continue;
            near.push_back(u);
            near.push_back(z);
        }
    }
    for (i64 r = 0; r + 1 < s.nst; ++r) {
        i64 a = s.st[r], b = s.st[r + 1];
        for (i64 v = a; v < b; ++v) {
            i64 w = next_in_ring(v, a, b);
            double p0x = s.x[v], p0y = s.y[v], p1x = s.x[w], p1y = s.y[w];
            double sx0 = pmin(p0x, p1x), sx1 = pmax(p0x, p1x), sy0 = pmin(p0y, p1y), sy1 = pmax(p0y, p1y);
            for (size_t e = 0; e < near.size(); e += 2) {
                i64 u = near[e], z = near[e + 1];
                double q0x = c.x[u], q0y = c.y[u], q1x = c.x[z], q1y = c.y[z];
                if (pmin(q0x, q1x) > sx1 + eps || pmax(q0x, q1x) < sx0 - eps) continue;
                if (pmin(q0y, q1y) > sy1 + eps || pmax(q0y, q1y) < sy0 - eps) continue;
                Crossing k = proper_crossing(p0x, p0y, p1x, p1y, q0x, q0y, q1x, q1y, eps);
                if (k.hit) {
                    px.push_back(k.x);
                    py.push_back(k.y);
                    edges.insert(edges.end(), {v, w, s.n + u, s.n + z});
                }
            }
        }
    }
}

// Distinct points sorted by (x, y) and the id of each input point. Points are taken in
// order of (x, y, input index): the order a stable sort by (x, y) gives.
void point_ids(const std::vector<double>& px, const std::vector<double>& py, std::vector<double>& ux,
               std::vector<double>& uy, std::vector<i64>& ids, std::vector<Keyed>& keyed) {
    i64 n = (i64)px.size();
    keyed.resize(n);
    for (i64 i = 0; i < n; ++i) keyed[i] = Keyed{px[i], py[i], i};
    std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
        return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.i < b.i)));
    });
    ux.clear();
    uy.clear();
    ids.resize(n);
    for (const Keyed& k : keyed) {
        if (ux.empty() || k.x != ux.back() || k.y != uy.back()) {
            ux.push_back(k.x);
            uy.push_back(k.y);
        }
        ids[k.i] = (i64)ux.size() - 1;
    }
}

// Each crossing whose two edges both pass within eps of one vertex (of either shape)
// moved onto that vertex (the one nearest the crossing); true when one moved, and the
// point ids are then stale. This happens where a hole's vertex lies on its own outline's
// edge and the other shape's edge passes through that point too. split inserts the vertex
// into both edges; the computed crossing, an ulp or so off it, would be inserted too, and
// between the two points the edges would share a tiny edge whose direction on each says
// nothing about which side is inside (classify then took a whole region to the wrong side).
bool snap_crossings(i64 nv, const std::vector<i64>& edges, std::vector<double>& px, std::vector<double>& py,
                    const std::vector<double>& ux, const std::vector<double>& uy, const std::vector<i64>& ids,
                    double eps, std::vector<char>& is_vertex) {
    is_vertex.assign(ux.size(), 0);
    for (i64 i = 0; i < nv; ++i) is_vertex[ids[i]] = 1;
    bool moved = false;
    for (i64 i = nv; i < (i64)px.size(); ++i) {
        if (is_vertex[ids[i]]) continue;  // already that vertex
        const i64* e = &edges[4 * (i - nv)];
        // a point on both edges is in both of their boxes (grown by eps)
        double x0 = pmax(pmin(px[e[0]], px[e[1]]), pmin(px[e[2]], px[e[3]])) - eps;
        double x1 = pmin(pmax(px[e[0]], px[e[1]]), pmax(px[e[2]], px[e[3]])) + eps;
        double y0 = pmax(pmin(py[e[0]], py[e[1]]), pmin(py[e[2]], py[e[3]])) - eps;
        double y1 = pmin(pmax(py[e[0]], py[e[1]]), pmax(py[e[2]], py[e[3]])) + eps;
        i64 best = -1;
        double best_d2 = 0.0;
        for (auto [j, hi] = positions_within(ux, x0, x1); j < hi; ++j) {
            if (!is_vertex[j] || uy[j] < y0 || uy[j] > y1) continue;
            if (on_segment(ux[j], uy[j], px[e[0]], py[e[0]], px[e[1]], py[e[1]], eps) < 0.0) continue;
            if (on_segment(ux[j], uy[j], px[e[2]], py[e[2]], px[e[3]], py[e[3]], eps) < 0.0) continue;
            double dx = ux[j] - px[i], dy = uy[j] - py[i], d2 = dx * dx + dy * dy;
            if (best < 0 || d2 < best_d2) best = j, best_d2 = d2;
        }
        if (best < 0) continue;
        px[i] = ux[best];
        py[i] = uy[best];
        moved = true;
    }
    return moved;
}

// -- steps 1 (cont.) and 3: the contours split at every point on them

// The contours (as point ids) with every point lying strictly inside an edge inserted
// into it, ordered along the edge; returns the number of points inserted.
i64 split(const i64* vid, const i64* labels, const i64* starts, i64 nst, const std::vector<double>& ux,
          const std::vector<double>& uy, double eps, IdShape& out, std::vector<double>& ts, std::vector<i64>& qs,
          const Box* other = nullptr) {
    i64 nu = (i64)ux.size();
    out.ids.clear();
    out.lab.clear();
    out.st.assign(nst, 0);
    i64 inserted = 0;
    for (i64 r = 0; r + 1 < nst; ++r) {
        i64 a = starts[r], b = starts[r + 1];
        out.st[r] = (i64)out.ids.size();
        i64 first = (i64)out.ids.size();
        for (i64 v = a; v < b; ++v) {
            i64 i0 = vid[v], i1 = vid[next_in_ring(v, a, b)];
            double p0x = ux[i0], p0y = uy[i0], p1x = ux[i1], p1y = uy[i1];
            double x0 = pmin(p0x, p1x), x1 = pmax(p0x, p1x), y0 = pmin(p0y, p1y), y1 = pmax(p0y, p1y);
            if (other && (x0 > other->x1 + eps || x1 < other->x0 - eps || y0 > other->y1 + eps || y1 < other->y0 - eps)) {
                // a clip edge away from the subject's box: no subject point or crossing is
                // on it, and classify drops it whole however it is cut: left as it is
                out.ids.push_back(i0);
                out.lab.push_back(labels[v]);
                continue;
            }
            auto [lo, hi] = positions_within(ux, x0 - eps, x1 + eps);
            ts.clear();
            qs.clear();
            for (i64 j = lo; j < std::min(hi, nu); ++j) {
                if (uy[j] < y0 - eps || uy[j] > y1 + eps || j == i0 || j == i1) continue;
                double t = on_segment(ux[j], uy[j], p0x, p0y, p1x, p1y, eps);
                if (t < 0.0) continue;
                // insertion by (t, id): ordered along the edge
                i64 z = (i64)ts.size();
                ts.push_back(t);
                qs.push_back(j);
                while (z > 0 && (ts[z - 1] > t || (ts[z - 1] == t && qs[z - 1] > j))) {
                    ts[z] = ts[z - 1];
                    qs[z] = qs[z - 1];
                    --z;
                }
                ts[z] = t;
                qs[z] = j;
            }
            i64 k = (i64)ts.size();
            inserted += k;
            out.ids.push_back(i0);
            out.lab.push_back(labels[v]);
            for (i64 z = 0; z < k; ++z) {
                if (qs[z] != out.ids.back()) {
                    out.ids.push_back(qs[z]);
                    out.lab.push_back(labels[v]);
                }
            }
        }
        // drop a closing duplicate (a split point equal to the first vertex)
        while ((i64)out.ids.size() - first > 1 && out.ids.back() == out.ids[first]) {
            out.ids.pop_back();
            out.lab.pop_back();
        }
    }
    out.st[nst - 1] = (i64)out.ids.size();
    return inserted;
}

// -- the edges classified

// Sorted keys from * nu + to of the contours' edges of positive length.
void edge_keys(const IdShape& s, i64 nu, std::vector<i64>& keys) {
    keys.clear();
    for (size_t r = 0; r + 1 < s.st.size(); ++r) {
        i64 a = s.st[r], b = s.st[r + 1];
        for (i64 v = a; v < b; ++v) {
            i64 w = s.ids[next_in_ring(v, a, b)];
            if (s.ids[v] != w) keys.push_back(s.ids[v] * nu + w);
        }
    }
    std::sort(keys.begin(), keys.end());
}

// winding() about contours given as point ids.
i64 winding_ids(double px, double py, const IdShape& s, const std::vector<double>& ux, const std::vector<double>& uy) {
    i64 w = 0;
    for (size_t r = 0; r + 1 < s.st.size(); ++r) {
        i64 a = s.st[r], b = s.st[r + 1];
        for (i64 i = a; i < b; ++i) {
            i64 j = i == a ? s.ids[b - 1] : s.ids[i - 1];
            w += winds(px, py, ux[j], uy[j], ux[s.ids[i]], uy[s.ids[i]]);
        }
    }
    return w;
}

// winding_ids() for many points about one shape: its edges registered in horizontal bands
// by their y range, so a point meets only the edges of its band. An edge adds to the
// winding number only where the point's y lies in its y range (see winds()), and the band
// of a y is monotone in y, so the edges left out add 0 and the sum is the same integer.
struct WindingIndex {
    const IdShape& s;
    const std::vector<double>& ux;
    const std::vector<double>& uy;
    i64 nb = 0;
    double lo = 0.0, scale = 0.0;
    std::vector<i64>& head;  // band b holds edges[head[b]:head[b + 1]]
    std::vector<i64>& edges;  // (vertex index i: the edge from its predecessor)

    WindingIndex(const IdShape& s_, const std::vector<double>& ux_, const std::vector<double>& uy_,
                 std::vector<i64>& head_, std::vector<i64>& edges_)
        : s(s_), ux(ux_), uy(uy_), head(head_), edges(edges_) {
        i64 n = (i64)s.ids.size();
        if (n < 64) return;  // few edges: every point tests them all
        double hi = uy[s.ids[0]];
        lo = hi;
        for (i64 v : s.ids) {
            lo = pmin(lo, uy[v]);
            hi = pmax(hi, uy[v]);
        }
        if (!(hi > lo)) return;
        nb = std::min<i64>(1024, (i64)std::sqrt((double)n) * 2);
        scale = (double)nb / (hi - lo);
        auto each_edge = [&](auto&& f) {
            for (size_t r = 0; r + 1 < s.st.size(); ++r) {
                i64 a = s.st[r], b = s.st[r + 1];
                for (i64 i = a; i < b; ++i) {
                    i64 j = i == a ? s.ids[b - 1] : s.ids[i - 1];
                    double y0 = uy[j], y1 = uy[s.ids[i]];
                    for (i64 k = band(pmin(y0, y1)); k <= band(pmax(y0, y1)); ++k) f(k, i);
                }
            }
        };
        // counted at k + 2 and filled through k + 1, which then holds band k + 1's start
        head.assign(nb + 2, 0);
        each_edge([&](i64 k, i64) { ++head[k + 2]; });
        for (i64 k = 0; k < nb; ++k) head[k + 2] += head[k + 1];
        edges.resize(head[nb + 1]);
        each_edge([&](i64 k, i64 i) { edges[head[k + 1]++] = i; });
    }
    i64 band(double y) const {
        double f = std::floor((y - lo) * scale);
        if (!(f > 0)) return 0;
        if (f >= (double)(nb - 1)) return nb - 1;
        return (i64)f;
    }
    // the contour start a of vertex i (for its predecessor)
    i64 winding(double px, double py) const {
        if (nb == 0) return winding_ids(px, py, s, ux, uy);
        i64 w = 0, k = band(py);
        for (i64 e = head[k]; e < head[k + 1]; ++e) {
            i64 i = edges[e];
            i64 r = (i64)(std::upper_bound(s.st.begin(), s.st.end(), i) - s.st.begin()) - 1;
            i64 a = s.st[r], b = s.st[r + 1];
            i64 j = i == a ? s.ids[b - 1] : s.ids[i - 1];
            w += winds(px, py, ux[j], uy[j], ux[s.ids[i]], uy[s.ids[i]]);
        }
        return w;
    }
};

// The directed edges of the inside and outside contours: subject edges by where they lie
// (shared edges by the side the clip shape's interior is on), clip edges inside the
// subject to both, walked backwards for the outside.
void classify(const IdShape& s, const IdShape& c, const std::vector<double>& ux, const std::vector<double>& uy,
              const Box& sb, Scratch& w, Edges& ins, Edges& outs) {
    i64 nu = (i64)ux.size();
    std::vector<i64>& s_keys = w.s_keys;
    std::vector<i64>& c_keys = w.c_keys;
    edge_keys(s, nu, s_keys);
    edge_keys(c, nu, c_keys);
    const WindingIndex s_index(s, ux, uy, w.band_head[0], w.band_edges[0]);
    const WindingIndex c_index(c, ux, uy, w.band_head[1], w.band_edges[1]);
    auto subject_edge = [&](i64 key) { return std::binary_search(s_keys.begin(), s_keys.end(), key); };
    auto clip_edge = [&](i64 key) { return std::binary_search(c_keys.begin(), c_keys.end(), key); };
    for (size_t r = 0; r + 1 < s.st.size(); ++r) {
        i64 ra = s.st[r], rb = s.st[r + 1];
        for (i64 v = ra; v < rb; ++v) {
            i64 a = s.ids[v], b = s.ids[next_in_ring(v, ra, rb)];
            if (a == b) continue;
            bool inside;
            if (clip_edge(a * nu + b)) inside = true;  // shared, same side
            else if (clip_edge(b * nu + a)) inside = false;  // shared, opposite sides
            else inside = c_index.winding(0.5 * (ux[a] + ux[b]), 0.5 * (uy[a] + uy[b])) > 0;
            (inside ? ins : outs).add(a, b, s.lab[v]);
        }
    }
    for (size_t r = 0; r + 1 < c.st.size(); ++r) {
        i64 ra = c.st[r], rb = c.st[r + 1];
        for (i64 v = ra; v < rb; ++v) {
            i64 a = c.ids[v], b = c.ids[next_in_ring(v, ra, rb)];
            if (a == b || subject_edge(a * nu + b) || subject_edge(b * nu + a)) continue;
            double mx = 0.5 * (ux[a] + ux[b]), my = 0.5 * (uy[a] + uy[b]);
            if (mx < sb.x0 || mx > sb.x1 || my < sb.y0 || my > sb.y1) continue;  // outside the subject's box: winding 0
            if (s_index.winding(mx, my) > 0) {
                ins.add(a, b, c.lab[v]);
                outs.add(b, a, c.lab[v]);  // walked backwards: it bounds the outside part
            }
        }
    }
}

bool shares_a_point(const std::vector<i64>& ids, i64 ns, i64 nc, i64 nu, std::vector<char>& mark) {
    mark.assign(nu, 0);
    for (i64 i = 0; i < ns; ++i) mark[ids[i]] = 1;
    for (i64 i = ns; i < ns + nc; ++i)
        if (mark[ids[i]]) return true;
    return false;
}

}  // namespace

ClipScratch::ClipScratch() : arrays(new Arrays) {}
ClipScratch::~ClipScratch() = default;

void grouped(const i64* keys, i64 m, i64 n, std::vector<i64>& starts, std::vector<i64>& order) {
    // counted at key + 2 and filled through key + 1, which then holds the next group's start
    starts.assign(n + 2, 0);
    for (i64 e = 0; e < m; ++e) starts[keys[e] + 2] += 1;
    for (i64 i = 0; i < n; ++i) starts[i + 2] += starts[i + 1];
    order.resize(m);
    for (i64 e = 0; e < m; ++e) order[starts[keys[e] + 1]++] = e;
    starts.pop_back();
}

bool clip_into(const ShapeView& s, const ShapeView& c, double eps, Shape& in, Shape& out, ClipScratch& scratch,
               bool subject_clean, bool want_inside, const char* clip_own, const Box* subject_box) {
    in.clear();
    out.clear();
    if (s.nst < 2 || s.n == 0) {
        in.st.push_back(0);
        out.st.push_back(0);
        return true;
    }
    Box sb = subject_box ? *subject_box : shape_bbox(s.x, s.y, s.n), cb = c.n > 0 ? shape_bbox(c.x, c.y, c.n) : Box{};
    if (c.nst < 2 || c.n == 0 || cb.x0 >= sb.x1 - eps || cb.x1 <= sb.x0 + eps || cb.y0 >= sb.y1 - eps ||
        cb.y1 <= sb.y0 + eps) {
        in.st.push_back(0);
        out.assign(s);
        return subject_clean;
    }
    Scratch& w = *scratch.arrays;
    if (subject_clean && clip_clean(s, c, eps, sb, w, in, out, want_inside, clip_own)) return true;
    snap(s, c, eps, w.cx, w.cy);
    ShapeView cs{w.cx.data(), w.cy.data(), c.lab, c.st, c.n, c.nst};
    points(s, cs, eps, w.px, w.py, w.near, w.crossing_edges);
    point_ids(w.px, w.py, w.ux, w.uy, w.ids, w.keyed);
    if (snap_crossings(s.n + c.n, w.crossing_edges, w.px, w.py, w.ux, w.uy, w.ids, eps, w.mark))
        point_ids(w.px, w.py, w.ux, w.uy, w.ids, w.keyed);
    i64 s_ins = split(w.ids.data(), s.lab, s.st, s.nst, w.ux, w.uy, eps, w.s2, w.ts, w.qs);
    i64 c_ins = split(w.ids.data() + s.n, c.lab, c.st, c.nst, w.ux, w.uy, eps, w.c2, w.ts, w.qs, &sb);
    if (s_ins == 0 && c_ins == 0 && !shares_a_point(w.ids, s.n, c.n, (i64)w.ux.size(), w.mark)) {
        holding_lists(s, w.cx.data(), w.cy.data(), c, in, out);
        return false;
    }
    w.ins.clear();
    w.outs.clear();
    classify(w.s2, w.c2, w.ux, w.uy, sb, w, w.ins, w.outs);
    if (want_inside) trace(w.ins, w.ux, w.uy, eps, w, in);
    else in.st.assign(1, 0);
    trace(w.outs, w.ux, w.uy, eps, w, out);
    return false;
}

std::pair<Shape, Shape> clip_arrays(const ShapeView& s, const ShapeView& c, double eps) {
    static thread_local ClipScratch scratch;
    std::pair<Shape, Shape> r;
    clip_into(s, c, eps, r.first, r.second, scratch);
    return r;
}

}  // namespace wa
