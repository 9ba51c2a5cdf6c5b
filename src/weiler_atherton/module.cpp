// aaeval.native.weiler_atherton: the Weiler-Atherton kernels bound with nanobind.
//
// Every input is checked here, once, before a kernel runs (dtype, dimensions, C order,
// consistent lengths, contour starts, indices in range, finite coordinates) and refused
// with a one-line ValueError; the kernels themselves trust their inputs and run without
// the GIL.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/optional.h>

#include <cmath>
#include <string>

#include "bindings.hpp"
#include "common/polygon_arrays.hpp"
#include "clipper.hpp"
#include "components.hpp"
#include "near_ties.hpp"
#include "raster.hpp"
#include "solver.hpp"

using namespace nb::literals;
using namespace wa::bindings;
using wa::i64;

namespace {

nb::tuple clip_arrays(const In& sx, const In& sy, const In& sl, const In& ss, const In& cx, const In& cy,
                      const In& cl, const In& cs, double eps) {
    wa::ShapeView s = shape(sx, sy, sl, ss, "subject");
    wa::ShapeView c = shape(cx, cy, cl, cs, "clip shape");
    check_scalar(eps, "eps");
    std::pair<wa::Shape, wa::Shape> r;
    {
        nb::gil_scoped_release release;
        r = wa::clip_arrays(s, c, eps);
    }
    nb::tuple in = shape_tuple(std::move(r.first)), out = shape_tuple(std::move(r.second));
    return nb::make_tuple(in[0], in[1], in[2], in[3], out[0], out[1], out[2], out[3]);
}

nb::tuple first_crossing(const In& xs, const In& ys, const In& starts, double eps) {
    const double* x = checked<const double>(xs, "xs", 1);
    i64 n = (i64)xs.shape(0), nst;
    const double* y = checked<const double>(ys, "ys", 1, {n});
    const i64* st = checked_starts(starts, "starts", n, nst, n > 0 ? 1 : 0);
    check_finite(x, n, "xs");
    check_finite(y, n, "ys");
    check_scalar(eps, "eps");
    std::pair<i64, i64> r;
    {
        nb::gil_scoped_release release;
        r = wa::first_crossing(x, y, n, st, nst, eps);
    }
    return nb::make_tuple(r.first, r.second);
}

double ring_area_of(const In& xs, const In& ys, i64 a, i64 b) {
    const double* x = checked<const double>(xs, "xs", 1);
    i64 n = (i64)xs.shape(0);
    const double* y = checked<const double>(ys, "ys", 1, {n});
    if (a < 0 || b > n || a > b) refuse("vertex range " + std::to_string(a) + ".." + std::to_string(b) +
                                        " is not within 0.." + std::to_string(n));
    return wa::ring_area_of(x, y, a, b);
}

i64 winding(double px, double py, const In& xs, const In& ys, const In& starts) {
    const double* x = checked<const double>(xs, "xs", 1);
    i64 n = (i64)xs.shape(0), nst;
    const double* y = checked<const double>(ys, "ys", 1, {n});
    const i64* st = checked_starts(starts, "starts", n, nst, 0);
    return wa::winding(px, py, x, y, st, nst);
}

// boxes (m, 4) and an order of indices into them
const i64* checked_order(const In& order, const char* name, i64 m, i64& n) {
    const i64* o = checked<const i64>(order, name, 1);
    n = (i64)order.shape(0);
    for (i64 i = 0; i < n; ++i)
        if (o[i] < 0 || o[i] >= m)
            refuse(std::string(name) + " holds " + std::to_string(o[i]) + ", not an index below " + std::to_string(m));
    return o;
}

nb::tuple later_neighbours(const In& obb, const In& order) {
    const double* bb = checked<const double>(obb, "boxes", 2, {-1, 4});
    i64 m = (i64)obb.shape(0), n;
    const i64* o = checked_order(order, "order", m, n);
    std::vector<i64> starts, rows;
    {
        nb::gil_scoped_release release;
        wa::later_neighbours(bb, o, n, starts, rows);
    }
    return nb::make_tuple(numpy_of(std::move(starts)), numpy_of(std::move(rows)));
}

nb::tuple originals(const In& vertices, const In& start, const In& length, const In& planes) {
    const double* v = checked<const double>(vertices, "vertices", 2, {-1, 3});
    i64 nv = (i64)vertices.shape(0);
    const i64* st = checked<const i64>(start, "start", 1);
    i64 n = (i64)start.shape(0);
    const i64* ln = checked<const i64>(length, "length", 1, {n});
    const double* pl = checked<const double>(planes, "planes", 2, {n, 3});
    check_finite(v, 3 * nv, "vertices");
    aaeval::arrays::check_records("", st, ln, n, nv);
    wa::Originals o;
    {
        nb::gil_scoped_release release;
        o = wa::originals(v, st, ln, n, pl);
    }
    return nb::make_tuple(numpy_of(std::move(o.xs)), numpy_of(std::move(o.ys)), numpy_of(std::move(o.starts)),
                          numpy_of(std::move(o.boxes), {(size_t)n, 4}), numpy_of(std::move(o.zmin)), o.scale, o.zmax);
}

// The polygons of a window solve, checked once: outlines (xs, ys, starts), boxes and
// planes, the window and tolerances, and the listed polygons (the solve order, or the
// sources of a near-tie group), each with an outline and a finite plane.
struct Outlines {
    const double* ox;
    const double* oy;
    const i64* ost;
    const double* obb;
    const double* planes;
    i64 npoly;
    const i64* listed;
    i64 nlisted;
};

Outlines checked_outlines(const In& oxs, const In& oys, const In& osts, const In& obbs, const In& planes_,
                          const In& listed_, const char* listed_name, const std::array<double, 4>& win,
                          double eps, double eps_z) {
    Outlines o{};
    o.ox = checked<const double>(oxs, "outline xs", 1);
    i64 nv = (i64)oxs.shape(0), nst;
    o.oy = checked<const double>(oys, "outline ys", 1, {nv});
    o.ost = checked_starts(osts, "outline starts", nv, nst, 0);
    if (nst == 0) refuse("outline starts must hold one entry more than there are polygons");
    o.npoly = nst - 1;
    o.obb = checked<const double>(obbs, "boxes", 2, {o.npoly, 4});
    o.planes = checked<const double>(planes_, "planes", 2, {o.npoly, 3});
    o.listed = checked_order(listed_, listed_name, o.npoly, o.nlisted);
    check_finite(o.ox, nv, "outline xs");
    check_finite(o.oy, nv, "outline ys");
    check_finite(o.obb, 4 * o.npoly, "boxes");
    check_finite(win.data(), 4, "window");
    check_scalar(eps, "eps");
    check_scalar(eps_z, "eps_z");
    for (i64 k = 0; k < o.nlisted; ++k) {
        i64 s = o.listed[k];
        if (o.ost[s + 1] == o.ost[s])
            refuse("polygon " + std::to_string(s) + " in the " + listed_name + " has an empty outline");
        check_finite(o.planes + 3 * s, 3, (std::string("planes of the ") + listed_name).c_str());
    }
    return o;
}

nb::tuple solve_window(const In& oxs, const In& oys, const In& osts, const In& obbs, const In& planes_,
                       const In& order_, const std::array<double, 4>& win, double eps, double eps_z,
                       bool convex_road, std::optional<In> group_) {
    const Outlines o = checked_outlines(oxs, oys, osts, obbs, planes_, order_, "order", win, eps, eps_z);
    const i64* group = group_ ? checked<const i64>(*group_, "group", 1, {o.npoly}) : nullptr;
    wa::Visible v;
    {
        nb::gil_scoped_release release;
        v = wa::solve_window(o.ox, o.oy, o.ost, o.npoly, o.obb, o.planes, o.listed, o.nlisted, win, eps, eps_z, convex_road, group);
    }
    return nb::make_tuple(numpy_of(std::move(v.xs)), numpy_of(std::move(v.ys)), numpy_of(std::move(v.labels)),
                          numpy_of(std::move(v.starts)), numpy_of(std::move(v.piece_rings)),
                          numpy_of(std::move(v.sources)));
}

nb::list solve_by_rule(const In& oxs, const In& oys, const In& osts, const In& obbs, const In& planes_,
                       const In& sources_, const std::array<double, 4>& win, double eps, double eps_z) {
    const Outlines o = checked_outlines(oxs, oys, osts, obbs, planes_, sources_, "sources", win, eps, eps_z);
    std::vector<std::pair<i64, wa::Shape>> regions;
    {
        nb::gil_scoped_release release;
        regions = wa::solve_by_rule(o.ox, o.oy, o.ost, o.obb, o.planes, o.listed, o.nlisted, win, eps, eps_z);
    }
    nb::list out;
    for (auto& [source, shape] : regions) {
        nb::tuple arrays = shape_tuple(std::move(shape));
        out.append(nb::make_tuple(source, arrays[0], arrays[1], arrays[2], arrays[3]));
    }
    return out;
}

// Contours given flat for the box filter: vertices xs, ys; contour r is starts[r]..starts[r + 1].
struct Rings {
    const double *x, *y;
    const i64* st;
    i64 n;  // contours
};

Rings checked_rings(const In& xs, const In& ys, const In& starts) {
    Rings r;
    r.x = checked<const double>(xs, "xs", 1);
    i64 n = (i64)xs.shape(0), nst;
    r.y = checked<const double>(ys, "ys", 1, {n});
    r.st = checked_starts(starts, "starts", n, nst, 0);
    if (nst == 0) refuse("starts must hold one entry more than there are contours");
    check_finite(r.x, n, "xs");
    check_finite(r.y, n, "ys");
    r.n = nst - 1;
    return r;
}

void add_coverage(const In& xs, const In& ys, const In& starts, const In& weights, Out& out) {
    const Rings r = checked_rings(xs, ys, starts);
    double* o = checked<double>(out, "out", 3);
    i64 h = (i64)out.shape(0), w = (i64)out.shape(1), k = (i64)out.shape(2);
    const double* wt = checked<const double>(weights, "weights", 2, {r.n, k});
    nb::gil_scoped_release release;
    wa::add_coverage(r.x, r.y, r.st, r.n, wt, o, h, w, k);
}

// A new (h, w, k) image: base (k values) plus the per-pixel sum of weights[ring] * the
// ring's area over the pixel (add_coverage on an image filled with base, without the fill).
nb::ndarray<nb::numpy, double> coverage_over(const In& xs, const In& ys, const In& starts, const In& weights,
                                             const In& base, i64 h, i64 w) {
    const Rings r = checked_rings(xs, ys, starts);
    const double* b = checked<const double>(base, "base", 1);
    const i64 k = (i64)base.shape(0);
    const double* wt = checked<const double>(weights, "weights", 2, {r.n, k});
    if (h < 0 || w < 0 || k < 1 || h > (i64(1) << 20) || w > (i64(1) << 20) || h * w > (i64(1) << 34) / k)
        refuse("image size must be between 0 and 2^20 a side and base hold at least one channel");
    double* o = nullptr;
    auto image = aaeval::results::new_array<double>({(size_t)h, (size_t)w, (size_t)k}, o, false);
    {
        nb::gil_scoped_release release;
        wa::coverage_over(r.x, r.y, r.st, r.n, wt, b, o, h, w, k);
    }
    return image;
}

// Connected components of the graph on n nodes with edges a[i] - b[i]: each node's label
// is the smallest node of its component.
nb::object components(i64 n, const In& a_, const In& b_) {
    if (n < 0) refuse("n must be >= 0");
    i64 m;
    const i64* a = checked_order(a_, "a", n, m);
    i64 mb;
    const i64* b = checked_order(b_, "b", n, mb);
    if (mb != m) refuse("a and b must have the same length");
    std::vector<i64> labels;
    {
        nb::gil_scoped_release release;
        labels = wa::components(n, a, b, m);
    }
    return numpy_of(std::move(labels));
}

}  // namespace

