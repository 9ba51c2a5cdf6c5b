// The scene format's near-tie rule for groups of nearly coplanar polygons
// (aaeval.weiler_atherton.near_ties is the API and explains the rule): polygon i is
// visible on its outline minus where another polygon is more than eps_z nearer, minus what
// later polygons claimed.
#pragma once

#include <array>
#include <utility>

#include "shape.hpp"

namespace wa {

// The visible region of each of `sources` inside the window by the rule, later polygons
// first: (source, region) for every non-empty region of positive area. Polygon s's
// outline is vertices ost[s]..ost[s + 1] - 1 of ox, oy (positive area), its box
// obb[4 s..], its plane planes[3 s..].
std::vector<std::pair<i64, Shape>> solve_by_rule(const double* ox, const double* oy, const i64* ost,
                                                 const double* obb, const double* planes, const i64* sources,
                                                 i64 nsources, const std::array<double, 4>& window, double eps,
                                                 double eps_z);

}  // namespace wa
