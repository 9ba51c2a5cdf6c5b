// The Weiler-Atherton (1977) general polygon clipper (aaeval.weiler_atherton.clipper is
// the Python API and describes the paper's steps). No validation here: the bindings
// check their inputs once (module.cpp).
#pragma once

#include <memory>
#include <utility>

#include "shape.hpp"

namespace wa {

// Clip the subject shape by the clip shape: (inside shape, outside shape).
std::pair<Shape, Shape> clip_arrays(const ShapeView& s, const ShapeView& c, double eps);

// The clipper's working arrays, reused from clip to clip (one a thread).
struct ClipScratch {
    struct Arrays;
    std::unique_ptr<Arrays> arrays;
    ClipScratch();
    ~ClipScratch();
};

// clip_arrays into the given shapes, with the given working arrays (no allocation once
// the arrays have grown). subject_clean: self_clean(s, eps) is known to hold, so that a
// clean pair may take the clean road (clean_clip.cpp: the same bits, sooner).
// want_inside false: where the boundaries meet, the inside part is not traced (left
// empty); the outside part is the same.
// clip_own (may be null: nothing known): per clip vertex, 1 when it and the edge from it
// belong to a self-clean outline, whose pairs the clean road then need not check again.
// subject_box (may be null): s's box as shape_bbox gives it, when the caller holds it.
// Returns whether both parts are self_clean for certain: the subject was, and the pair
// took the clean road (its parts' vertices and edges are the subject's and clip's, and
// crossings, all of them checked apart from one another) or did not meet.
bool clip_into(const ShapeView& s, const ShapeView& c, double eps, Shape& in, Shape& out, ClipScratch& scratch,
               bool subject_clean = false, bool want_inside = true, const char* clip_own = nullptr,
               const Box* subject_box = nullptr);

// Whether no vertex of s comes within a few eps of an edge of s that it does not end
// (nor of another vertex): a subject the clean road can take.
// (scratch: working arrays.)
bool self_clean(const ShapeView& s, double eps, ClipScratch& scratch);

// The first pair of edges (global vertex indices of their starts) of one shape that
// cross properly, each strictly inside the other; (-1, -1) when none do.
std::pair<i64, i64> first_crossing(const double* xs, const double* ys, i64 n, const i64* starts, i64 nst,
                                   double eps);

// Item indices grouped by key (0 <= key < n), each group in input order (a counting
// sort): starts (n + 1 entries) and the indices.
void grouped(const i64* keys, i64 m, i64 n, std::vector<i64>& starts, std::vector<i64>& order);

}  // namespace wa
