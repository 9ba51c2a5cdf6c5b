// Shapes as the Weiler-Atherton kernels take them, and the small geometry they share.
//
// A shape is four arrays: xs, ys (the vertices, contour after contour), labels (labels[v]
// labels the edge from vertex v to the next one of its contour) and starts (contour i is
// vertices starts[i]..starts[i + 1] - 1). Main contours have positive shoelace area,
// holes negative. Every function here runs its floating-point operations in a fixed order
// (no reassociation, no FMA: the family is built with -ffp-contract=off), so the results
// have the same bits on every machine.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "common/geometry.hpp"

namespace wa {

using i64 = std::int64_t;

// A read-only view of a shape's arrays (n vertices, nst = contours + 1 starts).
struct ShapeView {
    const double* x = nullptr;
    const double* y = nullptr;
    const i64* lab = nullptr;
    const i64* st = nullptr;
    i64 n = 0;
    i64 nst = 0;
};

// A shape that owns its arrays.
struct Shape {
    std::vector<double> x, y;
    std::vector<i64> lab, st;
    ShapeView view() const {
        return ShapeView{x.data(), y.data(), lab.data(), st.data(), (i64)x.size(), (i64)st.size()};
    }
    static Shape empty() {
        Shape s;
        s.st.push_back(0);
        return s;
    }
    static Shape of(const ShapeView& v) {
        Shape s;
        s.assign(v);
        return s;
    }
    void assign(const ShapeView& v) {
        x.assign(v.x, v.x + v.n);
        y.assign(v.y, v.y + v.n);
        lab.assign(v.lab, v.lab + v.n);
        st.assign(v.st, v.st + v.nst);
    }
    void clear() {
        x.clear();
        y.clear();
        lab.clear();
        st.clear();
    }
};

// Python's min(a, b) and max(a, b): the first argument unless the second
// compares strictly smaller (larger); common/geometry.hpp's.
inline double pmin(double a, double b) { return aaeval::geometry::pymin(a, b); }
inline double pmax(double a, double b) { return aaeval::geometry::pymax(a, b); }

// Python's float a % b (the remainder takes the divisor's sign).
inline double pmod(double vx, double wx) {
    double mod = std::fmod(vx, wx);
    if (mod != 0.0) {
        if ((wx < 0) != (mod < 0)) mod += wx;
    } else {
        mod = std::copysign(0.0, wx);
    }
    return mod;
}

// int(x) of a float64 as x86-64's cvttsd2si computes it: truncation, and
// INT64_MIN for NaN or anything out of range (instead of C++'s undefined behaviour).
inline i64 to_int(double x) {
    if (!(x >= -9223372036854775808.0 && x < 9223372036854775808.0)) return INT64_MIN;
    return (i64)x;
}

// Shoelace area of the contour made of vertices a..b-1 (positive: main contour): the fan
// from the first vertex of common/geometry.hpp, summed in its order.
inline double ring_area_of(const double* xs, const double* ys, i64 a, i64 b) {
    if (b - a < 3) return 0.0;  // (no vertex read: a may be the end of the arrays)
    return aaeval::geometry::signed_area(xs, ys, a, b - a);
}

// What edge (x0, y0)-(x1, y1) adds to the winding number of the point: +1 crossing its
// horizontal line upwards with the point on the left, -1 downwards on the right.
inline int winds(double px, double py, double x0, double y0, double x1, double y1) {
    if (y0 <= py) {
        if (y1 > py && (x1 - x0) * (py - y0) - (px - x0) * (y1 - y0) > 0) return 1;
    } else if (y1 <= py && (x1 - x0) * (py - y0) - (px - x0) * (y1 - y0) < 0) {
        return -1;
    }
    return 0;
}

// Winding number of the point about the oriented contours (1 inside a shape).
inline i64 winding(double px, double py, const double* xs, const double* ys, const i64* starts, i64 nst) {
    i64 w = 0;
    for (i64 r = 0; r + 1 < nst; ++r) {
        i64 a = starts[r], b = starts[r + 1];
        for (i64 i = a; i < b; ++i) {
            i64 j = i == a ? b - 1 : i - 1;
            w += winds(px, py, xs[j], ys[j], xs[i], ys[i]);
        }
    }
    return w;
}

struct Box {
    double x0, y0, x1, y1;
};

// Whether two closed boxes share a point.
inline bool boxes_meet(const Box& a, const Box& b) { return !(a.x0 > b.x1 || a.x1 < b.x0 || a.y0 > b.y1 || a.y1 < b.y0); }

// numpy's xs.min(), ys.min(), xs.max(), ys.max() (each the first extreme; n > 0), in one
// pass: each bound sees the same values in the same order as a pass of its own.
inline Box shape_bbox(const double* xs, const double* ys, i64 n) {
    Box b{xs[0], ys[0], xs[0], ys[0]};
    for (i64 i = 1; i < n; ++i) {
        if (xs[i] < b.x0) b.x0 = xs[i];
        if (ys[i] < b.y0) b.y0 = ys[i];
        if (xs[i] > b.x1) b.x1 = xs[i];
        if (ys[i] > b.y1) b.y1 = ys[i];
    }
    return b;
}

// The vertex after v in the contour of vertices a..b-1.
inline i64 next_in_ring(i64 v, i64 a, i64 b) { return v + 1 == b ? a : v + 1; }

}  // namespace wa
