// Exact integration of visible pieces against a separable pixel filter, by stage: the
// filter's basis (filter_basis.hpp), the integrals of one polygon in a knot cell
// (edge_integrals.hpp), rings cut on the knot grid (knot_grid.hpp), cells contracted into
// pixels (contraction.hpp) and the Catmull kernel's sink (moment_sink.hpp).
#pragma once

#include "catmull/filter_basis.hpp"
#include "catmull/edge_integrals.hpp"
#include "catmull/knot_grid.hpp"
#include "catmull/contraction.hpp"
#include "catmull/moment_sink.hpp"
