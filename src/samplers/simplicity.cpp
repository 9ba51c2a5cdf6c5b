// The Shamos-Hoey sweep line of the simplicity check (aaeval/scenes/simplicity.py, which
// explains it): edges enter an ordered list at their left end and leave it at their right
// end, and only edges that become neighbours are tested. Its orientation arithmetic is
// simplicity.py's, in the same order, so both judge every near-tie the same way.
#include <cstdint>
#include <vector>

#include "common/numeric.hpp"
#include "samplers/sampling.hpp"

namespace aaeval::samplers {

namespace {

struct Rings {
    const double* pts;  // (n, 2)
    const int64_t* a;   // edge e runs from vertex a[e] to vertex b[e]
    const int64_t* b;
    const int64_t* left;
    const int64_t* right;
    double x(int64_t v) const { return pts[2 * v]; }
    double y(int64_t v) const { return pts[2 * v + 1]; }

    int orient(int64_t u, int64_t v, int64_t w) const {
        const double value = (x(v) - x(u)) * (y(w) - y(u)) - (y(v) - y(u)) * (x(w) - x(u));
        return value > 0 ? 1 : (value < 0 ? -1 : 0);
    }

    bool within(int64_t u, int64_t v, int64_t w) const {  // w on segment uv, given collinear
        return pymin(x(u), x(v)) <= x(w) && x(w) <= pymax(x(u), x(v)) && pymin(y(u), y(v)) <= y(w) &&
               y(w) <= pymax(y(u), y(v));
    }

    // Whether edges e and f meet (consecutive ones: whether they fold along each other).
    bool meet(int64_t e, int64_t f) const {
        const int64_t p = a[e], q = b[e], r = a[f], s = b[f];
        if (p == r || p == s || q == r || q == s) {
            const int64_t near = (p == r || p == s) ? p : q;
            const int64_t far_e = near == p ? q : p;
            const int64_t far_f = near == r ? s : r;
            return orient(near, far_e, far_f) == 0 && (within(near, far_e, far_f) || within(near, far_f, far_e));
        }
        const int o1 = orient(p, q, r), o2 = orient(p, q, s);
        const int o3 = orient(r, s, p), o4 = orient(r, s, q);
        if (o1 * o2 < 0 && o3 * o4 < 0) return true;
        return (o1 == 0 && within(p, q, r)) || (o2 == 0 && within(p, q, s)) || (o3 == 0 && within(r, s, p)) ||
               (o4 == 0 && within(r, s, q));
    }

    // Edge e against listed edge t at the sweep point v, a vertex of e: +1 above, -1 below,
    // 2 when v lies on t (a meeting, unless t shares v).
    int side(int64_t e, int64_t t, int64_t v) const {
        int o = orient(left[t], right[t], v);
        if (o != 0) return o;
        if (a[t] == v || b[t] == v) {  // both edges leave (or both reach) v: order them by e's far end
            const int64_t far = a[e] == v ? b[e] : a[e];
            o = orient(left[t], right[t], far);
            return o == 0 ? 2 : o;
        }
        return 2;
    }

