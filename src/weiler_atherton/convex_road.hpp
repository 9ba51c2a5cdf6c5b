// The hidden-surface loop's working arrays and its short road for convex pairs (the
// cuts of convex.hpp applied to the solver's pieces; solver.cpp).
#pragma once

#include <algorithm>
#include <utility>
#include <vector>

#include "arena.hpp"
#include "clipper.hpp"
#include "convex.hpp"
#include "local_outline.hpp"

namespace wa {

// A convex piece that crosses a polygon's plane is cut along the crossing line by the convex
// road while it has at most this many vertices (with the two the cut adds), by the paper's
// clipper beyond. A convex piece clipped by a convex outline takes the convex road at any
// size: cutting by m edge lines costs O(n m), no more than the paper's clipper on such a
// pair, and its outside stays convex pieces instead of one growing polygon with holes.
constexpr i64 WORK_VERTICES = 64;
constexpr i64 SPLIT_VERTICES = 64;  // the solver halves pieces with more vertices (Solver::halve)

// The solver's working arrays. Scratch rows for cutting one convex piece: current x, y;
// left part x, y; right part x, y; line values; labels current, left, right. Rows grow
// (never shrink) to what a split can write, so no input can write past them.
struct Work {
    std::vector<double> f[7];
    std::vector<i64> l[3];
    Outline local;  // the outline a piece's box sees (local_outline)
    std::vector<signed char> clean;  // per piece: self_clean (-1: not known yet)
    Shape in, out;  // a clip's two parts
    ClipScratch clip;  // the clipper's working arrays
    void ensure(i64 n) {
        size_t need = (size_t)(2 * n + 2);
        if (f[0].size() >= need) return;
        for (auto& r : f) r.resize(need);
        for (auto& r : l) r.resize(need);
    }
    // whether piece pid is self_clean (computed once: pieces do not change)
    bool is_clean(const Arena& arena, i64 pid, double eps) {
        if ((i64)clean.size() < arena.size()) clean.resize(arena.size(), -1);
        if (clean[pid] < 0) clean[pid] = self_clean(arena.piece(pid), eps, clip);
        return clean[pid] > 0;
    }
    // Shape s stored as a piece of polygon source; its index. known_clean: s is self_clean
    // for certain (clip_into said so of the parts it made), so is_clean need not check it.
    i64 store(Arena& arena, const Shape& s, i64 source, bool known_clean) {
        i64 pid = arena.add(s, source);
        if (known_clean) {
            if ((i64)clean.size() < arena.size()) clean.resize(arena.size(), -1);
            clean[pid] = 1;
        }
        return pid;
    }
    i64 load(const ShapeView& s) {
        ensure(s.n);
        std::copy(s.x, s.x + s.n, f[0].begin());
        std::copy(s.y, s.y + s.n, f[1].begin());
        std::copy(s.lab, s.lab + s.n, l[0].begin());
        return s.n;
    }
    // the left part becomes the current contour
    i64 keep_left(i64 nl) {
        ensure(nl);
        std::copy(f[2].begin(), f[2].begin() + nl, f[0].begin());
        std::copy(f[3].begin(), f[3].begin() + nl, f[1].begin());
        std::copy(l[1].begin(), l[1].begin() + nl, l[0].begin());
        return nl;
    }
    std::pair<i64, i64> split(i64 n, double tol, i64 line_label) {
        return split_convex(f[0].data(), f[1].data(), l[0].data(), n, f[6].data(), tol, line_label, f[2].data(),
                            f[3].data(), l[1].data(), f[4].data(), f[5].data(), l[2].data());
    }
};

// Whether the contour (positive area) turns left or goes straight at every vertex.
bool is_convex(const double* xs, const double* ys, i64 n);

// Whether a piece is one convex contour.
bool is_convex_piece(const ShapeView& s);

// Whether a piece is one convex contour of at most WORK_VERTICES vertices with the two a
// cut along a line adds.
bool takes_convex_road(const ShapeView& s);

// Piece pid (one convex contour) clipped by a convex outline, edge line by edge line:
// the part beyond each line goes to the outside list, what is left at the end to the
// inside list (a part of area eps**2 or less is dropped, as the clipper drops it). A
// piece no line cuts goes whole to its list.
void cut_by_outline(Arena& arena, i64 pid, i64 source, const Outline& o, double eps, Work& w,
                    std::vector<i64>& inside, std::vector<i64>& outside);

// The part a x + b y + c <= 0 of piece pid (one convex contour), its edge along the line
// labelled EDGE_CROSSING, stored as a new piece: its index, or -1 when it has area eps**2
// or less. Only for a piece the line crosses (its relation is 0).
i64 cut_by_plane_line(Arena& arena, i64 pid, i64 source, double a, double b, double c, double eps, Work& w);

}  // namespace wa
