// The hidden-surface loop of Weiler & Atherton (aaeval.weiler_atherton.hidden_surface is
// the Python API and describes the steps).
#pragma once

#include <array>

#include "shape.hpp"

namespace wa {

constexpr i64 EDGE_CUT = 0;
constexpr i64 EDGE_OWN = 1;
constexpr i64 EDGE_CROSSING = 2;
constexpr int FRONT = -1;
constexpr int BEHIND = 1;
constexpr int OUTSIDE = 1;
constexpr int INSIDE = 2;

// For a convex clip contour: OUTSIDE when every subject vertex lies farther than 2 eps
// beyond one clip edge's line, INSIDE when every one lies farther than 2 eps inside every
// edge's line, else 0.
// len: the clip edges' lengths when known (nullptr: computed here); sbox: the subject's
// box when known (a box inside every edge's line by far more than 2 eps is INSIDE at once).
int separation(const double* sx, const double* sy, i64 ns, const double* cx, const double* cy, i64 nc, double eps,
               const double* len = nullptr, const Box* sbox = nullptr);

// The part a x + b y + c <= 0 of the bounding box (grown by one unit), as a convex shape
// whose edge along the line is labelled EDGE_CROSSING.
Shape half_plane(double a, double b, double c, const Box& bbox);

// For each position p of the depth order, the later positions whose polygons' boxes
// overlap polygon order[p]'s, in ascending order: (row starts, positions).
void later_neighbours(const double* obb, const i64* order, i64 n, std::vector<i64>& starts, std::vector<i64>& rows);

struct Originals {
    std::vector<double> xs, ys, boxes, zmin;  // boxes: 4 a polygon
    std::vector<i64> starts;
    double scale = 0.0, zmax = 0.0;
};

// Every polygon's outline as the solver takes it: consecutive repeats in (x, y) dropped,
// turned to positive shoelace area; polygons seen edge-on (non-finite plane) get an empty
// outline. vertices: (N, 3) rows; planes: (n, 3) rows.
Originals originals(const double* vertices, const i64* start, const i64* length, i64 n, const double* planes);

struct Visible {
    std::vector<double> xs, ys;
    std::vector<i64> labels, starts, piece_rings, sources;
};

// Visible pieces of the polygons `order` (depth-sorted) inside window `win`; ox, oy, ost:
// every polygon's original outline (positive area), obb their boxes (4 a polygon),
// planes their depth planes (3 a polygon); group (may be null): per polygon, the polygon
// it was cut from, parts of one group being known not to overlap.
Visible solve_window(const double* ox, const double* oy, const i64* ost, i64 npoly, const double* obb,
                     const double* planes, const i64* order, i64 norder, const std::array<double, 4>& win,
                     double eps, double eps_z, bool convex_road, const i64* group = nullptr);

}  // namespace wa