    // Binary search of the list at sweep point v for edge e: position where e is (or goes)
    // with hit = -1, or the position of an edge hit that v lies on.
    int64_t locate(const std::vector<int64_t>& active, int64_t size, int64_t e, int64_t v, int64_t& hit) const {
        int64_t lo = 0, hi = size;
        hit = -1;
        while (lo < hi) {
            const int64_t mid = (lo + hi) / 2;
            const int64_t t = active[mid];
            if (t == e) return mid;
            const int c = side(e, t, v);
            if (c == 2) {
                hit = t;
                return mid;
            }
            if (c > 0)
                lo = mid + 1;
            else
                hi = mid;
        }
        return lo;
    }
};

}  // namespace

bool sweep(int64_t n, const double* pts, const int64_t* a, const int64_t* b, const int64_t* order,
           const int64_t* incoming, int64_t& e_out, int64_t& f_out) {
    e_out = f_out = -1;
    std::vector<int64_t> rank(n), left(n), right(n);
    for (int64_t i = 0; i < n; ++i) rank[order[i]] = i;
    for (int64_t e = 0; e < n; ++e) {
        if (rank[a[e]] < rank[b[e]]) {
            left[e] = a[e];
            right[e] = b[e];
        } else {
            left[e] = b[e];
            right[e] = a[e];
        }
    }
    const Rings R{pts, a, b, left.data(), right.data()};
    std::vector<int64_t> active(n);  // edges crossing the sweep line, bottom to top
    int64_t size = 0;
    for (int64_t i = 0; i < n; ++i) {
        const int64_t v = order[i];
        for (int k = 0; k < 2; ++k) {  // edges ending at v leave first
            const int64_t e = k == 0 ? incoming[v] : v;
            if (right[e] != v) continue;
            int64_t hit;
            int64_t pos = R.locate(active, size, e, v, hit);
            if (hit >= 0) {
                e_out = e;
                f_out = hit;
                return true;
            }
            if (pos >= size || active[pos] != e) {  // rounding left the list unordered: look it up
                pos = 0;
                while (pos < size && active[pos] != e) ++pos;
                if (pos == size) return false;  // never entered: the arrays are not rings
            }
            for (int64_t m = pos; m < size - 1; ++m) active[m] = active[m + 1];
            --size;
            if (0 < pos && pos < size && R.meet(active[pos - 1], active[pos])) {
                e_out = active[pos - 1];
                f_out = active[pos];
                return true;
            }
        }
        for (int k = 0; k < 2; ++k) {  // then edges starting at v enter
            const int64_t e = k == 0 ? incoming[v] : v;
            if (left[e] != v) continue;
            int64_t hit;
            const int64_t lo = R.locate(active, size, e, v, hit);
            if (hit >= 0) {
                e_out = e;
                f_out = hit;
                return true;
            }
            if (size == n) return false;  // an edge entering twice: the arrays are not rings
            for (int64_t m = size; m > lo; --m) active[m] = active[m - 1];
            active[lo] = e;
            ++size;
            if (lo > 0 && R.meet(active[lo - 1], e)) {
                e_out = active[lo - 1];
                f_out = e;
                return true;
            }
            if (lo + 1 < size && R.meet(e, active[lo + 1])) {
                e_out = e;
                f_out = active[lo + 1];
                return true;
            }
        }
    }
    return true;
}

void first_meeting_pair(int64_t n, const double* pts, const int64_t* a, const int64_t* b, int64_t& e_out,
                        int64_t& f_out) {
    // every pair in order of e, then f (np.triu_indices' order); boxes first, with the same
    // closed comparisons, so a pair far apart is never judged by rounded orientations
    e_out = f_out = -1;
    const Rings R{pts, a, b, nullptr, nullptr};
    std::vector<double> box(static_cast<size_t>(4 * n));  // x0, x1, y0, y1 of each edge
    for (int64_t e = 0; e < n; ++e) {
        box[4 * e] = pymin(R.x(a[e]), R.x(b[e]));
        box[4 * e + 1] = pymax(R.x(a[e]), R.x(b[e]));
        box[4 * e + 2] = pymin(R.y(a[e]), R.y(b[e]));
        box[4 * e + 3] = pymax(R.y(a[e]), R.y(b[e]));
    }
    for (int64_t e = 0; e < n; ++e) {
        const double* be = &box[4 * e];
        for (int64_t f = e + 1; f < n; ++f) {
            const double* bf = &box[4 * f];
            if (!(be[0] <= bf[1] && bf[0] <= be[1] && be[2] <= bf[3] && bf[2] <= be[3])) continue;
            if (R.meet(e, f)) {
                e_out = e;
                f_out = f;
                return;
            }
        }
    }
}

}  // namespace aaeval::samplers
