// An outline as seen from a piece's box (solver.cpp): the edges near
// the box as they are, runs of far edges replaced by walks round the box, so that a clip
// of a piece inside the box sees a few vertices instead of the whole outline.
#pragma once

#include <vector>

#include "shape.hpp"

namespace wa {

// How far beyond a piece's box (in units of eps) an outline edge counts as away from it:
// far beyond every tolerance of the clipper, yet a negligible share of a pixel.
constexpr double RIM = 1e6;

struct Outline {
    std::vector<double> x, y, len;  // len: each edge's length (separation's margins, once an outline)
    std::vector<i64> lab, st;
    // clean: self_clean is known to hold (of the whole outline, or of the one a local
    // outline was taken from); own (local outlines only): per vertex, 1 when the vertex and
    // the edge from it are the whole outline's own, 0 for the rim walks' vertices and edges,
    // so that a clip need not check the pairs of own vertices and edges again
    bool clean = false;
    std::vector<char> own;
    // chunk (index_chunks, may be empty): the box of each CHUNK consecutive edges of a
    // ring (ring r's first chunk is chunk_first[r]), so that local_outline passes a run of
    // edges away from a piece's box chunk by chunk
    std::vector<Box> chunk;
    std::vector<i64> chunk_first;
    ShapeView view() const {
        return ShapeView{x.data(), y.data(), lab.data(), st.data(), (i64)x.size(), (i64)st.size()};
    }
};

// How many consecutive edges of an outline share one box in Outline::chunk.
constexpr i64 CHUNK = 8;

// Fill o.chunk and o.chunk_first from o's rings.
void index_chunks(Outline& o);

// Outline o (one or more rings) as box b sees it, into `local` (definition:
// local_outline.cpp). Returns false when no edge comes near b (local then not to be used).
bool local_outline(const Outline& o, const Box& b, Outline& local);

// The winding number of point (px, py) about outline o (as winding gives it).
i64 outline_winding(double px, double py, const Outline& o);

// The winding number of point (px, py) about ring r of outline o.
i64 ring_winding(double px, double py, const Outline& o, i64 r);

// Whether contour r of shape s lies inside outline o (for a contour whose boundary and
// o's are apart).
bool contour_inside(const ShapeView& s, i64 r, const Outline& o);

}  // namespace wa
