#include "local_outline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "solver.hpp"

namespace wa {

namespace {

// -- the outline as a piece's box sees it


// The side of box b by which the ray from its centre to a point outside it leaves (0
// right, 1 top, 2 left, 3 bottom: counter-clockwise in x-y), from the point's offset
// from the centre and the box's half sides.
int rim_side(double dx, double dy, double hw, double hh) {
    if (std::fabs(dy) * hw <= std::fabs(dx) * hh) return dx > 0 ? 0 : 2;
    return dy > 0 ? 1 : 3;
}

// Box b's corner between rim sides k and k + 1 (mod 4).
void rim_corner(const Box& b, int k, double& x, double& y) {
    x = (k == 0 || k == 3) ? b.x1 : b.x0;
    y = (k == 0 || k == 1) ? b.y1 : b.y0;
}

// The number of edges in the chunk that starts at vertex v of ring [a, e) when its box
// misses b (no edge of it near b), else 0. c0: the ring's first chunk.
i64 far_chunk(const Outline& o, i64 c0, i64 a, i64 e, i64 v, const Box& b) {
    if (o.chunk.empty() || (v - a) % CHUNK != 0) return 0;
    const Box& c = o.chunk[c0 + (v - a) / CHUNK];
    if (boxes_meet(c, b)) return 0;
    return std::min(CHUNK, e - v);
}

// Ring r of outline o as box b sees it, appended to `local` (one contour): its edges
// that come near b (their boxes meet it) as they are, each run of edges away from b
// replaced by a walk around b's rim (its corners) that turns about b as often and the same
// way as the run does. Run and walk join the same two vertices and neither enters b, so
// every point of b has the same winding number about both rings, while the edges near b,
// the only ones whose crossings and shared points the clipper computes for a shape inside
// b, are the ring's own: the clip of a shape inside b (away from b's rim by far more than
// the clipper's tolerance) by `local` is its clip by o, with a fraction of o's vertices.
// The turns are counted by the rim side each vertex faces: a straight edge that misses
// b sweeps less than half a turn about b's centre, so it passes to a neighbouring side
// the short way and to the opposite side the way its cross product says. A chunk of
// edges whose box misses b is counted as its chord (the straight edge from its first
// vertex to its last): inside a box that misses b, the edges sweep the same angle about
// b's centre as the chord, so they cross the rim sides' borders as often, the same way.
// Returns false when no edge of the ring comes near b (nothing appended).
bool local_ring(const Outline& o, i64 r, const Box& b, Outline& local) {
    i64 a = o.st[r], e = o.st[r + 1], m = e - a, c0 = o.chunk.empty() ? 0 : o.chunk_first[r];
    auto near = [&](i64 i) {
        i64 j = i + 1 < e ? i + 1 : a;
        return !(pmin(o.x[i], o.x[j]) > b.x1 || pmax(o.x[i], o.x[j]) < b.x0 || pmin(o.y[i], o.y[j]) > b.y1 ||
                 pmax(o.y[i], o.y[j]) < b.y0);
    };
    i64 first = a;
    while (first < e) {
        i64 skip = far_chunk(o, c0, a, e, first, b);
        if (skip == 0 && near(first)) break;
        first += skip > 0 ? skip : 1;
    }
    if (first == e) return false;
    double qx = 0.5 * (b.x0 + b.x1), qy = 0.5 * (b.y0 + b.y1), hw = 0.5 * (b.x1 - b.x0), hh = 0.5 * (b.y1 - b.y0);
    auto side = [&](i64 v) { return rim_side(o.x[v] - qx, o.y[v] - qy, hw, hh); };
    for (i64 k = 0; k < m;) {
        i64 i = first + k < e ? first + k : first + k - m;
        local.x.push_back(o.x[i]);
        local.y.push_back(o.y[i]);
        ++k;
        bool edge_near = near(i);
        local.own.push_back(edge_near);
        if (edge_near) continue;
        // a run of edges away from b, from vertex i to the next vertex whose edge is near:
        // edge by edge, or a chunk at a time (its inner vertices' edges are far, so the
        // run cannot end inside it; nor can it reach `first`, whose edge is near)
        int s0 = side(i), s = s0, turns = 0;
        i64 v = i;
        while (true) {
            i64 skip = far_chunk(o, c0, a, e, v, b);
            i64 u = skip > 0 ? (v + skip < e ? v + skip : a) : (v + 1 < e ? v + 1 : a);
            int su = side(u), d = (su - s + 4) % 4;
            if (d == 2)
                d = (o.x[v] - qx) * (o.y[u] - qy) - (o.y[v] - qy) * (o.x[u] - qx) > 0 ? 2 : -2;
            else if (d == 3)
                d = -1;
            turns += d;
            s = su;
            v = u;
            if (skip > 1) k += skip - 1;
            if (k == m || near(v)) break;
            ++k;
        }
        for (int t = 0; t < std::abs(turns); ++t) {
            double x, y;
            rim_corner(b, ((turns > 0 ? s0 + t : s0 - 1 - t) % 4 + 4) % 4, x, y);
            local.x.push_back(x);
            local.y.push_back(y);
            local.own.push_back(0);
        }
    }
    return true;
}

}  // namespace

void index_chunks(Outline& o) {
    o.chunk.clear();
    o.chunk_first.clear();
    for (size_t r = 0; r + 1 < o.st.size(); ++r) {
        i64 a = o.st[r], e = o.st[r + 1];
        o.chunk_first.push_back((i64)o.chunk.size());
        for (i64 v = a; v < e; v += CHUNK) {
            i64 last = v + CHUNK < e ? v + CHUNK : a;  // the chunk's last vertex (the ring's first at its end)
            Box c{o.x[last], o.y[last], o.x[last], o.y[last]};
            for (i64 i = v; i < v + CHUNK && i < e; ++i)
                c = Box{pmin(c.x0, o.x[i]), pmin(c.y0, o.y[i]), pmax(c.x1, o.x[i]), pmax(c.y1, o.y[i])};
            o.chunk.push_back(c);
        }
    }
}

// Outline o as box b sees it, into `local`: each ring with an edge near b as local_ring
// gives it; the rings with none keep the same winding number over all of b, and stand
// together as b's rim walked once that way round (or not at all when they add to
// nothing), so that every point of b keeps its winding number about the outline.
// Returns false when no edge comes near b (local then holds nothing of use).
bool local_outline(const Outline& o, const Box& b, Outline& local) {
    local.x.clear();
    local.y.clear();
    local.own.clear();
    local.clean = o.clean;
    local.st.assign(1, 0);
    bool near = false;
    i64 far_winding = 0;
    for (size_t r = 0; r + 1 < o.st.size(); ++r) {
        if (local_ring(o, (i64)r, b, local)) {
            near = true;
            local.st.push_back((i64)local.x.size());
        } else if (o.st.size() > 2) {  // a single ring away from b: no outline near b at all
            double qx = 0.5 * (b.x0 + b.x1), qy = 0.5 * (b.y0 + b.y1);
            far_winding += ring_winding(qx, qy, o, (i64)r);
        }
    }
    if (!near) return false;
    if (far_winding != 0) {
        const int ccw[4] = {2, 3, 0, 1}, cw[4] = {2, 1, 0, 3};
        for (int k : far_winding > 0 ? ccw : cw) {
            double x, y;
            rim_corner(b, k, x, y);
            local.x.push_back(x);
            local.y.push_back(y);
            local.own.push_back(0);
        }
        local.st.push_back((i64)local.x.size());
    }
    local.lab.assign(local.x.size(), EDGE_CUT);
    return true;
}

// Whether contour r of shape s lies inside outline o, by the winding number of the middle
// of its first edge (for a contour whose boundary and o's are apart).
bool contour_inside(const ShapeView& s, i64 r, const Outline& o) {
    i64 a = s.st[r], b = s.st[r + 1], c = a + 1 < b ? a + 1 : a;
    return outline_winding(0.5 * (s.x[a] + s.x[c]), 0.5 * (s.y[a] + s.y[c]), o) > 0;
}

// winding(px, py) about ring r of outline o, its chunks (when it has them) passed whole where
// their box lies above py or at or below it: none of their edges spans py, so none adds
// to the sum (winds), which is an integer, the same in any order.
i64 ring_winding(double px, double py, const Outline& o, i64 r) {
    if (o.chunk.empty()) return winding(px, py, o.x.data(), o.y.data(), o.st.data() + r, 2);
    i64 a = o.st[r], e = o.st[r + 1], w = 0;
    for (i64 v = a, k = o.chunk_first[r]; v < e; v += CHUNK, ++k) {
        if (o.chunk[k].y0 > py || o.chunk[k].y1 <= py) continue;
        for (i64 i = v; i < v + CHUNK && i < e; ++i) {
            i64 j = i + 1 < e ? i + 1 : a;
            w += winds(px, py, o.x[i], o.y[i], o.x[j], o.y[j]);
        }
    }
    return w;
}

i64 outline_winding(double px, double py, const Outline& o) {
    i64 w = 0;
    for (size_t r = 0; r + 1 < o.st.size(); ++r) w += ring_winding(px, py, o, (i64)r);
    return w;
}

}  // namespace wa
