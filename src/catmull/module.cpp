// aaeval.native.catmull: the bindings of the Catmull 1978 kernel and its sinks (render.hpp
// runs them). Every input is checked first (bindings.hpp); the kernels run without the GIL,
// bands of rows on a pool of C++ threads, with the same bits for every thread count.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/geometry.hpp"
#include "common/results.hpp"
#include "catmull/bindings.hpp"
#include "catmull/render.hpp"

namespace results = aaeval::results;
using namespace aaeval::catmull;
using namespace aaeval::catmull::bindings;

namespace {

nb::tuple fragments_py(In start, In length, In x, In y, In planes, double eps_z, int64_t width, int64_t height,
                       bool jagged, bool centroids, int64_t threads) {
    SortedPolygons P = polygons(start, length, x, y, planes);
    check_eps(eps_z);
    check_size(width, height, 8);
    check_threads(threads);
    FragmentSink f;
    {
        nb::gil_scoped_release release;
        f = fragments(P, eps_z, width, height, jagged, centroids, threads);
    }
    const size_t n = f.pix.size();
    return nb::make_tuple(results::from_vector(std::move(f.pix), {n}), results::from_vector(std::move(f.src), {n}),
                          results::from_vector(std::move(f.area), {n}), results::from_vector(std::move(f.cx), {n}),
                          results::from_vector(std::move(f.cy), {n}));
}

nb::ndarray<nb::numpy, double> render_flat_py(In start, In length, In x, In y, In planes, In colors, double eps_z,
                                              int64_t width, int64_t height, bool jagged, int64_t threads) {
    SortedPolygons P = polygons(start, length, x, y, planes);
    const double* c = colors_of(colors, P.n);
    check_eps(eps_z);
    check_size(width, height, 3);
    check_threads(threads);
    double* image = nullptr;  // not cleared: the sweep writes every pixel (render_flat)
    auto array = results::new_array<double>({size_t(height), size_t(width), 3}, image, false);
    {
        nb::gil_scoped_release release;
        render_flat(P, c, eps_z, width, height, jagged, threads, image);
    }
    return array;
}

nb::ndarray<nb::numpy, double> knot_grid_sums_py(In start, In length, In x, In y, In planes, double eps_z, In colors,
                                                 int64_t width, int64_t height, int64_t kind, int64_t radius,
                                                 int64_t k, double alpha, double bias, int64_t threads) {
    SortedPolygons P = polygons(start, length, x, y, planes);
    const double* c = colors_of(colors, P.n);
    check_eps(eps_z);
    const Filter F = render_filter(filter_of(kind, radius, k, alpha, bias));
    check_size(width, height, 3 * k * k);
    check_threads(threads);
    std::vector<double> acc(size_t((height + 1) * (width + 1) * k * k * 3), 0.0);
    {
        nb::gil_scoped_release release;
        knot_grid_sums(P, c, eps_z, width, height, F, threads, acc.data());
    }
    return results::from_vector(std::move(acc), {size_t(height + 1), size_t(width + 1), size_t(k), size_t(k), 3});
}

nb::ndarray<nb::numpy, double> filter_sums_py(In start, In length, In x, In y, In planes, double eps_z, In colors,
                                              int64_t width, int64_t height, int64_t kind, int64_t radius, int64_t k,
                                              double alpha, double bias, In e, int64_t threads,
                                              std::optional<In> weights_x, std::optional<In> weights_y) {
    SortedPolygons P = polygons(start, length, x, y, planes);
    const double* c = colors_of(colors, P.n);
    check_eps(eps_z);
    const Filter F = render_filter(filter_of(kind, radius, k, alpha, bias));
    if (radius < 1) fail("radius must be at least 1");
    check_size(width, height, 3 * k * k);
    check_threads(threads);
    const double* ev = data_of<const double>(e, "e", {2 * radius, k});
    check_finite(ev, size_t(2 * radius * k), "e");
    if (weights_x.has_value() != weights_y.has_value()) fail("weights_x and weights_y come together");
    const double* wx = weights_x ? data_of<const double>(*weights_x, "weights_x", {width}) : nullptr;
    const double* wy = weights_y ? data_of<const double>(*weights_y, "weights_y", {height}) : nullptr;
    double* image = nullptr;  // every row is written whole (filter_sums)
    auto array = results::new_array<double>({size_t(height), size_t(width), 3}, image, false);
    {
        nb::gil_scoped_release release;
        filter_sums(P, c, eps_z, width, height, F, ev, radius, wx, wy, threads, image);
    }
    return array;
}

nb::ndarray<nb::numpy, double> combine_cells_py(In acc, In e, int64_t radius, int64_t width, int64_t height,
                                                int64_t threads) {
    if (radius < 1 || radius > 64) fail("radius must be between 1 and 64");
    check_threads(threads);
    if (acc.ndim() != 5) fail("acc must have 5 dimensions (H + 1, W + 1, k, k, channels)");
    const int64_t k = int64_t(acc.shape(2));
    const int64_t nch = int64_t(acc.shape(4));
    if (k < 1 || k > 64 || nch < 1 || nch > 64) fail("acc: k and channels must be between 1 and 64");
    check_size(width, height, k * k * nch);
    const double* a = data_of<const double>(acc, "acc", {height + 1, width + 1, k, k, nch});
    const double* ev = data_of<const double>(e, "e", {2 * radius, k});
    check_finite(ev, size_t(2 * radius * k), "e");
    std::vector<double> image(size_t(width * height * nch), 0.0);
    {
        nb::gil_scoped_release release;
        combine_cells(a, ev, radius, k, nch, width, height, threads, image.data());
    }
    return results::from_vector(std::move(image), {size_t(height), size_t(width), size_t(nch)});
}

void piece_integrals_py(In xs, In ys, int64_t start, int64_t n, double ox, double oy, int64_t kind, int64_t radius,
                        int64_t k, double alpha, double bias, Out out) {
    const double* x = data_of<const double>(xs, "xs", {-1});
    const double* y = data_of<const double>(ys, "ys", {int64_t(xs.shape(0))});
    const int64_t nv = int64_t(xs.shape(0));
    if (start < 0 || n < 0 || start > nv || n > nv - start) fail("the polygon is not inside the vertex arrays");
    const Filter F = filter_of(kind, radius, k, alpha, bias);
    double* o = data_of<double>(out, "out", {k, k});
    check_finite(x + start, size_t(n), "xs");
    check_finite(y + start, size_t(n), "ys");
    if (!(std::fabs(ox) <= MAX_MAGNITUDE && std::fabs(oy) <= MAX_MAGNITUDE)) fail("ox, oy must be finite");
    std::vector<double> phi(static_cast<size_t>(k)), psi(static_cast<size_t>(k));
    piece_integrals(x, y, start, n, ox, oy, F, o, phi.data(), psi.data());
}

bool column_part_integrals_py(In xs, In ys, int64_t start, int64_t n, int64_t col, double ox, double oy, int64_t kind,
                              int64_t radius, int64_t k, double alpha, double bias, Out out) {
    const double* x = data_of<const double>(xs, "xs", {-1});
    const double* y = data_of<const double>(ys, "ys", {int64_t(xs.shape(0))});
    const int64_t nv = int64_t(xs.shape(0));
    if (start < 0 || n < 0 || start > nv || n > nv - start) fail("the polygon is not inside the vertex arrays");
    Filter F = filter_of(kind, radius, k, alpha, bias);
    F.fast = true;  // the form belongs to the fast route
    double* o = data_of<double>(out, "out", {k, k});
    check_finite(x + start, size_t(n), "xs");
    check_finite(y + start, size_t(n), "ys");
    if (!(std::fabs(ox) <= MAX_MAGNITUDE && std::fabs(oy) <= MAX_MAGNITUDE)) fail("ox, oy must be finite");
    if (!(std::fabs(double(col)) <= MAX_MAGNITUDE)) fail("col out of range");
    return column_part_integrals(x, y, start, n, col, ox, oy, F, o);
}

void accumulate_rings_py(In xs, In ys, In starts, In lengths, In weights, int64_t width, int64_t height, int64_t kind,
                         int64_t radius, int64_t k, double alpha, double bias, Out acc) {
    const double* x = data_of<const double>(xs, "xs", {-1});
    const int64_t nv = int64_t(xs.shape(0));
    const double* y = data_of<const double>(ys, "ys", {nv});
    const int64_t* st = data_of<const int64_t>(starts, "starts", {-1});
    const int64_t nr = int64_t(starts.shape(0));
    const int64_t* ln = data_of<const int64_t>(lengths, "lengths", {nr});
    const double* w = data_of<const double>(weights, "weights", {nr, -1});
    const int64_t nch = int64_t(weights.shape(1));
    const Filter F = filter_of(kind, radius, k, alpha, bias);
    check_size(width, height, k * k * (nch > 0 ? nch : 1));
    double* a = data_of<double>(acc, "acc", {height + 1, width + 1, k, k, nch});
    for (int64_t r = 0; r < nr; ++r)
        if (st[r] < 0 || ln[r] < 0 || st[r] > nv || ln[r] > nv - st[r])
            fail("ring " + std::to_string(r) + " is not inside the " + std::to_string(nv) + " vertices");
    check_finite(x, size_t(nv), "xs");
    check_finite(y, size_t(nv), "ys");
    check_finite(w, size_t(nr * nch), "weights");
    nb::gil_scoped_release release;
    accumulate_rings(x, y, st, ln, nr, w, nch, width, height, F, a);
}

// The part of a polygon inside the window [x0, x1] x [y0, y1], (k, 2); k = 0 when nothing is left.
nb::ndarray<nb::numpy, double> clip_to_window_py(In xs, In ys, double x0, double y0, double x1, double y1) {
    const double* x = data_of<const double>(xs, "xs", {-1});
    const int64_t n = int64_t(xs.shape(0));
    const double* y = data_of<const double>(ys, "ys", {n});
    check_finite(x, size_t(n), "xs");
    check_finite(y, size_t(n), "ys");
    std::vector<double> xy = aaeval::geometry::clip_to_window(x, y, n, x0, y0, x1, y1);
    const size_t m = xy.size() / 2;
    return results::from_vector(std::move(xy), {m, 2});
}

}  // namespace

