// aaeval.native.catmull_testing: the kernel's stages one by one, bound for the tests alone
// (tests/catmull/test_catmull_stages.py): each stage run on the smallest input it reads,
// compared with an answer worked out by hand. Inputs are checked as the kernel's bindings
// check them (bindings.hpp).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "common/results.hpp"
#include "catmull/bindings.hpp"
#include "catmull/sink.hpp"
#include "catmull/sweep.hpp"

namespace results = aaeval::results;
using namespace aaeval::catmull;
using namespace aaeval::catmull::bindings;

namespace {

// the polygons (owned copies), one band's workspaces, and a z-list in progress
struct StageScan {
    std::vector<int64_t> start, length;
    std::vector<double> x, y, planes;
    SortedPolygons P;
    int64_t width;
    Scan sc;
    int64_t n_zl = 0;

    StageScan(const aaeval::Polygons& p, int64_t width_) : width(width_), sc(width_) {
        start.assign(p.start, p.start + p.n);
        length.assign(p.length, p.length + p.n);
        int64_t nv = 0;
        for (int64_t i = 0; i < p.n; ++i) nv = std::max(nv, p.start[i] + p.length[i]);
        x.assign(p.x, p.x + nv);
        y.assign(p.y, p.y + nv);
        planes.assign(p.planes, p.planes + 3 * p.n);
        P.n = p.n;
        P.start = start.data();
        P.length = length.data();
        P.x = x.data();
        P.y = y.data();
        P.planes = planes.data();
        sort_polygons(P);
    }
    void check_col(int64_t col) const {
        if (col < 0 || col >= width) fail("column outside the image");
    }
    void check_piece(int64_t k) const {
        if (k < 0 || k >= sc.strip.n) fail("no such strip piece");
    }
};

template <class T>
nb::ndarray<nb::numpy, T> copy_of(const std::vector<T>& v, size_t rows, size_t cols = 0) {
    std::vector<T> c(v.begin(), v.begin() + std::ptrdiff_t(cols ? rows * cols : rows));
    if (cols) return results::from_vector(std::move(c), {rows, cols});
    return results::from_vector(std::move(c), {rows});
}

nb::tuple sink_arrays(const FragmentSink& s) {
    const size_t n = s.pix.size();
    return nb::make_tuple(copy_of(s.pix, n), copy_of(s.src, n), copy_of(s.area, n), copy_of(s.cx, n),
                          copy_of(s.cy, n));
}

struct Polygon {
    std::vector<double> x, y;
};

Polygon polygon_of(In& xs, In& ys) {
    const double* x = data_of<const double>(xs, "xs", {-1});
    const int64_t n = int64_t(xs.shape(0));
    const double* y = data_of<const double>(ys, "ys", {n});
    check_finite(x, size_t(n), "xs");
    check_finite(y, size_t(n), "ys");
    return {std::vector<double>(x, x + n), std::vector<double>(y, y + n)};
}

void check_run(const Polygon& p, int64_t start, int64_t n) {
    if (start < 0 || n < 1 || start > int64_t(p.x.size()) || n > int64_t(p.x.size()) - start)
        fail("the piece is not inside the vertex arrays");
}

}  // namespace

