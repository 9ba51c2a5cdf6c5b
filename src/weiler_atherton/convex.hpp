// Convex pieces cut by lines: the hidden-surface loop's short road.
//
// Where a piece and the outline clipping it are both one convex contour (every piece of a
// scene of triangles), the clip comes down to cutting by the outline's edge lines one
// after another: what lies beyond an edge's line is a convex piece of the outside, what
// lies within goes on to the next edge, and what is left after the last edge is the
// inside. The outside is then up to one convex piece per outline edge instead of the
// paper's single polygon (perhaps with a hole): the same region, cut into convex parts.
// A piece split along the line where its plane crosses another polygon's is cut the same
// way by that one line. The paper's clipper (clipper.hpp) handles every other pair.
#pragma once

#include <cmath>
#include <utility>

#include "shape.hpp"

namespace wa {

inline int side_of(double d, double tol) {
    if (d > tol) return 1;
    if (d < -tol) return -1;
    return 0;
}

// (has a vertex below -tol, has a vertex above tol) among d[:n].
inline std::pair<bool, bool> vertex_sides(const double* d, i64 n, double tol) {
    bool below = false, above = false;
    for (i64 k = 0; k < n; ++k) {
        if (d[k] < -tol) below = true;
        else if (d[k] > tol) above = true;
    }
    return {below, above};
}

// d[k] for the first n vertices: minus the cross product of the edge a->b with the
// vertex's offset from a (negative left of the edge, inside a positive contour); returns
// the tolerance scale that goes with it (eps in distance).
inline double edge_line_values(const double* xs, const double* ys, i64 n, double ax, double ay, double bx,
                               double by, double* d) {
    double ex = bx - ax, ey = by - ay;
    for (i64 k = 0; k < n; ++k) d[k] = ey * (xs[k] - ax) - ex * (ys[k] - ay);
    return std::hypot(ex, ey);
}

// d[k] = a x + b y + c for the first n vertices; returns |(a, b)|.
inline double plane_line_values(const double* xs, const double* ys, i64 n, double a, double b, double c,
                                double* d) {
    for (i64 k = 0; k < n; ++k) d[k] = a * xs[k] + b * ys[k] + c;
    return std::hypot(a, b);
}

// Where the edge between two vertices on opposite sides meets the line (d = 0), computed
// from the lexicographically first end, so that an edge walked either way (by the pieces
// on both sides of it) gives the same bits.
inline void line_crossing(double x0, double y0, double d0, double x1, double y1, double d1, double& x, double& y) {
    if (x1 < x0 || (x1 == x0 && y1 < y0)) {
        std::swap(x0, x1);
        std::swap(y0, y1);
        std::swap(d0, d1);
    }
    double t = d0 / (d0 - d1);
    x = x0 + t * (x1 - x0);
    y = y0 + t * (y1 - y0);
}

// Split a convex contour (its first n vertices, positive area) by a line, given the
// line's value d[k] at every vertex: the part where d <= 0 goes to (lx, ly, ll), the part
// where d >= 0 to (rx, ry, rl); returns their vertex counts (each at most 2 n: the output
// rows must hold that many). Vertices with |d| <= tol lie on the line and belong to both
// parts; an edge from one side to the other is cut at one point shared by both.
// labels[k] labels the edge leaving vertex k; a part's new edge along the line gets
// line_label. Call it only where vertices lie strictly on both sides.
inline std::pair<i64, i64> split_convex(const double* xs, const double* ys, const i64* labels, i64 n,
                                        const double* d, double tol, i64 line_label, double* lx, double* ly,
                                        i64* ll, double* rx, double* ry, i64* rl) {
    i64 nl = 0, nr = 0;
    for (i64 k = 0; k < n; ++k) {
        i64 j = k + 1 < n ? k + 1 : 0;
        int sk = side_of(d[k], tol), sj = side_of(d[j], tol);
        if (sk <= 0) {
            lx[nl] = xs[k];
            ly[nl] = ys[k];
            ll[nl] = (sk == 0 && sj > 0) ? line_label : labels[k];
            ++nl;
        }
        if (sk >= 0) {
            rx[nr] = xs[k];
            ry[nr] = ys[k];
            rl[nr] = (sk == 0 && sj < 0) ? line_label : labels[k];
            ++nr;
        }
        if (sk * sj < 0) {
            double x, y;
            line_crossing(xs[k], ys[k], d[k], xs[j], ys[j], d[j], x, y);
            lx[nl] = x;
            ly[nl] = y;
            ll[nl] = sk < 0 ? line_label : labels[k];
            ++nl;
            rx[nr] = x;
            ry[nr] = y;
            rl[nr] = sk > 0 ? line_label : labels[k];
            ++nr;
        }
    }
    return {nl, nr};
}

}  // namespace wa
