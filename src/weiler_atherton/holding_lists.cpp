#include "holding_lists.hpp"

#include <vector>

namespace wa {

namespace {

// Copy contour a..b-1 to the output (reversed: walked backwards, each edge keeping its
// label).
void append_ring(const double* xs, const double* ys, const i64* labels, i64 a, i64 b, bool reverse, Shape& o) {
    i64 k = b - a;
    for (i64 i = 0; i < k; ++i) {
        if (reverse) {
            i64 src = b - 1 - i;
            o.x.push_back(xs[src]);
            o.y.push_back(ys[src]);
            // reversed edge i runs from vertex b-1-i to b-2-i: the original edge b-2-i
            o.lab.push_back(i < k - 1 ? labels[b - 2 - i] : labels[b - 1]);
        } else {
            o.x.push_back(xs[a + i]);
            o.y.push_back(ys[a + i]);
            o.lab.push_back(labels[a + i]);
        }
    }
}

// A point in the middle of the first edge of contour a..b-1 (a one-vertex contour: that
// vertex).
inline double first_mid(const double* v, i64 a, i64 b) { return 0.5 * (v[a] + v[a + 1 < b ? a + 1 : a]); }

}  // namespace

// The paper's step 2 when no boundaries meet: whole contours to the holding lists; clip
// contours inside the subject go to both, reversed for the outside (a hole).
void holding_lists(const ShapeView& s, const double* cx, const double* cy, const ShapeView& c, Shape& in,
                   Shape& out) {
    std::vector<char> s_in(s.nst - 1), c_in(c.nst - 1);
    for (i64 r = 0; r + 1 < s.nst; ++r) {
        i64 a = s.st[r], b = s.st[r + 1];
        s_in[r] = winding(first_mid(s.x, a, b), first_mid(s.y, a, b), cx, cy, c.st, c.nst) > 0;
    }
    for (i64 r = 0; r + 1 < c.nst; ++r) {
        i64 a = c.st[r], b = c.st[r + 1];
        c_in[r] = winding(first_mid(cx, a, b), first_mid(cy, a, b), s.x, s.y, s.st, s.nst) > 0;
    }
    for (i64 r = 0; r + 1 < s.nst; ++r) {
        Shape& o = s_in[r] ? in : out;
        o.st.push_back((i64)o.x.size());
        append_ring(s.x, s.y, s.lab, s.st[r], s.st[r + 1], false, o);
    }
    for (i64 r = 0; r + 1 < c.nst; ++r) {
        if (!c_in[r]) continue;
        in.st.push_back((i64)in.x.size());
        append_ring(cx, cy, c.lab, c.st[r], c.st[r + 1], false, in);
        out.st.push_back((i64)out.x.size());
        append_ring(cx, cy, c.lab, c.st[r], c.st[r + 1], true, out);
    }
    in.st.push_back((i64)in.x.size());
    out.st.push_back((i64)out.x.size());
}

}  // namespace wa
