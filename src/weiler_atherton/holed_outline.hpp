// The whole outline of a polygon with holes, which the scene holds as convex parts that
// abut (aaeval.scenes.holes): the solver clips a piece wholly behind such a polygon
// by all of it at once. Clipped part by part instead, a piece is cut along each part's
// edges, and the next part's clip finds the piece's vertices on its own shared edges, the
// general road's slow case, over and over; the convex parts' wedges multiply the pieces
// besides.
#pragma once

#include <vector>

#include "clipper.hpp"
#include "local_outline.hpp"

namespace wa {

// The rings bounding the union of polygons `parts` (outlines ox, oy, ost, each of
// positive area; parts that abut share their edges' ends bit for bit): every part edge
// whose reverse is not another part's edge, linked end to start. Winding numbers about
// the result are those about the parts added, 1 inside the union and 0 outside.
Outline holed_outline(const double* ox, const double* oy, const i64* ost, const std::vector<i64>& parts);

// Per polygon: the group its parts share (group[p], may be null: none) and, built on
// first use, each group's whole outline (its clean flag set: self_clean with eps; its
// chunks indexed).
struct HoledOutlines {
    const double *ox = nullptr, *oy = nullptr;
    const i64* ost = nullptr;
    const i64* group = nullptr;
    double eps = 0.0;
    std::vector<std::vector<i64>> parts;  // by group id; a group of one part is no polygon with holes
    std::vector<Outline> outline;
    std::vector<char> built;
    ClipScratch scratch;
    HoledOutlines(const double* ox, const double* oy, const i64* ost, const i64* group, i64 npoly, double eps);
    // polygon p's group when p is one of several parts, else -1
    i64 holed_group(i64 p) const { return group && parts[group[p]].size() > 1 ? group[p] : -1; }
    const Outline& of(i64 g);
};

}  // namespace wa
