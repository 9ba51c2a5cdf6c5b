// The sink protocol: every result of the Catmull kernel leaves through a sink, a class given
// to the row sweep as a template parameter (compiled once per sink type). Its methods:
//
//   emit_pixel(pix, src, x0, y0)        the whole pixel square [x0, x0+1] x [y0, y0+1] is
//                                        polygon src (-1: the background)
//   emit_run(row, width, c0, c1, src)   the whole pixels c0 .. c1 of row are polygon src (a
//                                        sink without a faster way calls emit_pixel for each)
//   emit_piece(pix, src, xs, ys, start, n)
//                                        a visible piece of src inside the pixel, as the
//                                        polygon xs, ys[start .. start+n)
//   emit_strip_piece(pix, src, area, xs, ys, start, n)
//                                        a strip piece alone in front, clipped to the pixel,
//                                        with the exact area the strip coverage gave
//   emit_area(pix, src, area, x0, y0)    an area of src in the pixel without its shape (only
//                                        with centroids off, or a piece the clip left empty)
//   emit_rest(pix, src, x0, y0)          src covers the rest of the pixel: the square minus
//                                        what was emitted for this pixel so far
//   emit_signed_piece(pix, src, sign, xs, ys, start, n)
//                                        only for a sink with SIGNED_PIECES true: the
//                                        polygon counted with sign
//                                        (+1 or -1); a visible part may come as a piece less
//                                        another (two irregular pieces over what both hide:
//                                        the second's part is its piece less the overlap)
//
//   emit_column_part(pix, src, xs, ys, start, n, col) -> bool
//                                        only for a sink with COLUMN_PARTS true: a strip
//                                        piece alone in front, the polygon xs, ys[start ..
//                                        start+n) not yet cut to its pixel column col; false
//                                        when the sink wants it cut (emit_strip_piece then)
//
// SIGNED_PIECES (static): whether the sink's results are linear in the pieces, so that a
// piece less another is as good as the difference's own pieces. Sinks without it always get
// visible pieces from the integrator.
//
// A pixel's calls come together, pixels in row order. The sinks: FragmentSink (per pixel,
// each visible polygon's area and area centroid, its pieces merged), ColorSink (flat colours
// box-filtered straight into the image) and MomentSink (moments.hpp: each piece's integrals
// against a filter's basis, per knot cell).
#pragma once

#include <cstdint>
#include <vector>

#include "common/geometry.hpp"
#include "catmull/buffers.hpp"

namespace aaeval::catmull {

// Fragments: pixel, source polygon (-1: background), area, area centroid.
struct FragmentSink {
    static constexpr bool SIGNED_PIECES = false;
    static constexpr bool COLUMN_PARTS = false;
    std::vector<int64_t> pix, src;
    std::vector<double> area, cx, cy;

    void append(int64_t p, int64_t s, double a, double x, double y) {
        pix.push_back(p);
        src.push_back(s);
        area.push_back(a);
        cx.push_back(x);
        cy.push_back(y);
    }
    void emit_pixel(int64_t p, int64_t s, double x0, double y0) { append(p, s, 1.0, x0 + 0.5, y0 + 0.5); }
    void emit_run(int64_t row, int64_t width, int64_t c0, int64_t c1, int64_t s) {
        for (int64_t c = c0; c <= c1; ++c) emit_pixel(row * width + c, s, double(c), double(row));
    }
    void emit_area(int64_t p, int64_t s, double a, double x0, double y0) { append(p, s, a, x0 + 0.5, y0 + 0.5); }
    // pieces of one polygon in one pixel merge into one fragment (area-weighted centroid)
    void emit_piece(int64_t p, int64_t s, const double* xs, const double* ys, int64_t start, int64_t n) {
        const geometry::AreaCentroid ac = geometry::area_centroid(xs, ys, start, n);
        int64_t g = int64_t(pix.size()) - 1;
        while (g >= 0 && pix[size_t(g)] == p && src[size_t(g)] != s) --g;
        if (g < 0 || pix[size_t(g)] != p) {
            append(p, s, ac.area, ac.cx, ac.cy);
            return;
        }
        const size_t G = size_t(g);
        const double total = area[G] + ac.area;
        if (total > 0.0) {
            cx[G] = (cx[G] * area[G] + ac.cx * ac.area) / total;
            cy[G] = (cy[G] * area[G] + ac.cy * ac.area) / total;
        }
        area[G] = total;
    }
    // the coverage's area is kept, so fragments with and without centroids agree exactly
    void emit_strip_piece(int64_t p, int64_t s, double a, const double* xs, const double* ys, int64_t start,
                          int64_t n) {
        const geometry::AreaCentroid ac = geometry::area_centroid(xs, ys, start, n);
        append(p, s, a, ac.cx, ac.cy);
    }
    void emit_rest(int64_t p, int64_t s, double x0, double y0) {
        size_t first = pix.size();
        while (first > 0 && pix[first - 1] == p) --first;
        double covered = 0.0, mx = 0.0, my = 0.0;
        for (size_t g = first; g < pix.size(); ++g) {
            covered += area[g];
            mx += area[g] * cx[g];
            my += area[g] * cy[g];
        }
        const double rest = 1.0 - covered;
        if (rest > 0.0) append(p, s, rest, (x0 + 0.5 - mx) / rest, (y0 + 0.5 - my) / rest);
    }
};

// Box-filtered flat colours written straight into image (pixels x 3). colors holds
// n_colors rows, a polygon's colour per source, the background's last. The current pixel's
// fragments (pieces of one polygon merged) are summed into the image when the next pixel
// starts (flush), in the order a bincount over FragmentSink fragments adds them: both give the
// same bits.
struct ColorSink {
    static constexpr bool SIGNED_PIECES = false;
    static constexpr bool COLUMN_PARTS = false;
    double* image;
    const double* colors;
    int64_t n_colors;
    int64_t pixel = -1;
    std::vector<int64_t> src;
    std::vector<double> area;
    int64_t n = 0;