NB_MODULE(catmull_testing, m) {
    m.doc() = "The Catmull kernel's stages one by one, for the tests (tests/catmull/test_catmull_stages.py).";
    nb::class_<StageScan>(m, "Scan", "Polygons sorted on their first scanline with one band's workspaces.")
        .def("__init__", [](StageScan* self, In start, In length, In x, In y, In planes, int64_t width) {
            check_size(width, 1, 1);
            new (self) StageScan(polygons(start, length, x, y, planes), width);
        }, nb::arg("start"), nb::arg("length"), nb::arg("x"), nb::arg("y"), nb::arg("planes"), nb::arg("width"))
        .def_prop_ro("order", [](StageScan& s) { return copy_of(s.P.order, size_t(s.P.n)); }, nb::rv_policy::automatic)
        .def_prop_ro("ymin", [](StageScan& s) { return copy_of(s.P.ymin, size_t(s.P.n)); }, nb::rv_policy::automatic)
        .def_prop_ro("ymax", [](StageScan& s) { return copy_of(s.P.ymax, size_t(s.P.n)); }, nb::rv_policy::automatic)
        .def("enter_polygons", [](StageScan& s, int64_t row) { enter_polygons(s.P, s.sc.active, row, s.sc.flags); })
        .def("clip_to_strip", [](StageScan& s, int64_t row) {
            clip_to_strip(s.sc.active, s.sc.strip, row, s.width);
            s.sc.zlist.fit(s.sc.strip.n);
        })
        .def("bucket_by_x", [](StageScan& s) {
            bucket_by_x(s.sc.strip, s.width, s.sc.fill);
            s.n_zl = 0;
        })
        .def_prop_ro("active_n", [](StageScan& s) { return s.sc.active.n; })
        .def_prop_ro("next_in", [](StageScan& s) { return s.sc.active.next_in; })
        .def_prop_ro("active_recs", [](StageScan& s) { return copy_of(s.sc.active.recs.data, size_t(s.sc.active.n), 3); }, nb::rv_policy::automatic)
        .def_prop_ro("active_x", [](StageScan& s) { return copy_of(s.sc.active.v.x, size_t(s.sc.active.used)); }, nb::rv_policy::automatic)
        .def_prop_ro("active_y", [](StageScan& s) { return copy_of(s.sc.active.v.y, size_t(s.sc.active.used)); }, nb::rv_policy::automatic)
        .def_prop_ro("strip_n", [](StageScan& s) { return s.sc.strip.n; })
        .def_prop_ro("pieces", [](StageScan& s) { return copy_of(s.sc.strip.pieces.data, size_t(s.sc.strip.n), 3); }, nb::rv_policy::automatic)
        .def_prop_ro("span", [](StageScan& s) { return copy_of(s.sc.strip.span.data, size_t(s.sc.strip.n), 3); }, nb::rv_policy::automatic)
        .def_prop_ro("cov", [](StageScan& s) { return copy_of(s.sc.strip.cov, size_t(s.sc.strip.cov_used)); }, nb::rv_policy::automatic)
        .def_prop_ro("strip_x", [](StageScan& s) { return copy_of(s.sc.strip.v.x, size_t(s.sc.strip.used)); }, nb::rv_policy::automatic)
        .def_prop_ro("strip_y", [](StageScan& s) { return copy_of(s.sc.strip.v.y, size_t(s.sc.strip.used)); }, nb::rv_policy::automatic)
        .def_prop_ro("bucket_head", [](StageScan& s) { return copy_of(s.sc.strip.bucket_head, size_t(s.width + 1)); }, nb::rv_policy::automatic)
        .def_prop_ro("bucket_items", [](StageScan& s) { return copy_of(s.sc.strip.bucket_items, size_t(s.sc.strip.n)); }, nb::rv_policy::automatic)
        .def("update_zlist", [](StageScan& s, int64_t col, int64_t row) {
            s.check_col(col);
            s.n_zl = update_zlist(s.sc.zlist.items.data(), s.sc.zlist.depth.data(), s.n_zl, s.sc.strip, s.P.planes,
                                  col, row);
            return std::vector<int64_t>(s.sc.zlist.items.begin(), s.sc.zlist.items.begin() + s.n_zl);
        }, nb::arg("col"), nb::arg("row"), "The z-list moved to column col (piece indices, front to back).")
        .def("pixel_list", [](StageScan& s, int64_t col, int64_t row, double eps_z) {
            s.check_col(col);
            const PixelList pl = pixel_list(s.sc.zlist.items.data(), s.n_zl, s.sc.zlist.pixel.data(), s.sc.strip,
                                            s.P.planes, col, row, eps_z);
            return nb::make_tuple(std::vector<int64_t>(s.sc.zlist.pixel.begin(), s.sc.zlist.pixel.begin() + pl.n),
                                  pl.solid);
        }, nb::arg("col"), nb::arg("row"), nb::arg("eps_z"), "The pixel's polygon list and its solid piece (-1: none).")
        .def("solid_run", [](StageScan& s, int64_t k, int64_t col, int64_t row) {
            s.check_col(col);
            s.check_piece(k);
            const Run r = solid_run(k, s.sc.zlist.items.data(), s.n_zl, s.sc.strip, s.P.planes, col, row, s.width);
            s.n_zl = r.n_zl;
            return nb::make_tuple(r.end, std::vector<int64_t>(s.sc.zlist.items.begin(), s.sc.zlist.items.begin() + s.n_zl));
        }, nb::arg("k"), nb::arg("col"), nb::arg("row"), "(last column of the run, the z-list after it).")
        .def("two_layer_overlap", [](StageScan& s, int64_t ka, int64_t kb, double x0) {
            s.check_piece(ka);
            s.check_piece(kb);
            PixelWork W;
            W.v.grow_to(two_layer_room(s.sc.strip.pieces[ka][1], s.sc.strip.pieces[kb][1]));
            return two_layer_overlap(s.sc.strip, ka, kb, x0, W.v.x.data(), W.v.y.data(), W.v.f.data(), W.v.size());
        }, nb::arg("ka"), nb::arg("kb"), nb::arg("x0"))
        .def("integrate", [](StageScan& s, std::vector<int64_t> plist, int64_t solid, double x0, double y0,
                             double eps_z, int64_t pix, bool tiny) {
            for (int64_t k : plist) s.check_piece(k);
            if (solid != -1) s.check_piece(solid);
            PixelWork W;
            if (tiny) {  // the smallest workspace: the integrator grows it and gives the same answer
                W.v = Verts(8);
                W.recs = Rows<int64_t, 3>(2);
                W.areas.assign(2, 0.0);
                W.items.assign(2, 0);
                W.lists = Rows<int64_t, 2>(1);
                W.stack.assign(1, 0);
                W.visible.assign(1, 0);
            }
            FragmentSink out;
            integrate(s.sc.strip, plist.data(), int64_t(plist.size()), solid, x0, y0, s.P.planes, eps_z, pix, W, out);
            return nb::make_tuple(sink_arrays(out), W.v.size());
        }, nb::arg("plist"), nb::arg("solid"), nb::arg("x0"), nb::arg("y0"), nb::arg("eps_z"), nb::arg("pix") = 0,
           nb::arg("tiny") = false, "The pixel integrator's fragments and its vertex buffer's final size.");

    m.def("strip_coverage", [](In xs, In ys, int64_t start, int64_t n, double row, int64_t c0, int64_t c1) {
        const Polygon p = polygon_of(xs, ys);
        check_run(p, start, n);
        if (c1 < c0 || c1 - c0 > MAX_ENTRIES) fail("bad column range");
        std::vector<double> cov(size_t(c1 - c0 + 1));
        strip_coverage(p.x.data(), p.y.data(), start, n, row, c0, c1, cov.data(), 0);
        return results::from_vector(std::move(cov), {size_t(c1 - c0 + 1)});
    }, nb::arg("xs"), nb::arg("ys"), nb::arg("start"), nb::arg("n"), nb::arg("row"), nb::arg("c0"), nb::arg("c1"));
    m.def("hidden_until", [](In planes, int64_t p, int64_t q, int64_t col, int64_t end, int64_t row, int64_t width) {
        const double* pl = data_of<const double>(planes, "planes", {-1, 3});
        const int64_t n = int64_t(planes.shape(0));
        if (p < 0 || q < 0 || p >= n || q >= n) fail("no such plane");
        return hidden_until(pl, p, q, col, end, row, width);
    }, nb::arg("planes"), nb::arg("p"), nb::arg("q"), nb::arg("col"), nb::arg("end"), nb::arg("row"), nb::arg("width"));

    struct PySink {
        FragmentSink s;
    };
    nb::class_<PySink>(m, "FragmentSink", "The fragments sink, driven by hand.")
        .def(nb::init<>())
        .def("emit_piece", [](PySink& k, int64_t pix, int64_t src, In xs, In ys, int64_t start, int64_t n) {
            const Polygon p = polygon_of(xs, ys);
            check_run(p, start, n);
            k.s.emit_piece(pix, src, p.x.data(), p.y.data(), start, n);
        })
        .def("emit_strip_piece", [](PySink& k, int64_t pix, int64_t src, double area, In xs, In ys, int64_t start,
                                    int64_t n) {
            const Polygon p = polygon_of(xs, ys);
            check_run(p, start, n);
            k.s.emit_strip_piece(pix, src, area, p.x.data(), p.y.data(), start, n);
        })
        .def("emit_rest", [](PySink& k, int64_t pix, int64_t src, double x0, double y0) { k.s.emit_rest(pix, src, x0, y0); })
        .def("emit_pixel", [](PySink& k, int64_t pix, int64_t src, double x0, double y0) { k.s.emit_pixel(pix, src, x0, y0); })
        .def("emit_area", [](PySink& k, int64_t pix, int64_t src, double a, double x0, double y0) {
            k.s.emit_area(pix, src, a, x0, y0);
        })
        .def("arrays", [](PySink& k) { return sink_arrays(k.s); });
}
