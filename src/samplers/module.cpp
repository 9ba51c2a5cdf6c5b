// aaeval.native.samplers: the bindings of the point samplers, the A-buffer, the depth tie rule
// and the simplicity sweep line. Every input is checked here, once, before a kernel runs
// (dtype, C order, shape, lengths, index ranges, finiteness, sizes): a bad input is a
// one-line ValueError, never an out-of-bounds access. The kernels run without the GIL.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/pair.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "common/arrays.hpp"
#include "common/polygon_arrays.hpp"
#include "common/results.hpp"
#include "samplers/depth.hpp"
#include "samplers/sampling.hpp"

namespace nb = nanobind;
using namespace aaeval::samplers;

namespace {

using Array = nb::ndarray<nb::ro, nb::device::cpu>;
using OutArray = nb::ndarray<nb::numpy, double>;
using IndexArray = nb::ndarray<nb::numpy, int64_t>;

[[noreturn]] void fail(const std::string& message) { throw nb::value_error(message.c_str()); }

// The array's data after checking dtype T, ndim, C order and (where >= 0) each extent.
template <typename T>
const T* checked(const Array& x, const char* name, std::initializer_list<int64_t> shape) {
    return aaeval::arrays::checked<const T>("", x, name, shape.size(), shape);
}

void check_finite(const double* v, size_t n, const char* name) { aaeval::arrays::check_finite("", v, n, name); }

void check_size(int64_t width, int64_t height, int64_t per_pixel) {
    if (width < 0 || height < 0) fail("image size must not be negative");
    // refuse sizes whose element counts could overflow before trying to allocate them
    const double elements = static_cast<double>(width) * static_cast<double>(height) * static_cast<double>(per_pixel);
    if (width > (int64_t(1) << 31) || height > (int64_t(1) << 31) || elements > 0x1p40)
        fail("image too large: " + std::to_string(width) + " x " + std::to_string(height));
}

struct Scene {
    Polygons polygons;
    const double* colors;
    const double* background;
};

Scene checked_scene(const Array& starts, const Array& lengths, const Array& xs, const Array& ys, const Array& planes,
                    double eps_z, const Array& colors, const Array& background) {
    const Polygons P = aaeval::arrays::checked_polygons("", starts, lengths, xs, ys, planes);
    const double* c = checked<double>(colors, "colors", {P.n, 3});
    const double* bg = checked<double>(background, "background", {3});
    check_finite(c, 3 * P.n, "colors");
    check_finite(bg, 3, "background");
    if (!std::isfinite(eps_z)) fail("eps_z: expected a finite value");
    return {P, c, bg};
}

// A new zeroed numpy array of `shape`; `data` points at it (common/results.hpp).
template <typename T>
nb::ndarray<nb::numpy, T> owned(const std::vector<size_t>& shape, T*& data) {
    return aaeval::results::new_array<T>(shape, data, true);
}

// A filter profile (aaeval.filters.evaluate.profile_args) after its checks.
Profile checked_filter(int64_t fkind, double fradius, const Array& fpieces, double falpha, double fbias) {
    if (fkind != KIND_BOX && fkind != KIND_POLYNOMIAL && fkind != KIND_GAUSSIAN)
        fail("unknown filter kind " + std::to_string(fkind));
    if (!(fradius > 0.0 && fradius <= 1e6)) fail("filter radius must be in (0, 1e6]");
    if (!std::isfinite(falpha) || !std::isfinite(fbias)) fail("filter alpha and bias must be finite");
    const double* pieces = checked<double>(fpieces, "filter pieces", {-1, -1});
    const int64_t rows = static_cast<int64_t>(fpieces.shape(0)), cols = static_cast<int64_t>(fpieces.shape(1));
    check_finite(pieces, rows * cols, "filter pieces");
    if (fkind == KIND_POLYNOMIAL) {
        // |t| < radius puts floor(t) in [-ceil(radius), ceil(radius) - 1]: rows r + that
        const int64_t reach = static_cast<int64_t>(std::ceil(fradius));
        if (cols < 1 || rows / 2 - reach < 0 || rows / 2 + reach - 1 >= rows)
            fail("filter pieces: expected 2 x ceil(radius) rows of coefficients");
    }
    return Profile{fkind, fradius, pieces, rows, cols, falpha, fbias};
}

OutArray py_sample_image(int64_t width, int64_t height, const Array& starts, const Array& lengths, const Array& xs,
                         const Array& ys, const Array& planes, double eps_z, const Array& colors,
                         const Array& background, int64_t k, bool jitter, uint64_t seed, int64_t fkind, double fradius,
                         const Array& fpieces, double falpha, double fbias) {
    const Scene scene = checked_scene(starts, lengths, xs, ys, planes, eps_z, colors, background);
    if (k < 1 || k > 4096) fail("k must be in 1..4096, got " + std::to_string(k));
    check_size(width, height, 3);
    check_size(width, k * k, 2);
    const Profile filter = checked_filter(fkind, fradius, fpieces, falpha, fbias);
    double* data;
    OutArray image = owned<double>({size_t(height), size_t(width), 3}, data);
    bool ok;
    {
        nb::gil_scoped_release release;
        ok = sample_image(width, height, scene.polygons, eps_z, scene.colors, scene.background, k, jitter, seed, filter,
                          data);
    }
    if (!ok) {
        PyErr_SetString(PyExc_ZeroDivisionError, "a pixel collected no filter weight");
        throw nb::python_error();
    }
    return image;
}

OutArray py_abuffer_image(int64_t width, int64_t height, const Array& starts, const Array& lengths, const Array& xs,
                          const Array& ys, const Array& planes, double eps_z, const Array& colors,
                          const Array& background) {
    const Scene scene = checked_scene(starts, lengths, xs, ys, planes, eps_z, colors, background);
    check_size(width, height, 3);
    double* data;
    OutArray image = owned<double>({size_t(height), size_t(width), 3}, data);
    {
        nb::gil_scoped_release release;
        abuffer_image(width, height, scene.polygons, eps_z, scene.colors, scene.background, data);
    }
    return image;
}

IndexArray py_tied_latest_first(const Array& order, const Array& depth, const Array& index, double eps) {
    const int64_t* o = checked<int64_t>(order, "order", {-1});
    const int64_t n = static_cast<int64_t>(order.shape(0));
    const double* d = checked<double>(depth, "depth", {-1});
    const int64_t nd = static_cast<int64_t>(depth.shape(0));
    const int64_t* ix = checked<int64_t>(index, "index", {nd});
    for (int64_t i = 0; i < n; ++i)
        if (o[i] < 0 || o[i] >= nd) fail("order: position " + std::to_string(o[i]) + " out of range");
    int64_t* out;
    IndexArray result = owned<int64_t>({size_t(n)}, out);
    std::memcpy(out, o, sizeof(int64_t) * n);
    {
        nb::gil_scoped_release release;
        tied_latest_first(out, n, d, ix, eps);
    }
    return result;
}

OutArray py_profile_array(int64_t fkind, double fradius, const Array& fpieces, double falpha, double fbias,
                          const Array& t) {
    const Profile filter = checked_filter(fkind, fradius, fpieces, falpha, fbias);
    const double* tv = checked<double>(t, "t", {-1});
    const size_t n = t.shape(0);
    for (size_t i = 0; i < n; ++i)
        if (std::isnan(tv[i])) fail("t: expected numbers, not NaN");
    double* data;
    OutArray out = owned<double>({n}, data);
    {
        nb::gil_scoped_release release;
        profile_values(filter, tv, n, data);
    }
    return out;
}

std::pair<int64_t, int64_t> py_sweep(const Array& pts, const Array& a, const Array& b, const Array& order,
                                     const Array& incoming) {
    const double* p = checked<double>(pts, "pts", {-1, 2});
    const int64_t n = static_cast<int64_t>(pts.shape(0));
    const int64_t* pa = checked<int64_t>(a, "a", {n});
    const int64_t* pb = checked<int64_t>(b, "b", {n});
    const int64_t* po = checked<int64_t>(order, "order", {n});
    const int64_t* pi = checked<int64_t>(incoming, "incoming", {n});
    check_finite(p, 2 * n, "pts");
    std::vector<char> seen(n, 0);
    for (int64_t i = 0; i < n; ++i) {
        if (pa[i] != i) fail("a: edge e must start at vertex e");
        if (pb[i] < 0 || pb[i] >= n || po[i] < 0 || po[i] >= n || pi[i] < 0 || pi[i] >= n)
            fail("ring arrays: vertex index out of range");
        if (seen[po[i]]) fail("order: expected a permutation of the vertices");
        seen[po[i]] = 1;
    }
    for (int64_t e = 0; e < n; ++e)
        if (pi[pb[e]] != e) fail("incoming: expected the edge ending at each vertex");
    int64_t e = -1, f = -1;
    bool ok;
    {
        nb::gil_scoped_release release;
        ok = sweep(n, p, pa, pb, po, pi, e, f);
    }
    if (!ok) fail("ring arrays: not closed rings");
    return {e, f};
}

std::pair<int64_t, int64_t> py_first_meeting_pair(const Array& pts, const Array& a, const Array& b) {
    const double* p = checked<double>(pts, "pts", {-1, 2});
    const int64_t n = static_cast<int64_t>(pts.shape(0));
    const int64_t* pa = checked<int64_t>(a, "a", {n});
    const int64_t* pb = checked<int64_t>(b, "b", {n});
    check_finite(p, 2 * n, "pts");
    for (int64_t i = 0; i < n; ++i)
        if (pa[i] < 0 || pa[i] >= n || pb[i] < 0 || pb[i] >= n) fail("ring arrays: vertex index out of range");
    int64_t e = -1, f = -1;
    {
        nb::gil_scoped_release release;
        first_meeting_pair(n, p, pa, pb, e, f);
    }
    return {e, f};
}

}  // namespace

