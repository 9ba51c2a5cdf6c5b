// What each catmull binding runs once its inputs are checked (module.cpp): the polygons
// sorted on their first row, then the kernel over bands of rows on the thread pool
// (bands.hpp) into the sink of the output asked for. The same bits for every thread count.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "catmull/bands.hpp"
#include "catmull/moments.hpp"
#include "catmull/sink.hpp"
#include "catmull/sweep.hpp"

namespace aaeval::catmull {

// The filter as a render takes it (Filter.fast): the tent's integrals in closed form, a
// cubic's edge nodes four at a time and the Gaussian's basis as polynomials (gauss_table).
inline Filter render_filter(Filter F) {
    F.fast = true;
    if (F.kind == KIND_GAUSSIAN && F.k == 4 && F.radius == 2)
        F.gauss = std::make_shared<const GaussTable>(gauss_table(F.alpha, F.bias));
    return F;
}

// The bands' fragments, one field at a time, in band (so pixel) order; each band's own
// vector is freed once copied.
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

// Visible fragments (pixel, polygon or BACKGROUND, area, centroid) in pixel order.
inline FragmentSink fragments(SortedPolygons& P, double eps_z, int64_t width, int64_t height, bool jagged,
                              bool centroids, int64_t threads) {
    sort_polygons(P);
    std::vector<FragmentSink> sinks(size_t((height + BAND_ROWS - 1) / BAND_ROWS));
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
    FragmentSink all;
    all.pix = concat(sinks, &FragmentSink::pix);
    all.src = concat(sinks, &FragmentSink::src);
    all.area = concat(sinks, &FragmentSink::area);
    all.cx = concat(sinks, &FragmentSink::cx);
    all.cy = concat(sinks, &FragmentSink::cy);
    return all;
}

// The box-filtered flat-colour image into image (H, W, 3). It need not be cleared: the row
// sweep writes every pixel of a band's rows once (a run, a whole pixel or a flushed sum), on
// the band's own thread, so the pages of a large new image are first touched in parallel
// (100 MB at 2048x2048) and no pass clears what the sweep then overwrites
// (tests/catmull/test_catmull_native.py fills the image with NaN first to check).
inline void render_flat(SortedPolygons& P, const double* colors, double eps_z, int64_t width, int64_t height,
                        bool jagged, int64_t threads, double* image) {
    sort_polygons(P);
    run_bands(height, threads, [&](int64_t, int64_t r0, int64_t r1) {
        ColorSink out(image, colors, P.n + 1);
        scan_rows(P, width, r0, r1, eps_z, jagged, false, out);
        out.flush();
    });
}

// Per-cell integrals (H + 1, W + 1, k, k, 3) of the visible colour, into acc (zeroed): the
// scene moved by (1/2, 1/2) at (W + 1) x (H + 1) pixels gives the knot cells.
inline void knot_grid_sums(SortedPolygons& P, const double* colors, double eps_z, int64_t width, int64_t height,
                           const Filter& F, int64_t threads, double* acc) {
    sort_polygons(P);
    run_bands(height + 1, threads, [&](int64_t, int64_t r0, int64_t r1) {
        MomentSink out(acc, colors, P.n + 1, width, height, F);
        scan_rows(P, width + 1, r0, r1, eps_z, false, true, out);
    });
}

// The film's division, in place on pixel rows j0 .. j1 of image (H, W, 3): each pixel by the
// filter weight it collects inside the image, weights_y[j] * weights_x[i] (as numpy's
// sums / (wy[:, None] * wx[None, :])[..., None] rounds it: the product, then the quotient).
inline void divide_by_weights(double* image, const double* wx, const double* wy, int64_t width, int64_t j0,
                              int64_t j1) {
    for (int64_t j = j0; j < j1; ++j)
        for (int64_t i = 0; i < width; ++i) {
            const double d = wy[j] * wx[i];
            double* px = image + (j * width + i) * 3;
            px[0] = px[0] / d;
            px[1] = px[1] / d;
            px[2] = px[2] / d;
        }
}

// The pixel sums (H, W, 3) of an exact filter into image (every row written whole): the
// kernel's cells contracted along x row by row inside the sink (no (H + 1, W + 1, k, k, 3)
// array), then along y; the same bits as combine_cells of knot_grid_sums. e: (2R, k), the
// filter's cell-local coefficients; wx, wy (may be null): the film's weights to divide by.
inline void filter_sums(SortedPolygons& P, const double* colors, double eps_z, int64_t width, int64_t height,
                        const Filter& F, const double* e, int64_t radius, const double* wx, const double* wy,
                        int64_t threads, double* image) {
    const int64_t k = F.k;
    // tx is not cleared up front: the sink writes every row it reaches whole (flush), and
    // the rows it never reached are cleared after the kernel
    const size_t row_len = size_t(width * k * 3);
    // (a temporary: malloc hands back the block the last render freed, already mapped,
    // where huge pages would be mapped and zeroed afresh: 5% of a cubic's render at 512 x 512)
    std::unique_ptr<double[]> tx_store(new double[size_t(height + 1) * row_len + 1]);
    double* tx = tx_store.get();
    std::vector<uint8_t> written(size_t(height + 1), 0);
    sort_polygons(P);
    run_bands(height + 1, threads, [&](int64_t, int64_t r0, int64_t r1) {
        MomentSink out(nullptr, colors, P.n + 1, width, height, F);
        out.rows_to(tx, e, radius);
        out.written = written.data();
        scan_rows(P, width + 1, r0, r1, eps_z, false, true, out);
        out.flush();
    });
    for (int64_t n = 0; n <= height; ++n)
        if (!written[size_t(n)]) std::fill(tx + n * int64_t(row_len), tx + (n + 1) * int64_t(row_len), 0.0);
    run_bands(height, threads, [&](int64_t, int64_t j0, int64_t j1) {
        contract_y_rows(tx, 0, height, e, radius, k, 3, width, j0, j1, image);
        if (wx != nullptr) divide_by_weights(image, wx, wy, width, j0, j1);
    });
}

// Pixel sums (H, W, nch) into image (zeroed) from knot-cell integrals acc (H + 1, W + 1, k, k, nch).
inline void combine_cells(const double* acc, const double* e, int64_t radius, int64_t k, int64_t nch, int64_t width,
                          int64_t height, int64_t threads, double* image) {
    run_bands(height, threads, [&](int64_t, int64_t j0, int64_t j1) {
        std::vector<double> tx;
        combine_rows(acc, e, radius, k, nch, width, height, j0, j1, image, tx);
    });
}

}  // namespace aaeval::catmull
