// The clipper's working arrays and the stages shared by its two roads: the paper's
// general one (clipper.cpp) and the clean road (clean_clip.cpp).
#pragma once

#include <cmath>
#include <vector>

#include "clipper.hpp"

namespace wa {

struct IdShape {
    std::vector<i64> ids, lab, st;
};

struct Edges {
    std::vector<i64> from, to, lab;
    void clear() {
        from.clear();
        to.clear();
        lab.clear();
    }
    void add(i64 a, i64 b, i64 l) {
        from.push_back(a);
        to.push_back(b);
        lab.push_back(l);
    }
};

// A point with its input index (lex_order's sort key).
struct Keyed {
    double x, y;
    i64 i;
};

// A crossing of the clean road: its subject edge (start vertex v), its clip edge (start
// vertex u), its parameters along both (on_segment's), its point's index, and what
// crossing there adds to the winding number about the other shape of a point walking
// along the subject (subject_turn) and along the clip (clip_turn): +1 or -1.
struct CleanCrossing {
    i64 v, u;
    double ts, tc;
    i64 id;
    int subject_turn, clip_turn;
};

// Every working array of one clip, kept between calls so that a clip allocates nothing
// once the arrays have grown to its size: the hidden-surface loop makes tens of
// thousands of small clips, and allocating a few dozen arrays each took a third of
// their time.
struct ClipScratch::Arrays {
    std::vector<double> cx, cy, px, py, ux, uy, ts;
    std::vector<i64> ids, near, crossing_edges, qs, s_keys, c_keys, head, out_edges, fill;
    std::vector<i64> band_head[2], band_edges[2];
    std::vector<Keyed> keyed;
    std::vector<char> used, mark;
    IdShape s2, c2;
    Edges ins, outs;
    std::vector<CleanCrossing> crossings;
    std::vector<i64> by_subject, by_clip;  // crossing indices ordered along each shape
    // edge boxes grown by the clean margin: of the subject edges in `meeting`, of the near clip edges
    std::vector<Box> subject_boxes, near_boxes;
    std::vector<Box> group_boxes;  // near_boxes together, a few at a time (clean_crossings)
    std::vector<i64> meeting;  // subject edges (start, end) near the near clip edges (clean_crossings)
    std::vector<i64> by_x;  // vertex indices ordered by x (self_clean)
    std::vector<i64> close;  // clip vertices near the subject (clip_edges_clean)
    std::vector<i64> exit;  // per point, the one edge that starts there (trace)
};

// Parameter t in (0, 1) of q on segment p0-p1 when q lies on it strictly between the
// ends (distance <= eps from the line, > eps from both ends); else -1.
inline double on_segment(double qx, double qy, double p0x, double p0y, double p1x, double p1y, double eps) {
    double dx = p1x - p0x, dy = p1y - p0y;
    double ll = dx * dx + dy * dy;
    if (ll == 0.0) return -1.0;
    double rx = qx - p0x, ry = qy - p0y;
    double cr = dx * ry - dy * rx;
    if (cr * cr > eps * eps * ll) return -1.0;
    double t = (dx * rx + dy * ry) / ll;
    double tol = eps / std::sqrt(ll);
    if (t <= tol || t >= 1.0 - tol) return -1.0;
    return t;
}

// Link directed edges (point indices into ux, uy) into closed contours (clipper.cpp).
void trace(const Edges& edges, const std::vector<double>& ux, const std::vector<double>& uy, double eps,
           ClipScratch::Arrays& w, Shape& out);

// The clip of a clean pair (clean_clip.cpp): false, with nothing written, when the pair
// is not clean. sb: the subject's box; want_inside false: the inside part is not traced;
// clip_own: as clip_into takes it.
bool clip_clean(const ShapeView& s, const ShapeView& c, double eps, const Box& sb, ClipScratch::Arrays& w,
                Shape& in, Shape& out, bool want_inside, const char* clip_own);

}  // namespace wa
