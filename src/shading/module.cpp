// aaeval.native.shading: the binding of the Phong shade integrated exactly over Catmull's
// visible pieces (render.hpp runs it; the model is phong.hpp, the quadrature quadrature.hpp).
// Inputs are checked here before any kernel runs: a bad input is a ValueError.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "common/polygon_arrays.hpp"
#include "common/results.hpp"
#include "shading/render.hpp"

namespace nb = nanobind;
namespace results = aaeval::results;
using namespace aaeval;

namespace {

using In = nb::ndarray<nb::ro, nb::device::cpu, nb::c_contig>;

[[noreturn]] void fail(const std::string& msg) { throw nb::value_error(("shading: " + msg).c_str()); }

template <class T>
const T* data_of(const In& a, const char* name, std::initializer_list<int64_t> shape) {
    if (a.dtype() != nb::dtype<T>()) fail(std::string(name) + " has the wrong dtype");
    if (a.ndim() != shape.size()) fail(std::string(name) + " has the wrong number of dimensions");
    size_t i = 0;
    for (int64_t s : shape) {
        if (s >= 0 && int64_t(a.shape(i)) != s) fail(std::string(name) + " has the wrong shape");
        ++i;
    }
    return static_cast<const T*>(a.data());
}

void check_finite(const double* v, size_t n, const char* name) {
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(v[i]) || std::fabs(v[i]) > 1e100) fail(std::string(name) + " must be finite");
}

nb::tuple render_exact_py(In start, In length, In x, In y, In planes, double eps_z, int64_t width, int64_t height,
                       In G, In colors, In ka, In kd, In shaded, bool point_light, In light, In frag_offset,
                       In frag_src, In frag_n, In frag_ks, double tol, int64_t threads) {
    catmull::SortedPolygons P{arrays::checked_polygons("shading", start, length, x, y, planes)};
    if (width < 0 || height < 0 || width > (1 << 16) || height > (1 << 16)) fail("image size out of range");
    if (threads < 1 || threads > 4096) fail("threads must be between 1 and 4096");
    if (!(eps_z >= 0.0) || !(tol > 0.0)) fail("eps_z must be >= 0 and tol > 0");
    const int64_t size = width * height;
    shading::Material M{P.n,
                        data_of<double>(G, "G", {P.n, 9}),
                        P.planes,
                        data_of<double>(colors, "colors", {P.n + 1, 3}),
                        data_of<double>(ka, "ka", {P.n}),
                        data_of<double>(kd, "kd", {P.n}),
                        data_of<uint8_t>(shaded, "shaded", {P.n}),
                        point_light,
                        data_of<double>(light, "light", {3}),
                        data_of<int64_t>(frag_offset, "frag_offset", {size + 1}),
                        nullptr,
                        nullptr,
                        nullptr,
                        tol};
    const int64_t nf = int64_t(frag_src.shape(0));
    M.frag_src = data_of<int64_t>(frag_src, "frag_src", {nf});
    M.frag_n = data_of<double>(frag_n, "frag_n", {nf});
    M.frag_ks = data_of<double>(frag_ks, "frag_ks", {nf});
    for (int64_t p = 0; p < size; ++p)
        if (M.frag_offset[p] < 0 || M.frag_offset[p] > M.frag_offset[p + 1] || M.frag_offset[p + 1] > nf)
            fail("frag_offset must be non-decreasing within the fragment table");
    for (int64_t p = 0; p < P.n; ++p)
        if (M.shaded[p]) check_finite(M.G + 9 * p, 9, "G of a shaded polygon");
    std::vector<double> rgb(size_t(3 * size), 0.0), spec(size_t(size), 0.0), bound(size_t(size), 0.0),
        evals(size_t(size), 0.0);
    {
        nb::gil_scoped_release release;
        shading::render_exact(P, M, eps_z, width, height, threads, {rgb.data(), spec.data(), bound.data(), evals.data()});
    }
    const size_t H = size_t(height), W = size_t(width);
    return nb::make_tuple(results::from_vector(std::move(rgb), {H, W, 3}), results::from_vector(std::move(spec), {H, W}),
                          results::from_vector(std::move(bound), {H, W}), results::from_vector(std::move(evals), {H, W}));
}

}  // namespace

NB_MODULE(shading, m) {
    m.doc() = "The Phong shade integrated over Catmull's visible pieces (adaptive Gauss-Legendre), native";
    m.def("render_exact", &render_exact_py, nb::arg("start"), nb::arg("length"), nb::arg("x"), nb::arg("y"),
          nb::arg("planes"), nb::arg("eps_z"), nb::arg("width"), nb::arg("height"), nb::arg("G"), nb::arg("colors"),
          nb::arg("ka"), nb::arg("kd"), nb::arg("shaded"), nb::arg("point_light"), nb::arg("light"),
          nb::arg("frag_offset"), nb::arg("frag_src"), nb::arg("frag_n"), nb::arg("frag_ks"), nb::arg("tol"),
          nb::arg("threads"),
          "(rgb (H, W, 3), specular (H, W), error bound (H, W), shade evaluations (H, W)) of the box-filtered "
          "Phong image.");
}
