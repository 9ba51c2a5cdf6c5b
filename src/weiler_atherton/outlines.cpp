// The solver's free helpers (solver.hpp): the separation test of convex pairs, the
// half-plane of a crossing line, the pairs of overlapping boxes, and the outlines as the
// solver takes them. Kept apart from the hidden-surface loop (solver.cpp) for size.
#include <algorithm>
#include <cmath>

#include "clipper.hpp"
#include "solver.hpp"

namespace wa {

namespace {

Box box_of(const double* obb, i64 s) { return Box{obb[4 * s], obb[4 * s + 1], obb[4 * s + 2], obb[4 * s + 3]}; }

// Whether every vertex in box b lies farther than 2 eps inside every edge's line of the
// convex contour, as separation computes it, for certain from b's corners alone: the
// computed side value is within 3 roundings of the exact one (affine in the point, so
// smallest at a corner), both at a corner and at a vertex, so corners 16 roundings of the
// largest term beyond the margin leave every vertex beyond it. A box that passes saves
// separation's test of every vertex against every edge (a piece inside a round outline).
bool box_well_inside(const Box& b, const double* cx, const double* cy, i64 nc, double eps, const double* len) {
    constexpr double unit = 0x1p-53;  // float64's unit roundoff
    for (i64 i = 0; i < nc; ++i) {
        i64 j = i + 1 < nc ? i + 1 : 0;
        double ex = cx[j] - cx[i], ey = cy[j] - cy[i];
        double margin = 2.0 * eps * (len ? len[i] : std::hypot(ex, ey));
        double ax = pmax(std::fabs(b.x0 - cx[i]), std::fabs(b.x1 - cx[i]));
        double ay = pmax(std::fabs(b.y0 - cy[i]), std::fabs(b.y1 - cy[i]));
        double need = margin + 16.0 * unit * (std::fabs(ex) * ay + std::fabs(ey) * ax);
        const double xs[4] = {b.x0, b.x1, b.x1, b.x0}, ys[4] = {b.y0, b.y0, b.y1, b.y1};
        for (int k = 0; k < 4; ++k)
            if (!(ex * (ys[k] - cy[i]) - ey * (xs[k] - cx[i]) > need)) return false;
    }
    return true;
}

}  // namespace

int separation(const double* sx, const double* sy, i64 ns, const double* cx, const double* cy, i64 nc, double eps,
               const double* len, const Box* sbox) {
    if (sbox && box_well_inside(*sbox, cx, cy, nc, eps, len)) return INSIDE;
    bool inside = true;
    for (i64 i = 0; i < nc; ++i) {
        i64 j = i + 1 < nc ? i + 1 : 0;
        double ex = cx[j] - cx[i], ey = cy[j] - cy[i];
        double margin = 2.0 * eps * (len ? len[i] : std::hypot(ex, ey));
        bool beyond = true;
        for (i64 v = 0; v < ns; ++v) {
            double d = ex * (sy[v] - cy[i]) - ey * (sx[v] - cx[i]);  // > 0: left, the inner side
            if (d >= -margin) beyond = false;
            if (d <= margin) inside = false;
            if (!beyond && !inside) break;
        }
        if (beyond) return OUTSIDE;
    }
    return inside ? INSIDE : 0;
}

Shape half_plane(double a, double b, double c, const Box& bbox) {
    double x0 = bbox.x0 - 1, y0 = bbox.y0 - 1, x1 = bbox.x1 + 1, y1 = bbox.y1 + 1;
    const double bx[4] = {x0, x1, x1, x0}, by[4] = {y0, y0, y1, y1};  // positive shoelace area already
    double xs[8], ys[8];
    bool on_line[8] = {false};
    int n = 0;
    for (int k = 0; k < 4; ++k) {
        int j = (k + 1) % 4;
        double dp = a * bx[k] + b * by[k] + c;
        double dq = a * bx[j] + b * by[j] + c;
        if (dp <= 0) {
            xs[n] = bx[k];
            ys[n] = by[k];
            on_line[n] = dp == 0;
            ++n;
        }
        if ((dp < 0 && 0 < dq) || (dq < 0 && 0 < dp)) {
            double t = dp / (dp - dq);
            xs[n] = bx[k] + t * (bx[j] - bx[k]);
            ys[n] = by[k] + t * (by[j] - by[k]);
            on_line[n] = true;
            ++n;
        }
    }
    Shape s;
    s.x.assign(xs, xs + n);
    s.y.assign(ys, ys + n);
    for (int k = 0; k < n; ++k) s.lab.push_back(on_line[k] && on_line[(k + 1) % n] ? EDGE_CROSSING : EDGE_CUT);
    s.st = {0, n};
    return s;
}

void later_neighbours(const double* obb, const i64* order, i64 n, std::vector<i64>& starts, std::vector<i64>& rows) {
    std::vector<Box> bx(n);
    for (i64 i = 0; i < n; ++i) bx[i] = box_of(obb, order[i]);
    std::vector<i64> by_x(n);
    for (i64 i = 0; i < n; ++i) by_x[i] = i;
    std::stable_sort(by_x.begin(), by_x.end(), [&](i64 a, i64 b) { return bx[a].x0 < bx[b].x0; });
    std::vector<i64> lo, hi;
    for (i64 i = 0; i < n; ++i) {
        i64 p = by_x[i];
        for (i64 j = i + 1; j < n; ++j) {
            i64 q = by_x[j];
            if (bx[q].x0 >= bx[p].x1) break;
            if (bx[q].y0 >= bx[p].y1 || bx[q].y1 <= bx[p].y0 || bx[q].x1 <= bx[p].x0) continue;
            lo.push_back(std::min(p, q));
            hi.push_back(std::max(p, q));
        }
    }
    std::vector<i64> by_lo;
    grouped(lo.data(), (i64)lo.size(), n, starts, by_lo);
    rows.resize(by_lo.size());
    for (size_t k = 0; k < by_lo.size(); ++k) rows[k] = hi[by_lo[k]];
    for (i64 p = 0; p < n; ++p) std::sort(rows.begin() + starts[p], rows.begin() + starts[p + 1]);
}

Originals originals(const double* vertices, const i64* start, const i64* length, i64 n, const double* planes) {
    Originals o;
    o.starts.assign(n + 1, 0);
    o.boxes.assign(4 * n, 0.0);
    o.zmin.assign(n, 0.0);
    auto vx = [&](i64 i) { return vertices[3 * i]; };
    auto vy = [&](i64 i) { return vertices[3 * i + 1]; };
    auto vz = [&](i64 i) { return vertices[3 * i + 2]; };
    for (i64 p = 0; p < n; ++p) {
        i64 a = start[p], b = a + length[p];
        double zm = vz(a);
        for (i64 i = a + 1; i < b; ++i)
            if (vz(i) < zm) zm = vz(i);
        o.zmin[p] = zm;
        if (!(std::isfinite(planes[3 * p]) && std::isfinite(planes[3 * p + 1]) && std::isfinite(planes[3 * p + 2]))) {
            o.starts[p + 1] = (i64)o.xs.size();
            continue;
        }
        i64 first = (i64)o.xs.size();
        for (i64 i = a; i < b; ++i) {
            i64 j = i == a ? b - 1 : i - 1;
            if (vx(i) != vx(j) || vy(i) != vy(j)) {
                o.xs.push_back(vx(i));
                o.ys.push_back(vy(i));
            }
        }
        if ((i64)o.xs.size() == first) {  // all one point
            o.xs.push_back(vx(a));
            o.ys.push_back(vy(a));
        }
        i64 m = (i64)o.xs.size();
        if (ring_area_of(o.xs.data(), o.ys.data(), first, m) < 0) {
            std::reverse(o.xs.begin() + first, o.xs.end());
            std::reverse(o.ys.begin() + first, o.ys.end());
        }
        o.starts[p + 1] = m;
        Box bb = shape_bbox(o.xs.data() + first, o.ys.data() + first, m - first);
        o.boxes[4 * p] = bb.x0;
        o.boxes[4 * p + 1] = bb.y0;
        o.boxes[4 * p + 2] = bb.x1;
        o.boxes[4 * p + 3] = bb.y1;
        for (i64 i = a; i < b; ++i) {
            o.scale = pmax(pmax(o.scale, std::fabs(vx(i))), std::fabs(vy(i)));
            o.zmax = pmax(o.zmax, std::fabs(vz(i)));
        }
    }
    return o;
}

}  // namespace wa
