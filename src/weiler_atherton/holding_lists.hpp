// The paper's step 2, for a subject and clip whose boundaries do not meet (clipper.cpp).
#pragma once

#include "shape.hpp"

namespace wa {

// Whole contours to the holding lists: subject contours by where they lie, clip contours
// inside the subject to both, reversed for the outside (a hole). cx, cy: the clip's
// vertices (snapped); c: its labels and contour starts.
void holding_lists(const ShapeView& s, const double* cx, const double* cy, const ShapeView& c, Shape& in,
                   Shape& out);

}  // namespace wa
