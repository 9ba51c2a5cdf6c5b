// The solver's short road for convex pairs (convex_road.hpp).
#include "convex_road.hpp"

#include "solver.hpp"

namespace wa {

bool is_convex(const double* xs, const double* ys, i64 n) {
    for (i64 i = 0; i < n; ++i) {
        i64 j = (i + 1) % n, k = (i + 2) % n;
        if ((xs[j] - xs[i]) * (ys[k] - ys[j]) - (ys[j] - ys[i]) * (xs[k] - xs[j]) < 0) return false;
    }
    return true;
}

bool is_convex_piece(const ShapeView& s) { return s.nst == 2 && is_convex(s.x, s.y, s.n); }

bool takes_convex_road(const ShapeView& s) { return s.nst == 2 && s.n + 2 <= WORK_VERTICES && is_convex(s.x, s.y, s.n); }

void cut_by_outline(Arena& arena, i64 pid, i64 source, const Outline& o, double eps, Work& w,
                    std::vector<i64>& inside, std::vector<i64>& outside) {
    i64 n = w.load(arena.piece(pid));
    double tiny = eps * eps;
    i64 m = (i64)o.x.size();
    bool cut = false;
    for (i64 i = 0; i < m; ++i) {
        i64 j = i + 1 < m ? i + 1 : 0;
        double tol = eps * edge_line_values(w.f[0].data(), w.f[1].data(), n, o.x[i], o.y[i], o.x[j], o.y[j],
                                            w.f[6].data());
        auto [below, above] = vertex_sides(w.f[6].data(), n, tol);
        if (!above) continue;
        if (!below) {  // the rest lies beyond this edge: all of it outside
            outside.push_back(cut ? arena.add_contour(w.f[0].data(), w.f[1].data(), w.l[0].data(), n, source) : pid);
            return;
        }
        auto [nl, nr] = w.split(n, tol, o.lab[i]);
        if (ring_area_of(w.f[4].data(), w.f[5].data(), 0, nr) > tiny)
            outside.push_back(arena.add_contour(w.f[4].data(), w.f[5].data(), w.l[2].data(), nr, source));
        n = w.keep_left(nl);
        cut = true;
    }
    if (!cut) inside.push_back(pid);
    else if (ring_area_of(w.f[0].data(), w.f[1].data(), 0, n) > tiny)
        inside.push_back(arena.add_contour(w.f[0].data(), w.f[1].data(), w.l[0].data(), n, source));
}

i64 cut_by_plane_line(Arena& arena, i64 pid, i64 source, double a, double b, double c, double eps, Work& w) {
    i64 n = w.load(arena.piece(pid));
    double tol = eps * plane_line_values(w.f[0].data(), w.f[1].data(), n, a, b, c, w.f[6].data());
    auto [below, above] = vertex_sides(w.f[6].data(), n, tol);
    if (!below) return -1;
    if (!above) return pid;
    i64 nl = w.split(n, tol, EDGE_CROSSING).first;
    if (ring_area_of(w.f[2].data(), w.f[3].data(), 0, nl) <= eps * eps) return -1;
    return arena.add_contour(w.f[2].data(), w.f[3].data(), w.l[1].data(), nl, source);
}

}  // namespace wa
