// aaeval.native.weiler_atherton_testing: the solver's inner pieces bound for the tests alone
// (the convex road's cuts, the separation test, the half-plane of a crossing line), checked
// as the kernel's bindings are (bindings.hpp).
#include <nanobind/stl/array.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "convex.hpp"
#include "solver.hpp"

using namespace nb::literals;
using namespace wa::bindings;
using wa::i64;

namespace {

nb::tuple half_plane(double a, double b, double c, const std::array<double, 4>& bbox) {
    return shape_tuple(wa::half_plane(a, b, c, wa::Box{bbox[0], bbox[1], bbox[2], bbox[3]}));
}

const double* first_n(const In& a, const char* name, i64 n) {
    const double* p = checked<const double>(a, name, 1);
    if ((i64)a.shape(0) < n) refuse(std::string(name) + " holds fewer than n entries");
    return p;
}

nb::tuple split_convex(const In& xs, const In& ys, const In& labels, i64 n, const In& d, double tol, i64 line_label,
                       Out& lx, Out& ly, Out& ll, Out& rx, Out& ry, Out& rl) {
    if (n < 0) refuse("n must be >= 0");
    const double* x = first_n(xs, "xs", n);
    const double* y = first_n(ys, "ys", n);
    const i64* lab = checked<const i64>(labels, "labels", 1);
    if ((i64)labels.shape(0) < n) refuse("labels holds fewer than n entries");
    const double* dd = first_n(d, "d", n);
    std::vector<double> bx(2 * n + 2), by(2 * n + 2), cx(2 * n + 2), cy(2 * n + 2);
    std::vector<i64> bl(2 * n + 2), cl(2 * n + 2);
    auto [nl, nr] = wa::split_convex(x, y, lab, n, dd, tol, line_label, bx.data(), by.data(), bl.data(), cx.data(),
                                     cy.data(), cl.data());
    double* outs_f[4] = {checked<double>(lx, "lx", 1), checked<double>(ly, "ly", 1), checked<double>(rx, "rx", 1),
                         checked<double>(ry, "ry", 1)};
    i64* outs_i[2] = {checked<i64>(ll, "ll", 1), checked<i64>(rl, "rl", 1)};
    if ((i64)lx.shape(0) < nl || (i64)ly.shape(0) < nl || (i64)ll.shape(0) < nl || (i64)rx.shape(0) < nr ||
        (i64)ry.shape(0) < nr || (i64)rl.shape(0) < nr)
        refuse("the output rows are too short for the parts (" + std::to_string(nl) + " and " + std::to_string(nr) +
               " vertices)");
    std::copy(bx.begin(), bx.begin() + nl, outs_f[0]);
    std::copy(by.begin(), by.begin() + nl, outs_f[1]);
    std::copy(bl.begin(), bl.begin() + nl, outs_i[0]);
    std::copy(cx.begin(), cx.begin() + nr, outs_f[2]);
    std::copy(cy.begin(), cy.begin() + nr, outs_f[3]);
    std::copy(cl.begin(), cl.begin() + nr, outs_i[1]);
    return nb::make_tuple(nl, nr);
}

double edge_line_values(const In& xs, const In& ys, i64 n, double ax, double ay, double bx, double by, Out& d) {
    if (n < 0) refuse("n must be >= 0");
    const double* x = first_n(xs, "xs", n);
    const double* y = first_n(ys, "ys", n);
    double* dd = checked<double>(d, "d", 1);
    if ((i64)d.shape(0) < n) refuse("d holds fewer than n entries");
    return wa::edge_line_values(x, y, n, ax, ay, bx, by, dd);
}

double plane_line_values(const In& xs, const In& ys, i64 n, double a, double b, double c, Out& d) {
    if (n < 0) refuse("n must be >= 0");
    const double* x = first_n(xs, "xs", n);
    const double* y = first_n(ys, "ys", n);
    double* dd = checked<double>(d, "d", 1);
    if ((i64)d.shape(0) < n) refuse("d holds fewer than n entries");
    return wa::plane_line_values(x, y, n, a, b, c, dd);
}

nb::tuple vertex_sides(const In& d, i64 n, double tol) {
    if (n < 0) refuse("n must be >= 0");
    auto [below, above] = wa::vertex_sides(first_n(d, "d", n), n, tol);
    return nb::make_tuple(below, above);
}

int separation(const In& sxs, const In& sys, const In& cxs, const In& cys, double eps) {
    const double* sx = checked<const double>(sxs, "subject xs", 1);
    i64 ns = (i64)sxs.shape(0);
    const double* sy = checked<const double>(sys, "subject ys", 1, {ns});
    const double* cx = checked<const double>(cxs, "clip xs", 1);
    i64 nc = (i64)cxs.shape(0);
    const double* cy = checked<const double>(cys, "clip ys", 1, {nc});
    return wa::separation(sx, sy, ns, cx, cy, nc, eps);
}

}  // namespace

NB_MODULE(weiler_atherton_testing, m) {
    m.doc() = "The Weiler-Atherton solver's inner pieces, for the tests";
    m.attr("OUTSIDE") = wa::OUTSIDE;
    m.attr("INSIDE") = wa::INSIDE;
    m.def("half_plane", &half_plane, "a"_a, "b"_a, "c"_a, "bbox"_a,
          "The part a x + b y + c <= 0 of the box grown by one unit, its edge along the line labelled EDGE_CROSSING.");
    m.def("split_convex", &split_convex, "xs"_a, "ys"_a, "labels"_a, "n"_a, "d"_a, "tol"_a, "line_label"_a, "lx"_a,
          "ly"_a, "ll"_a, "rx"_a, "ry"_a, "rl"_a, "Split a convex contour by a line.");
    m.def("edge_line_values", &edge_line_values, "xs"_a, "ys"_a, "n"_a, "ax"_a, "ay"_a, "bx"_a, "by"_a, "d"_a);
    m.def("plane_line_values", &plane_line_values, "xs"_a, "ys"_a, "n"_a, "a"_a, "b"_a, "c"_a, "d"_a);
    m.def("vertex_sides", &vertex_sides, "d"_a, "n"_a, "tol"_a);
    m.def("separation", &separation, "sx"_a, "sy"_a, "cx"_a, "cy"_a, "eps"_a,
          "OUTSIDE, INSIDE or 0: a piece's place against a convex clip contour, decided without clipping.");
}
