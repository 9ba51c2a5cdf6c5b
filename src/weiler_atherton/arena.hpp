// The solver's pieces: pools of vertices, labels and contour starts, and per piece its
// ranges, source polygon and box; pieces are referred to by index (solver.cpp).
#pragma once

#include <vector>

#include "shape.hpp"

namespace wa {

struct Arena {
    struct Meta {
        i64 v0, v1, r0, r1, source;
    };
    std::vector<double> x, y;
    std::vector<i64> lab, st;
    std::vector<Meta> meta;
    std::vector<Box> box;

    Arena() { reserve(1024, 128); }
    // Room for about `vertices` vertices in `pieces` pieces before a pool is copied to
    // grow (reserved memory that is never written costs no pages).
    void reserve(i64 vertices, i64 pieces) {
        x.reserve(vertices);
        y.reserve(vertices);
        lab.reserve(vertices);
        st.reserve(2 * pieces);
        meta.reserve(pieces);
        box.reserve(pieces);
    }
    i64 size() const { return (i64)meta.size(); }
    i64 source(i64 k) const { return meta[k].source; }

    // the vertices just appended (v0..) close piece k: its box
    i64 close(i64 v0, i64 r0, i64 source) {
        i64 v1 = (i64)x.size();
        meta.push_back(Meta{v0, v1, r0, (i64)st.size(), source});
        box.push_back(v1 > v0 ? shape_bbox(x.data() + v0, y.data() + v0, v1 - v0) : Box{0, 0, 0, 0});
        return size() - 1;
    }
    // Store a piece (not a view into this arena); its index.
    i64 add(const Shape& s, i64 source) {
        i64 v0 = (i64)x.size(), r0 = (i64)st.size();
        x.insert(x.end(), s.x.begin(), s.x.end());
        y.insert(y.end(), s.y.begin(), s.y.end());
        lab.insert(lab.end(), s.lab.begin(), s.lab.end());
        st.insert(st.end(), s.st.begin(), s.st.end());
        return close(v0, r0, source);
    }
    // Store a piece of one contour, the first n vertices of xs, ys, labels; its index.
    i64 add_contour(const double* xs, const double* ys, const i64* labels, i64 n, i64 source) {
        i64 v0 = (i64)x.size(), r0 = (i64)st.size();
        x.insert(x.end(), xs, xs + n);
        y.insert(y.end(), ys, ys + n);
        lab.insert(lab.end(), labels, labels + n);
        st.push_back(0);
        st.push_back(n);
        return close(v0, r0, source);
    }
    // (xs, ys, labels, starts) of piece k: valid until the next piece is added
    ShapeView piece(i64 k) const {
        const Meta& m = meta[k];
        return ShapeView{x.data() + m.v0, y.data() + m.v0, lab.data() + m.v0, st.data() + m.r0, m.v1 - m.v0,
                         m.r1 - m.r0};
    }
};

}  // namespace wa