NB_MODULE(catmull, m) {
    m.doc() = "Catmull 1978 exact area sampling: the scanline kernel and its sinks (colour, fragments, filter "
              "moments), native (see aaeval.catmull)";
    m.attr("BAND_ROWS") = BAND_ROWS;
    m.attr("BACKGROUND") = BACKGROUND;
    m.def("fragments", &fragments_py, nb::arg("start"), nb::arg("length"), nb::arg("x"), nb::arg("y"), nb::arg("planes"),
          nb::arg("eps_z"), nb::arg("width"), nb::arg("height"), nb::arg("jagged"), nb::arg("centroids"),
          nb::arg("threads"),
          "Visible fragments (pixel, kernel polygon or -1, area, centroid x, centroid y) in pixel order.");
    m.def("render_flat", &render_flat_py, nb::arg("start"), nb::arg("length"), nb::arg("x"), nb::arg("y"),
          nb::arg("planes"), nb::arg("colors"), nb::arg("eps_z"), nb::arg("width"), nb::arg("height"),
          nb::arg("jagged"), nb::arg("threads"),
          "The box-filtered flat-colour image (H, W, 3); colors: a row per kernel polygon, the background last.");
    m.def("knot_grid_sums", &knot_grid_sums_py, nb::arg("start"), nb::arg("length"), nb::arg("x"), nb::arg("y"),
          nb::arg("planes"), nb::arg("eps_z"), nb::arg("colors"), nb::arg("width"), nb::arg("height"),
          nb::arg("kind"), nb::arg("radius"), nb::arg("k"), nb::arg("alpha"), nb::arg("bias"), nb::arg("threads"),
          "Per-cell integrals (H+1, W+1, k, k, 3) of the visible colour of a scene moved by (1/2, 1/2).");
    m.def("filter_sums", &filter_sums_py, nb::arg("start"), nb::arg("length"), nb::arg("x"), nb::arg("y"),
          nb::arg("planes"), nb::arg("eps_z"), nb::arg("colors"), nb::arg("width"), nb::arg("height"),
          nb::arg("kind"), nb::arg("radius"), nb::arg("k"), nb::arg("alpha"), nb::arg("bias"), nb::arg("e"),
          nb::arg("threads"), nb::arg("weights_x") = nb::none(),
          nb::arg("weights_y") = nb::none(),
          "Pixel sums (H, W, 3) of the visible colour against a filter (e: (2R, k)), of a scene moved by (1/2, 1/2); "
          "with weights_x (W,) and weights_y (H,), each pixel divided by weights_y[j] * weights_x[i] (the film).");
    m.def("combine_cells", &combine_cells_py, nb::arg("acc"), nb::arg("e"), nb::arg("radius"), nb::arg("width"),
          nb::arg("height"), nb::arg("threads"),
          "Pixel sums (H, W, channels) from knot-cell integrals (H+1, W+1, k, k, channels); e: (2R, k).");
    m.def("piece_integrals", &piece_integrals_py, nb::arg("xs"), nb::arg("ys"), nb::arg("start"), nb::arg("n"),
          nb::arg("ox"), nb::arg("oy"), nb::arg("kind"), nb::arg("radius"), nb::arg("k"), nb::arg("alpha"),
          nb::arg("bias"), nb::arg("out"), "Integrals of the basis over one polygon inside a knot cell, into out.");
    m.def("column_part_integrals", &column_part_integrals_py, nb::arg("xs"), nb::arg("ys"), nb::arg("start"),
          nb::arg("n"), nb::arg("col"), nb::arg("ox"), nb::arg("oy"), nb::arg("kind"), nb::arg("radius"), nb::arg("k"),
          nb::arg("alpha"), nb::arg("bias"), nb::arg("out"),
          "Integrals of the basis over a polygon's part in pixel column col, into out, without cutting it out "
          "(False: the filter has no such form).");
    m.def("accumulate_rings", &accumulate_rings_py, nb::arg("xs"), nb::arg("ys"), nb::arg("starts"),
          nb::arg("lengths"), nb::arg("weights"), nb::arg("width"), nb::arg("height"), nb::arg("kind"),
          nb::arg("radius"), nb::arg("k"), nb::arg("alpha"), nb::arg("bias"), nb::arg("acc"),
          "Cut signed rings on the knot grid and add their integrals times weights to acc.");
    m.def("far_apart", [](int64_t n, int64_t threads) {
        if (n < 0 || threads < 1) fail("far_apart needs n >= 0 and threads >= 1");
        return far_apart(n, threads);
    }, nb::arg("n"), nb::arg("threads"), "The order the threads take n bands in.");
    m.def("clip_to_window", &clip_to_window_py, nb::arg("xs"), nb::arg("ys"), nb::arg("x0"), nb::arg("y0"),
          nb::arg("x1"), nb::arg("y1"), "A polygon's part inside an axis-aligned window, (k, 2).");
}
