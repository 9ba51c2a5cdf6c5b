// The near-tie rule's regions, clip by clip in one fixed order (later polygons first, each
// cut by the nearer parts of the others in the order given, then by what earlier ones
// claimed), so a region's bits depend on the scene alone.
#include "near_ties.hpp"

#include <algorithm>
#include <functional>

#include "clipper.hpp"
#include "solver.hpp"

namespace wa {

namespace {

struct MaybeBox {
    bool empty;
    Box b;
};

// the region's box; empty when the region has no contour
MaybeBox region_box(const Shape& s) {
    if (s.st.size() < 2) return {true, {}};
    return {false, shape_bbox(s.x.data(), s.y.data(), (i64)s.x.size())};
}

bool meet(const Box& a, const Box& b) { return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1; }

// main contours minus holes, summed contour by contour from 0
double shape_area(const Shape& s) {
    double a = 0.0;
    for (size_t r = 0; r + 1 < s.st.size(); ++r) a += ring_area_of(s.x.data(), s.y.data(), s.st[r], s.st[r + 1]);
    return a;
}

}  // namespace

std::vector<std::pair<i64, Shape>> solve_by_rule(const double* ox, const double* oy, const i64* ost,
                                                 const double* obb, const double* planes, const i64* sources,
                                                 i64 nsources, const std::array<double, 4>& window, double eps,
                                                 double eps_z) {
    const double fx[4] = {window[0], window[2], window[2], window[0]};
    const double fy[4] = {window[1], window[1], window[3], window[3]};
    const i64 fl[4] = {EDGE_CUT, EDGE_CUT, EDGE_CUT, EDGE_CUT}, fs[2] = {0, 4};
    const ShapeView frame{fx, fy, fl, fs, 4, 2};
    std::vector<i64> order(sources, sources + nsources);
    // each polygon's outline, its edges labelled EDGE_OWN
    std::vector<std::vector<i64>> own_labels(nsources), own_starts(nsources);
    std::vector<ShapeView> outline(nsources);
    for (i64 k = 0; k < nsources; ++k) {
        i64 s = order[k], a = ost[s], b = ost[s + 1];
        own_labels[k].assign(b - a, EDGE_OWN);
        own_starts[k] = {0, b - a};
        outline[k] = ShapeView{ox + a, oy + a, own_labels[k].data(), own_starts[k].data(), b - a, 2};
    }
    std::vector<i64> later(nsources);
    for (i64 k = 0; k < nsources; ++k) later[k] = k;
    std::stable_sort(later.begin(), later.end(), [&](i64 p, i64 q) { return order[p] > order[q]; });
    std::vector<std::pair<Shape, Box>> claimed;
    std::vector<std::pair<i64, Shape>> out;
    for (i64 ki : later) {  // later polygons claim first
        i64 i = order[ki];
        Shape region = clip_arrays(outline[ki], frame, eps).first;
        MaybeBox box = region_box(region);
        for (i64 kj = 0; kj < nsources; ++kj) {
            i64 j = order[kj];
            Box bj{obb[4 * j], obb[4 * j + 1], obb[4 * j + 2], obb[4 * j + 3]};
            if (j == i || box.empty || !meet(bj, box.b)) continue;
            double a = planes[3 * j] - planes[3 * i];
            double b = planes[3 * j + 1] - planes[3 * i + 1];
            double c = planes[3 * j + 2] - planes[3 * i + 2];
            Shape nearer = half_plane(a, b, c + eps_z, box.b);  // z_j < z_i - eps
            if (nearer.x.size() < 3) continue;
            Shape cut = clip_arrays(outline[kj], nearer.view(), eps).first;
            if (cut.st.size() > 1) {
                region = clip_arrays(region.view(), cut.view(), eps).second;
                box = region_box(region);
            }
        }
        for (const auto& [taken, taken_box] : claimed) {
            if (!box.empty && meet(taken_box, box.b)) {
                region = clip_arrays(region.view(), taken.view(), eps).second;
                box = region_box(region);
            }
        }
        if (!box.empty && shape_area(region) > 0) {
            claimed.emplace_back(region, box.b);
            out.emplace_back(i, std::move(region));
        }
    }
    return out;
}

}  // namespace wa
