// aaeval.native.catmull: the Catmull 1978 kernel (strips.hpp, buckets.hpp, sweep.hpp,
// integrator.hpp) with its sinks (sink.hpp, moments.hpp), bound with nanobind.
//
// Every input is checked here, once, before any kernel runs: dtypes, shapes, C order,
// polygon records inside the vertex arrays, finite coordinates and sizes; a bad input is a
// ValueError, never a read out of bounds. The kernels run without the GIL, bands of rows on
// a pool of C++ threads (bands.hpp), with the same bits for every thread count.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "common/arrays.hpp"
#include "common/polygon_arrays.hpp"
#include "common/results.hpp"
#include "catmull/bands.hpp"
#include "catmull/moments.hpp"
#include "catmull/sink.hpp"
#include "catmull/sweep.hpp"

namespace nb = nanobind;
namespace results = aaeval::results;
using namespace aaeval::catmull;

namespace {

using In = nb::ndarray<nb::ro, nb::device::cpu>;
using Out = nb::ndarray<nb::device::cpu>;

using aaeval::arrays::MAX_MAGNITUDE;
// pixels (times channels, times basis functions) an image may have
constexpr int64_t MAX_ENTRIES = int64_t(1) << 34;

[[noreturn]] void fail(const std::string& msg) { throw nb::value_error(("catmull: " + msg).c_str()); }

// the array's data after checking dtype, dimensions, C order and (where >= 0) the shape
template <class T, class A>
T* data_of(A& a, const char* name, std::initializer_list<int64_t> shape) {
    return aaeval::arrays::checked<T>("catmull", a, name, shape.size(), shape);
}

void check_finite(const double* v, size_t n, const char* name) {
    aaeval::arrays::check_finite("catmull", v, n, name, MAX_MAGNITUDE, "1e100");
}

void check_size(int64_t width, int64_t height, int64_t per_pixel) {
    if (width < 0 || height < 0) fail("image size must not be negative");
    if (width > MAX_ENTRIES || height > MAX_ENTRIES || (width + 1) * (height + 1) > MAX_ENTRIES / per_pixel)
        fail("image too large: " + std::to_string(width) + " x " + std::to_string(height));
}

void check_threads(int64_t threads) {
    if (threads < 1 || threads > 4096) fail("threads must be between 1 and 4096");
}

// The kernel polygons, checked (common/polygon_arrays.hpp), to be sorted on their first row.
SortedPolygons polygons(In& start, In& length, In& x, In& y, In& planes) {
    return SortedPolygons{aaeval::arrays::checked_polygons("catmull", start, length, x, y, planes)};
}

double check_eps(double eps_z) {
    if (!(eps_z >= 0.0 && eps_z <= MAX_MAGNITUDE)) fail("eps_z must be finite and not negative");
    return eps_z;
}

const double* colors_of(In& colors, int64_t n_polys) {
    const double* c = data_of<const double>(colors, "colors", {n_polys + 1, 3});
    check_finite(c, size_t(3 * (n_polys + 1)), "colors");
    return c;
}

Filter filter_of(int64_t kind, int64_t radius, int64_t k, double alpha, double bias) {
    if (kind != KIND_POLYNOMIAL && kind != KIND_GAUSSIAN) fail("kind must be 1 (polynomial) or 2 (Gaussian)");
    if (k < 1 || k > 64) fail("k (basis functions per axis) must be between 1 and 64");
    if (radius < 0 || radius > 64) fail("radius must be between 0 and 64");
    if (!std::isfinite(bias) || !std::isfinite(alpha)) fail("alpha and bias must be finite");
    if (kind == KIND_GAUSSIAN && !(alpha < 0.0)) fail("a Gaussian's alpha must be negative");
    return {kind, radius, k, alpha, bias};
}

// The filter as a render takes it (Filter.fast): the tent's integrals in closed form, a
// cubic's edge nodes four at a time and the Gaussian's basis as polynomials (gauss_table).
Filter render_filter(Filter F) {
    F.fast = true;
    if (F.kind == KIND_GAUSSIAN && F.k == 4 && F.radius == 2)
        F.gauss = std::make_shared<const GaussTable>(gauss_table(F.alpha, F.bias));
    return F;
}


template <class T>
std::vector<T> concat(std::vector<FragmentSink>& sinks, std::vector<T> FragmentSink::*field) {
    size_t n = 0;
    for (FragmentSink& s : sinks) n += (s.*field).size();
    std::vector<T> out;
    out.reserve(n);
    for (FragmentSink& s : sinks) {
        out.insert(out.end(), (s.*field).begin(), (s.*field).end());
        std::vector<T>().swap(s.*field);
    }
    return out;
}

nb::tuple fragments(In start, In length, In x, In y, In planes, double eps_z, int64_t width, int64_t height,
                    bool jagged, bool centroids, int64_t threads) {
    SortedPolygons P = polygons(start, length, x, y, planes);
    check_eps(eps_z);
    check_size(width, height, 8);
    check_threads(threads);
    std::vector<FragmentSink> sinks;
    {
        nb::gil_scoped_release release;
        sort_polygons(P);
        sinks.resize(size_t((height + BAND_ROWS - 1) / BAND_ROWS));
        run_bands(height, threads, [&](int64_t i, int64_t r0, int64_t r1) {
            FragmentSink& out = sinks[size_t(i)];
            const size_t cap = size_t((r1 - r0) * width + 16);
            out.pix.reserve(cap);
            out.src.reserve(cap);
            out.area.reserve(cap);
            out.cx.reserve(cap);
            out.cy.reserve(cap);
            scan_rows(P, width, r0, r1, eps_z, jagged, centroids, out);
        });
    }
    std::vector<int64_t> pix = concat(sinks, &FragmentSink::pix);
    std::vector<int64_t> src = concat(sinks, &FragmentSink::src);
    std::vector<double> area = concat(sinks, &FragmentSink::area);
    std::vector<double> cx = concat(sinks, &FragmentSink::cx);
    std::vector<double> cy = concat(sinks, &FragmentSink::cy);
    const size_t n = pix.size();
    return nb::make_tuple(results::from_vector(std::move(pix), {n}), results::from_vector(std::move(src), {n}),
                          results::from_vector(std::move(area), {n}), results::from_vector(std::move(cx), {n}),
                          results::from_vector(std::move(cy), {n}));
}

nb::ndarray<nb::numpy, double> render_flat(In start, In length, In x, In y, In planes, In colors, double eps_z,
                                           int64_t width, int64_t height, bool jagged, int64_t threads) {
    SortedPolygons P = polygons(start, length, x, y, planes);
    const double* c = colors_of(colors, P.n);
    check_eps(eps_z);
    check_size(width, height, 3);
    check_threads(threads);
    // Never cleared: the row sweep writes every pixel of a band's rows once (a run, a whole
    // pixel or a flushed sum), on the band's own thread, so the pages of a large new image
    // are first touched in parallel (100 MB at 2048x2048) and no pass clears what the sweep
    // then overwrites (tests/catmull/test_catmull_native.py fills the image with NaN first to check).
    double* image = nullptr;
    auto array = results::new_array<double>({size_t(height), size_t(width), 3}, image, false);
    {
        nb::gil_scoped_release release;
        sort_polygons(P);
        run_bands(height, threads, [&](int64_t, int64_t r0, int64_t r1) {
            ColorSink out(image, c, P.n + 1);
            scan_rows(P, width, r0, r1, eps_z, jagged, false, out);
            out.flush();
        });
    }
    return array;
}

nb::ndarray<nb::numpy, double> knot_grid_sums(In start, In length, In x, In y, In planes, double eps_z, In colors,
                                              int64_t width, int64_t height, int64_t kind, int64_t radius, int64_t k,
                                              double alpha, double bias, int64_t threads) {
    SortedPolygons P = polygons(start, length, x, y, planes);
    const double* c = colors_of(colors, P.n);
    check_eps(eps_z);
    const Filter F = render_filter(filter_of(kind, radius, k, alpha, bias));
    check_size(width, height, 3 * k * k);
    check_threads(threads);
    std::vector<double> acc(size_t((height + 1) * (width + 1) * k * k * 3), 0.0);
    {
        nb::gil_scoped_release release;
        sort_polygons(P);
        // the scene moved by (1/2, 1/2) at (W + 1) x (H + 1) pixels: the knot cells
        run_bands(height + 1, threads, [&](int64_t, int64_t r0, int64_t r1) {
            MomentSink out(acc.data(), c, P.n + 1, width, height, F);
            scan_rows(P, width + 1, r0, r1, eps_z, false, true, out);
        });
    }
    return results::from_vector(std::move(acc), {size_t(height + 1), size_t(width + 1), size_t(k), size_t(k), 3});
}

// The film's division, in place on pixel rows j0 .. j1 of image (H, W, 3): each pixel by the
// filter weight it collects inside the image, weights_y[j] * weights_x[i] (as numpy's
// sums / (wy[:, None] * wx[None, :])[..., None] rounds it: the product, then the quotient).
void divide_by_weights(double* image, const double* wx, const double* wy, int64_t width, int64_t j0, int64_t j1) {
    for (int64_t j = j0; j < j1; ++j)
        for (int64_t i = 0; i < width; ++i) {
            const double d = wy[j] * wx[i];
            double* px = image + (j * width + i) * 3;
            px[0] = px[0] / d;
            px[1] = px[1] / d;
            px[2] = px[2] / d;
        }
}

// The pixel sums (H, W, 3) of an exact filter: the kernel's cells contracted along x row by
// row inside the sink (no (H + 1, W + 1, k, k, 3) array), then along y; the same bits as
// combine_cells(knot_grid_sums(...)). e: (2R, k), the filter's cell-local coefficients.
nb::ndarray<nb::numpy, double> filter_sums(In start, In length, In x, In y, In planes, double eps_z, In colors,
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
    // tx is not cleared up front: the sink writes every row it reaches whole (flush), and
    // the rows it never reached are cleared after the kernel
    const size_t row_len = size_t(width * k * 3);
    // (a temporary: malloc hands back the block the last render freed, already mapped,
    // where huge pages would be mapped and zeroed afresh: 5% of a cubic's render at 512 x 512)
    std::unique_ptr<double[]> tx_store(new double[size_t(height + 1) * row_len + 1]);
    double* tx = tx_store.get();
    std::vector<uint8_t> written(size_t(height + 1), 0);
    double* image = nullptr;  // every row is written whole (contract_y_rows)
    auto array = results::new_array<double>({size_t(height), size_t(width), 3}, image, false);
    {
        nb::gil_scoped_release release;
        sort_polygons(P);
        // the scene moved by (1/2, 1/2) at (W + 1) x (H + 1) pixels: the knot cells
        run_bands(height + 1, threads, [&](int64_t, int64_t r0, int64_t r1) {
            MomentSink out(nullptr, c, P.n + 1, width, height, F);
            out.rows_to(tx, ev, radius);
            out.written = written.data();
            scan_rows(P, width + 1, r0, r1, eps_z, false, true, out);
            out.flush();
        });
        for (int64_t n = 0; n <= height; ++n)
            if (!written[size_t(n)]) std::fill(tx + n * int64_t(row_len), tx + (n + 1) * int64_t(row_len), 0.0);
        run_bands(height, threads, [&](int64_t, int64_t j0, int64_t j1) {
            contract_y_rows(tx, 0, height, ev, radius, k, 3, width, j0, j1, image);
            if (wx != nullptr) divide_by_weights(image, wx, wy, width, j0, j1);
        });
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
        run_bands(height, threads, [&](int64_t, int64_t j0, int64_t j1) {
            std::vector<double> tx;
            combine_rows(a, ev, radius, k, nch, width, height, j0, j1, image.data(), tx);
        });
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

}  // namespace

void bind_stages(nb::module_& m);

namespace {

// The part of a polygon inside the window [x0, x1] x [y0, y1]: clip_side against its four
// sides in turn (inside: side A of -x + x0, x - x1, -y + y0, y - y1); (k, 2), k = 0 when
// nothing is left.
nb::ndarray<nb::numpy, double> clip_to_window(In xs, In ys, double x0, double y0, double x1, double y1) {
    const double* x = data_of<const double>(xs, "xs", {-1});
    const int64_t n = int64_t(xs.shape(0));
    const double* y = data_of<const double>(ys, "ys", {n});
    check_finite(x, size_t(n), "xs");
    check_finite(y, size_t(n), "ys");
    const double lines[4][3] = {{-1.0, 0.0, x0}, {1.0, 0.0, -x1}, {0.0, -1.0, y0}, {0.0, 1.0, -y1}};
    std::vector<double> cx(x, x + n), cy(y, y + n);
    std::vector<uint8_t> cf(size_t(n), 0);
    int64_t m = n;
    for (const auto& l : lines) {
        const int64_t size = 2 * m + 4;
        std::vector<double> ox(static_cast<size_t>(size)), oy(static_cast<size_t>(size));
        std::vector<uint8_t> of(static_cast<size_t>(size));
        m = aaeval::geometry::clip_side(cx.data(), cy.data(), cf.data(), 0, m, l[0], l[1], l[2], -1, ox.data(),
                                        oy.data(), of.data(), 0);
        if (m == 0) return results::from_vector(std::vector<double>(), {0, 2});
        cx.swap(ox);
        cy.swap(oy);
        cf.swap(of);
    }
    std::vector<double> out(size_t(2 * m));
    for (int64_t i = 0; i < m; ++i) {
        out[size_t(2 * i)] = cx[size_t(i)];
        out[size_t(2 * i + 1)] = cy[size_t(i)];
    }
    return results::from_vector(std::move(out), {size_t(m), 2});
}

}  // namespace

#include "catmull/stages_py.hpp"

NB_MODULE(catmull, m) {
    m.doc() = "Catmull 1978 exact area sampling: the scanline kernel and its sinks (colour, fragments, filter "
              "moments), native (see aaeval.catmull)";
    m.attr("BAND_ROWS") = BAND_ROWS;
    m.attr("BACKGROUND") = BACKGROUND;
    m.def("fragments", &fragments, nb::arg("start"), nb::arg("length"), nb::arg("x"), nb::arg("y"), nb::arg("planes"),
          nb::arg("eps_z"), nb::arg("width"), nb::arg("height"), nb::arg("jagged"), nb::arg("centroids"),
          nb::arg("threads"),
          "Visible fragments (pixel, kernel polygon or -1, area, centroid x, centroid y) in pixel order.");
    m.def("render_flat", &render_flat, nb::arg("start"), nb::arg("length"), nb::arg("x"), nb::arg("y"),
          nb::arg("planes"), nb::arg("colors"), nb::arg("eps_z"), nb::arg("width"), nb::arg("height"),
          nb::arg("jagged"), nb::arg("threads"),
          "The box-filtered flat-colour image (H, W, 3); colors: a row per kernel polygon, the background last.");
    m.def("knot_grid_sums", &knot_grid_sums, nb::arg("start"), nb::arg("length"), nb::arg("x"), nb::arg("y"),
          nb::arg("planes"), nb::arg("eps_z"), nb::arg("colors"), nb::arg("width"), nb::arg("height"),
          nb::arg("kind"), nb::arg("radius"), nb::arg("k"), nb::arg("alpha"), nb::arg("bias"), nb::arg("threads"),
          "Per-cell integrals (H+1, W+1, k, k, 3) of the visible colour of a scene moved by (1/2, 1/2).");
    m.def("filter_sums", &filter_sums, nb::arg("start"), nb::arg("length"), nb::arg("x"), nb::arg("y"),
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
    m.def("clip_to_window", &clip_to_window, nb::arg("xs"), nb::arg("ys"), nb::arg("x0"), nb::arg("y0"),
          nb::arg("x1"), nb::arg("y1"), "A polygon's part inside an axis-aligned window, (k, 2).");
    nb::module_ stages = m.def_submodule("stages", "The kernel's stages one by one, for the tests.");
    bind_stages(stages);
}