NB_MODULE(samplers, m) {
    m.doc() = "Point samplers, A-buffer, depth tie rule and simplicity sweep of aaeval (C++17).";
    m.def("sample_image", &py_sample_image, nb::arg("width"), nb::arg("height"), nb::arg("starts"), nb::arg("lengths"),
          nb::arg("xs"), nb::arg("ys"), nb::arg("planes"), nb::arg("eps_z"), nb::arg("colors"), nb::arg("background"),
          nb::arg("k"), nb::arg("jitter"), nb::arg("seed"), nb::arg("fkind"), nb::arg("fradius"), nb::arg("fpieces"),
          nb::arg("falpha"), nb::arg("fbias"),
          "Filtered image (height, width, 3) from k x k point samples per pixel (regular grid or jittered).");
    m.def("abuffer_image", &py_abuffer_image, nb::arg("width"), nb::arg("height"), nb::arg("starts"),
          nb::arg("lengths"), nb::arg("xs"), nb::arg("ys"), nb::arg("planes"), nb::arg("eps_z"), nb::arg("colors"),
          nb::arg("background"), "The A-buffer image (height, width, 3) of the polygons (file order).");
    m.def("tied_latest_first", &py_tied_latest_first, nb::arg("order"), nb::arg("depth"), nb::arg("index"),
          nb::arg("eps"),
          "A copy of order (positions sorted front to back on depth) with each run within eps of its "
          "nearest depth listed latest index first.");
    m.def("sweep", &py_sweep, nb::arg("pts"), nb::arg("a"), nb::arg("b"), nb::arg("order"), nb::arg("incoming"),
          "Shamos-Hoey sweep over the ring edges (a[e], b[e]): two edges that meet, or (-1, -1).");
    m.def("first_meeting_pair", &py_first_meeting_pair, nb::arg("pts"), nb::arg("a"), nb::arg("b"),
          "The first pair of ring edges (a[e], b[e]), e < f in order, that meet, or (-1, -1).");
    m.def("profile_array", &py_profile_array, nb::arg("fkind"), nb::arg("fradius"), nb::arg("fpieces"),
          nb::arg("falpha"), nb::arg("fbias"), nb::arg("t"),
          "k(t) of a filter profile (the samplers' splat weight) at every t of a flat float64 array.");
}