    // src, area: the current pixel's sources, grown as a pixel needs (not one per colour:
    // every band would clear that many)
    ColorSink(double* image_, const double* colors_, int64_t n_colors_)
        : image(image_), colors(colors_), n_colors(n_colors_), src(16), area(16) {}

    const double* color(int64_t s) const { return colors + 3 * (s < 0 ? n_colors + s : s); }

    void flush() {
        if (n == 0) return;
        for (int ch = 0; ch < 3; ++ch) {
            double acc = 0.0;
            for (int64_t g = 0; g < n; ++g) acc += area[size_t(g)] * color(src[size_t(g)])[ch];
            image[3 * pixel + ch] = acc;
        }
        n = 0;
    }
    void add(int64_t p, int64_t s, double a) {
        if (p != pixel) {
            flush();
            pixel = p;
        }
        int64_t g = 0;
        while (g < n && src[size_t(g)] != s) ++g;
        if (g < n) {
            area[size_t(g)] = area[size_t(g)] + a;
        } else {
            if (n == int64_t(src.size())) {
                grow(src, n + 1);
                grow(area, n + 1);
            }
            src[size_t(n)] = s;
            area[size_t(n)] = a;
            ++n;
        }
    }
    void emit_pixel(int64_t p, int64_t s, double, double) {
        if (n > 0) flush();
        pixel = p;
        const double* c = color(s);
        for (int ch = 0; ch < 3; ++ch) image[3 * p + ch] = 1.0 * c[ch];
    }
    void emit_run(int64_t row, int64_t width, int64_t c0, int64_t c1, int64_t s) {
        if (c1 < c0) return;
        const int64_t p0 = row * width + c0;
        const int64_t count = c1 - c0 + 1;
        if (n > 0) flush();
        pixel = p0 + count - 1;
        const double* c = color(s);
        const double r = 1.0 * c[0], g = 1.0 * c[1], b = 1.0 * c[2];
        for (int64_t p = p0; p < p0 + count; ++p) {
            image[3 * p] = r;
            image[3 * p + 1] = g;
            image[3 * p + 2] = b;
        }
    }
    void emit_piece(int64_t p, int64_t s, const double* xs, const double* ys, int64_t start, int64_t m) {
        add(p, s, geometry::signed_area(xs, ys, start, m));
    }
    void emit_strip_piece(int64_t p, int64_t s, double a, const double*, const double*, int64_t, int64_t) {
        add(p, s, a);
    }
    void emit_area(int64_t p, int64_t s, double a, double, double) { add(p, s, a); }
    void emit_rest(int64_t p, int64_t s, double, double) {
        double covered = 0.0;
        if (p == pixel)
            for (int64_t g = 0; g < n; ++g) covered += area[size_t(g)];
        const double rest = 1.0 - covered;
        if (rest > 0.0) add(p, s, rest);
    }
};

}  // namespace aaeval::catmull
