// The clipper's clean road: a subject and a clip whose boundaries meet only in proper
// crossings, each far from every vertex and every other edge (the common clip of the
// hidden-surface loop: a piece and the few edges of an outline near it). There the
// paper's stages (snapping, sorting every point, splitting edges at every point on them,
// classifying every edge by a winding number) come to this: the crossings, the edges
// split at them, and one winding number per run of edges between two crossings, along
// which the side cannot change. The directed edges are the general road's, in its order,
// and are traced by the same code, so the two roads give the same bits; a pair that is
// not clean takes the general road.
#include <algorithm>
#include <cmath>

#include "clip_stages.hpp"
#include "holding_lists.hpp"
#include "segments.hpp"

namespace wa {

namespace {

// How far apart (in units of eps) a clean pair's vertices, edges and crossings stay:
// beyond every tolerance of the general road (eps), and far enough that a winding number
// taken at the middle of an edge has a sign no rounding can flip.
constexpr double CLEAN_MARGIN = 4.0;

// Squared distance from q to the segment p0-p1.
double distance2(double qx, double qy, double p0x, double p0y, double p1x, double p1y) {
    double dx = p1x - p0x, dy = p1y - p0y, rx = qx - p0x, ry = qy - p0y;
    double ll = dx * dx + dy * dy;
    double t = ll > 0.0 ? (dx * rx + dy * ry) / ll : 0.0;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    double ex = rx - t * dx, ey = ry - t * dy;
    return ex * ex + ey * ey;
}

// The box of segment p0-p1 grown by g.
Box segment_box(double p0x, double p0y, double p1x, double p1y, double g) {
    return Box{pmin(p0x, p1x) - g, pmin(p0y, p1y) - g, pmax(p0x, p1x) + g, pmax(p0y, p1y) + g};
}

bool in_box(double x, double y, const Box& b) { return x >= b.x0 && x <= b.x1 && y >= b.y0 && y <= b.y1; }

// Whether point q is farther than tol from segment p0-p1 (box grown by tol given).
bool apart(double qx, double qy, const Box& grown, double p0x, double p0y, double p1x, double p1y, double tol) {
    return !in_box(qx, qy, grown) || distance2(qx, qy, p0x, p0y, p1x, p1y) > tol * tol;
}

// The box holding boxes a and b.
Box join(const Box& a, const Box& b) {
    return Box{pmin(a.x0, b.x0), pmin(a.y0, b.y0), pmax(a.x1, b.x1), pmax(a.y1, b.y1)};
}

// The union of the boxes (an empty box, meeting none, for no boxes).
Box union_of(const std::vector<Box>& boxes) {
    Box all{HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const Box& b : boxes) all = join(all, b);
    return all;
}

// What crossing edge q0-q1 at a proper crossing adds to the winding number about it of a
// point walking to e (the walk's end beyond the crossing): +1 onto its left (the sign is
// proper_crossing's own test of that end, which holds it more than eps from the line).
int turn(double q0x, double q0y, double q1x, double q1y, double ex, double ey) {
    return (q1x - q0x) * (ey - q0y) - (q1y - q0y) * (ex - q0x) > 0.0 ? 1 : -1;
}

constexpr size_t NEAR_GROUP = 4;  // near clip edges a group box holds (clean_crossings)

// Whether every clip vertex stays apart from every clip edge near the subject (its
// starts in w.near) that it does not end: the general road would insert such a vertex
// into the edge, or merge two equal vertices. Only the clip vertices inside the near
// edges' grown boxes together (`all`) can come near one (gathered into `close` first).
// A vertex and an edge that are both a self-clean outline's own (clip_own, may be null)
// are apart already: self_clean checked that pair with the same arithmetic.
bool clip_edges_clean(const ShapeView& c, const std::vector<i64>& near, const std::vector<Box>& boxes,
                      const Box& all, double tol, const char* clip_own, std::vector<i64>& close) {
    if (boxes.empty()) return true;
    bool foreign_edge = !clip_own;
    for (size_t e = 0; e < near.size() && !foreign_edge; e += 2) foreign_edge = !clip_own[near[e]];
    close.clear();
    for (i64 j = 0; j < c.n; ++j)
        if ((foreign_edge || !clip_own[j]) && in_box(c.x[j], c.y[j], all)) close.push_back(j);
    for (size_t e = 0; e < near.size(); e += 2) {
        i64 u = near[e], z = near[e + 1];
        const Box& g = boxes[e / 2];
        bool own_edge = clip_own && clip_own[u];
        for (i64 j : close) {
            if (own_edge && clip_own[j]) continue;
            if (j != u && j != z && !apart(c.x[j], c.y[j], g, c.x[u], c.y[u], c.x[z], c.y[z], tol)) return false;
        }
    }
    return true;
}

// The proper crossings (appended to w.px, w.py and w.crossings in the general road's
// order), or false where a subject vertex comes near a clip edge, a clip vertex near a
// subject edge, or a crossing lies where the general road would not split both edges
// at it. all: the union of the near clip edges' grown boxes (a subject edge whose box
// misses it meets none of them); the subject edges whose grown boxes meet it are
// appended to w.meeting (start and end vertex) and w.subject_boxes (the box).
bool clean_crossings(const ShapeView& s, const ShapeView& c, double eps, double tol, const Box& all,
                     ClipScratch::Arrays& w) {
    // the near edges in groups of NEAR_GROUP consecutive ones (mostly neighbours along the
    // outline, so their boxes together stay small), each group's boxes together: a
    // subject edge whose box misses a group's meets none of its edges
    const size_t m = w.near_boxes.size();
    w.group_boxes.clear();
    for (size_t g = 0; g < m; g += NEAR_GROUP) {
        Box u = w.near_boxes[g];
        for (size_t e = g + 1; e < g + NEAR_GROUP && e < m; ++e) u = join(u, w.near_boxes[e]);
        w.group_boxes.push_back(u);
    }
    for (i64 r = 0; r + 1 < s.nst; ++r) {
        i64 a = s.st[r], b = s.st[r + 1];
        for (i64 v = a; v < b; ++v) {
            i64 t = next_in_ring(v, a, b);
            double p0x = s.x[v], p0y = s.y[v], p1x = s.x[t], p1y = s.y[t];
            Box sg = segment_box(p0x, p0y, p1x, p1y, tol);
            if (!boxes_meet(sg, all)) continue;
            w.meeting.push_back(v);
            w.meeting.push_back(t);
            w.subject_boxes.push_back(sg);
            for (size_t e = 0; e < w.near.size(); e += 2) {
                if ((e / 2) % NEAR_GROUP == 0 && !boxes_meet(sg, w.group_boxes[(e / 2) / NEAR_GROUP])) {
                    e += 2 * (NEAR_GROUP - 1);  // the whole group (the loop adds the last 2)
                    continue;
                }
                const Box& cg = w.near_boxes[e / 2];
                if (!boxes_meet(sg, cg)) continue;
                i64 u = w.near[e], z = w.near[e + 1];
                double q0x = c.x[u], q0y = c.y[u], q1x = c.x[z], q1y = c.y[z];
                if (!apart(p0x, p0y, cg, q0x, q0y, q1x, q1y, tol)) return false;
                if (!apart(q0x, q0y, sg, p0x, p0y, p1x, p1y, tol)) return false;
                Crossing k = proper_crossing(p0x, p0y, p1x, p1y, q0x, q0y, q1x, q1y, eps);
                if (!k.hit) continue;
                double ts = on_segment(k.x, k.y, p0x, p0y, p1x, p1y, eps);
                double tc = on_segment(k.x, k.y, q0x, q0y, q1x, q1y, eps);
                if (ts < 0.0 || tc < 0.0) return false;
                w.crossings.push_back(CleanCrossing{v, u, ts, tc, (i64)w.px.size(),
                                                    turn(q0x, q0y, q1x, q1y, p1x, p1y),
                                                    turn(p0x, p0y, p1x, p1y, q1x, q1y)});
                w.px.push_back(k.x);
                w.py.push_back(k.y);
            }
        }
    }
    return true;
}

// Whether every crossing stays apart from every edge but its own two. A crossing lies on a
// near clip edge, inside its grown box, so inside `all` (clean_crossings): apart from
// every subject edge whose grown box misses `all`, so only those of w.meeting are tried.
bool crossings_apart(const ShapeView& s, const ShapeView& c, double tol, const ClipScratch::Arrays& w) {
    for (const CleanCrossing& k : w.crossings) {
        double x = w.px[k.id], y = w.py[k.id];
        for (size_t e = 0; e < w.meeting.size(); e += 2) {
            i64 v = w.meeting[e], t = w.meeting[e + 1];
            if (v == k.v) continue;
            if (!apart(x, y, w.subject_boxes[e / 2], s.x[v], s.y[v], s.x[t], s.y[t], tol)) return false;
        }
        for (size_t e = 0; e < w.near.size(); e += 2) {
            i64 u = w.near[e], z = w.near[e + 1];
            if (u == k.u) continue;
            if (!apart(x, y, w.near_boxes[e / 2], c.x[u], c.y[u], c.x[z], c.y[z], tol)) return false;
        }
    }
    return true;
}

// Crossing indices ordered by edge, then along it (order), or false when two crossings
// of one edge have the same parameter (the general road then orders them by point id).
template <class Edge, class Param>
bool along(const std::vector<CleanCrossing>& ks, std::vector<i64>& order, Edge edge, Param param) {
    order.resize(ks.size());
    for (size_t i = 0; i < ks.size(); ++i) order[i] = (i64)i;
    std::sort(order.begin(), order.end(), [&](i64 a, i64 b) {
        return edge(ks[a]) != edge(ks[b]) ? edge(ks[a]) < edge(ks[b]) : param(ks[a]) < param(ks[b]);
    });
    for (size_t i = 1; i < order.size(); ++i)
        if (edge(ks[order[i]]) == edge(ks[order[i - 1]]) && param(ks[order[i]]) == param(ks[order[i - 1]]))
            return false;
    return true;
}

// A shape's contours as point ids with the crossings on each edge inserted in order
// (what the general road's split gives a clean pair); base: the id of vertex 0.
void with_crossings(const ShapeView& s, i64 base, const std::vector<CleanCrossing>& ks,
                    const std::vector<i64>& order, bool subject, IdShape& out) {
    out.ids.resize(s.n + order.size());  // every vertex, and every crossing once
    out.lab.resize(s.n + order.size());
    out.st.assign(s.nst, 0);
    size_t k = 0;
    i64 n = 0;
    for (i64 r = 0; r + 1 < s.nst; ++r) {
        out.st[r] = n;
        for (i64 v = s.st[r]; v < s.st[r + 1]; ++v) {
            out.ids[n] = base + v;
            out.lab[n++] = s.lab[v];
            for (; k < order.size() && (subject ? ks[order[k]].v : ks[order[k]].u) == v; ++k) {
                out.ids[n] = ks[order[k]].id;
                out.lab[n++] = s.lab[v];
            }
        }
    }
    out.st[s.nst - 1] = n;
}

// The general road's classify for a clean pair: the side of an edge changes only at a
// crossing, where the winding number about the other shape moves by the crossing's turn
// (a clean crossing is proper, far from every other edge), so it is taken once per
// contour, at its first edge, and carried along. want_inside false: the inside part's
// edges are not gathered (it is not traced).
void classify_runs(const ShapeView& s, const ShapeView& c, const Box& sb, bool want_inside, ClipScratch::Arrays& w) {
    const std::vector<double>&px = w.px, &py = w.py;
    i64 first_crossing = s.n + c.n;
    for (size_t r = 0; r + 1 < w.s2.st.size(); ++r) {
        i64 ra = w.s2.st[r], rb = w.s2.st[r + 1];
        i64 wn = 0;
        for (i64 v = ra; v < rb; ++v) {
            i64 a = w.s2.ids[v], b = w.s2.ids[next_in_ring(v, ra, rb)];
            if (v == ra) wn = winding(0.5 * (px[a] + px[b]), 0.5 * (py[a] + py[b]), c.x, c.y, c.st, c.nst);
            else if (a >= first_crossing) wn += w.crossings[a - first_crossing].subject_turn;
            if (wn <= 0) w.outs.add(a, b, w.s2.lab[v]);
            else if (want_inside) w.ins.add(a, b, w.s2.lab[v]);
        }
    }
    for (size_t r = 0; r + 1 < w.c2.st.size(); ++r) {
        i64 ra = w.c2.st[r], rb = w.c2.st[r + 1];
        i64 wn = 0;
        for (i64 v = ra; v < rb; ++v) {
            i64 a = w.c2.ids[v], b = w.c2.ids[next_in_ring(v, ra, rb)];
            double mx = 0.5 * (px[a] + px[b]), my = 0.5 * (py[a] + py[b]);
            bool in_sb = !(mx < sb.x0 || mx > sb.x1 || my < sb.y0 || my > sb.y1);
            // a point outside the subject's box winds 0 about it
            if (v == ra) wn = in_sb ? winding(mx, my, s.x, s.y, s.st, s.nst) : 0;
            else if (a >= first_crossing) wn += w.crossings[a - first_crossing].clip_turn;
            if (wn > 0 && in_sb) {
                if (want_inside) w.ins.add(a, b, w.c2.lab[v]);
                w.outs.add(b, a, w.c2.lab[v]);  // walked backwards: it bounds the outside part
            }
        }
    }
}

}  // namespace

bool self_clean(const ShapeView& s, double eps, ClipScratch& scratch) {
    ClipScratch::Arrays& w = *scratch.arrays;
    double tol = CLEAN_MARGIN * eps;
    // each edge meets only the vertices whose x lies in its box: found in the vertices
    // ordered by x
    w.by_x.resize(s.n);
    for (i64 i = 0; i < s.n; ++i) w.by_x[i] = i;
    std::sort(w.by_x.begin(), w.by_x.end(), [&](i64 a, i64 b) { return s.x[a] < s.x[b]; });
    w.px.resize(s.n);
    for (i64 i = 0; i < s.n; ++i) w.px[i] = s.x[w.by_x[i]];
    for (i64 r = 0; r + 1 < s.nst; ++r) {
        i64 a = s.st[r], b = s.st[r + 1];
        for (i64 v = a; v < b; ++v) {
            i64 t = next_in_ring(v, a, b);
            Box g = segment_box(s.x[v], s.y[v], s.x[t], s.y[t], tol);
            auto k = std::lower_bound(w.px.begin(), w.px.end(), g.x0) - w.px.begin();
            for (; k < s.n && w.px[k] <= g.x1; ++k) {
                i64 j = w.by_x[k];
                if (j != v && j != t && !apart(s.x[j], s.y[j], g, s.x[v], s.y[v], s.x[t], s.y[t], tol)) return false;
            }
        }
    }
    return true;
}

bool clip_clean(const ShapeView& s, const ShapeView& c, double eps, const Box& sb, ClipScratch::Arrays& w,
                Shape& in, Shape& out, bool want_inside, const char* clip_own) {
    double tol = CLEAN_MARGIN * eps;
    Box g{sb.x0 - tol, sb.y0 - tol, sb.x1 + tol, sb.y1 + tol};
    w.near.clear();
    w.near_boxes.clear();
    for (i64 r = 0; r + 1 < c.nst; ++r) {
        i64 a = c.st[r], b = c.st[r + 1];
        for (i64 u = a; u < b; ++u) {
            i64 z = next_in_ring(u, a, b);
            if (!boxes_meet(segment_box(c.x[u], c.y[u], c.x[z], c.y[z], 0.0), g)) continue;
            w.near.push_back(u);
            w.near.push_back(z);
            w.near_boxes.push_back(segment_box(c.x[u], c.y[u], c.x[z], c.y[z], tol));
        }
    }
    Box all = union_of(w.near_boxes);
    if (!clip_edges_clean(c, w.near, w.near_boxes, all, tol, clip_own, w.close)) return false;
    w.px.assign(s.x, s.x + s.n);
    w.py.assign(s.y, s.y + s.n);
    w.px.insert(w.px.end(), c.x, c.x + c.n);
    w.py.insert(w.py.end(), c.y, c.y + c.n);
    w.crossings.clear();
    w.meeting.clear();
    w.subject_boxes.clear();
    if (!clean_crossings(s, c, eps, tol, all, w) || !crossings_apart(s, c, tol, w)) return false;
    if (w.crossings.empty()) {  // boundaries apart: the paper's step 2
        holding_lists(s, c.x, c.y, c, in, out);
        return true;
    }
    if (!along(w.crossings, w.by_subject, [](const CleanCrossing& k) { return k.v; },
               [](const CleanCrossing& k) { return k.ts; }) ||
        !along(w.crossings, w.by_clip, [](const CleanCrossing& k) { return k.u; },
               [](const CleanCrossing& k) { return k.tc; }))
        return false;
    with_crossings(s, 0, w.crossings, w.by_subject, true, w.s2);
    with_crossings(c, s.n, w.crossings, w.by_clip, false, w.c2);
    w.ins.clear();
    w.outs.clear();
    classify_runs(s, c, sb, want_inside, w);
    if (want_inside) trace(w.ins, w.px, w.py, eps, w, in);
    else in.st.assign(1, 0);
    trace(w.outs, w.px, w.py, eps, w, out);
    return true;
}

}  // namespace wa