NB_MODULE(weiler_atherton, m) {
    m.doc() = "Weiler-Atherton kernels: the polygon clipper, the hidden-surface solver and the exact box filter";
    m.attr("EDGE_CUT") = wa::EDGE_CUT;
    m.attr("EDGE_OWN") = wa::EDGE_OWN;
    m.attr("EDGE_CROSSING") = wa::EDGE_CROSSING;
    m.attr("OUTSIDE") = wa::OUTSIDE;
    m.attr("INSIDE") = wa::INSIDE;
    m.def("clip_arrays", &clip_arrays, "sx"_a, "sy"_a, "sl"_a, "ss"_a, "cx"_a, "cy"_a, "cl"_a, "cs"_a, "eps"_a,
          "Clip the subject shape (xs, ys, labels, starts) by the clip shape: the inside shape's four arrays, "
          "then the outside shape's.");
    m.def("first_crossing", &first_crossing, "xs"_a, "ys"_a, "starts"_a, "eps"_a,
          "The first pair of edges of one shape that cross properly, (-1, -1) when none do.");
    m.def("ring_area_of", &ring_area_of, "xs"_a, "ys"_a, "a"_a, "b"_a,
          "Shoelace area of the contour of vertices a..b-1 (positive: main contour).");
    m.def("winding", &winding, "px"_a, "py"_a, "xs"_a, "ys"_a, "starts"_a,
          "Winding number of the point about the oriented contours.");
    m.def("later_neighbours", &later_neighbours, "boxes"_a, "order"_a,
          "For each position of the order, the later positions whose boxes overlap: (row starts, positions).");
    m.def("originals", &originals, "vertices"_a, "start"_a, "length"_a, "planes"_a,
          "Every polygon's outline as the solver takes it: (xs, ys, starts, boxes, nearest depth, scale, zmax).");
    m.def("solve_window", &solve_window, "ox"_a, "oy"_a, "ost"_a, "obb"_a, "planes"_a, "order"_a, "win"_a, "eps"_a,
          "eps_z"_a, "convex_road"_a = true, "group"_a = nb::none(),
          "Visible pieces of the depth-sorted polygons inside the window, flattened: (xs, ys, labels, starts, "
          "piece_rings, sources).");
    m.def("solve_by_rule", &solve_by_rule, "ox"_a, "oy"_a, "ost"_a, "obb"_a, "planes"_a, "sources"_a, "win"_a,
          "eps"_a, "eps_z"_a,
          "The near-tie rule's visible region of each source inside the window, later polygons first: "
          "[(source, xs, ys, labels, starts), ...] for the regions of positive area.");
    m.def("add_coverage", &add_coverage, "xs"_a, "ys"_a, "starts"_a, "weights"_a, "out"_a,
          "out (h, w, k) += per-pixel sum of weights[ring] * the ring's area over the pixel.");
    m.def("coverage_over", &coverage_over, "xs"_a, "ys"_a, "starts"_a, "weights"_a, "base"_a, "h"_a, "w"_a,
          "A new (h, w, k) image: base plus the per-pixel sum of weights[ring] * the ring's area over the pixel.");
    m.def("components", &components, "n"_a, "a"_a, "b"_a,
          "Connected components of the graph with edges a[i] - b[i]: each node's smallest node of its component.");
}
