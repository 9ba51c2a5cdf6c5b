// Step c of the hidden-surface loop (solver.cpp): a piece's depth against a clip
// polygon's plane.
#pragma once

#include "shape.hpp"

namespace wa {

// Whether every vertex of piece s (of polygon source) lies behind polygon src's plane by
// more than twice the tie band eps_z (planes: 3 a polygon).
bool wholly_behind(const ShapeView& s, i64 source, i64 src, const double* planes, double eps_z);

// FRONT, BEHIND or 0 (planes cross inside the piece): piece s of polygon source relative
// to polygon src.
int relation(const ShapeView& s, i64 source, i64 src, const double* planes, double eps_z);

}  // namespace wa
