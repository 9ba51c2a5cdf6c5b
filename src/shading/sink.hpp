// ShadeSink: a Catmull kernel sink (src/catmull/sink.hpp's protocol) that integrates the
// Phong shade exactly over every visible piece it is given, into rgb, specular, error
// bound and evaluation-count images. Flat polygons and the background contribute their
// colour times the piece's area. Each (pixel, polygon) takes its exponent and ks from the
// fragment table (the clamped material of a specular method, per visible polygon per pixel).
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/geometry.hpp"
#include "shading/quadrature.hpp"

namespace aaeval::shading {

struct Material {
    int64_t n_polys;
    const double* G;       // n x 9
    const double* planes;  // n x 3
    const double* color;   // (n + 1) x 3, the background last
    const double* ka;
    const double* kd;
    const uint8_t* shaded;
    bool point_light;
    const double* light;
    // fragment table: the pixel's rows frag_offset[p] .. frag_offset[p + 1)
    const int64_t* frag_offset;
    const int64_t* frag_src;
    const double* frag_n;
    const double* frag_ks;
    double tol;  // error per unit area a triangle is refined to
};

struct Images {
    double* rgb;    // pixels x 3
    double* spec;   // pixels
    double* bound;  // pixels
    double* evals;  // pixels
};

struct ShadeSink {
    static constexpr bool SIGNED_PIECES = false;
    static constexpr bool COLUMN_PARTS = false;
    const Material& M;
    Images out;
    // the current pixel's pieces so far (for emit_rest): their outlines, or an area alone
    int64_t pixel = -1;
    std::vector<double> px, py;
    std::vector<int64_t> piece_start, piece_n;
    std::vector<double> piece_area;
    double covered = 0.0;

    ShadeSink(const Material& m, Images o) : M(m), out(o) {}

    const double* color(int64_t s) const { return M.color + 3 * (s < 0 ? M.n_polys : s); }
    bool is_shaded(int64_t s) const { return s >= 0 && M.shaded[s]; }

    Shade shade_of(int64_t p, int64_t s) const {
        double n = 0.0, ks = 0.0;
        for (int64_t r = M.frag_offset[p]; r < M.frag_offset[p + 1]; ++r)
            if (M.frag_src[r] == s) {
                n = M.frag_n[r];
                ks = M.frag_ks[r];
                break;
            }
        const double sigma = n > 0.0 ? 0.5 / std::sqrt(n) : std::numeric_limits<double>::infinity();
        Shade sh;
        for (int i = 0; i < 9; ++i) sh.G[i] = M.G[9 * s + i];
        for (int i = 0; i < 3; ++i) {
            sh.plane[i] = M.planes[3 * s + i];
            sh.light[i] = M.light[i];
        }
        sh.point_light = M.point_light;
        sh.n = n;
        sh.ks = ks;
        sh.sigma = sigma;
        return sh;
    }
    double diffuse_weight(int64_t s) const {
        const double* c = color(s);
        return M.kd[s] * std::fmax(std::fmax(std::fabs(c[0]), std::fabs(c[1])), std::fabs(c[2]));
    }

    void start_pixel(int64_t p) {
        if (p == pixel) return;
        pixel = p;
        px.clear();
        py.clear();
        piece_start.clear();
        piece_n.clear();
        piece_area.clear();
        covered = 0.0;
    }
    void add(int64_t p, int64_t s, double area, const Integral& I) {
        const double* c = color(s);
        if (!is_shaded(s)) {
            for (int ch = 0; ch < 3; ++ch) out.rgb[3 * p + ch] += area * c[ch];
            return;
        }
        for (int ch = 0; ch < 3; ++ch)
            out.rgb[3 * p + ch] += c[ch] * (M.ka[s] * area + M.kd[s] * I.value.diffuse) + I.value.spec;
        out.spec[p] += I.value.spec;
        out.bound[p] += I.bound;
        out.evals[p] += double(I.evals);
    }
    void remember(const double* xs, const double* ys, int64_t start, int64_t n, double area) {
        piece_start.push_back(int64_t(px.size()));
        piece_n.push_back(n);
        piece_area.push_back(area);
        for (int64_t i = start; i < start + n; ++i) {
            px.push_back(xs[i]);
            py.push_back(ys[i]);
        }
        covered += area;
    }
    // polygon s's shade over the square [x0, x0 + 1] x [y0, y0 + 1], as two triangles
    Integral square(int64_t p, int64_t s, double x0, double y0) const {
        Integral I;
        if (!is_shaded(s)) return I;
        const Shade sh = shade_of(p, s);
        const double w = diffuse_weight(s);
        integrate_triangle(sh, {x0, y0, x0 + 1.0, y0, x0 + 1.0, y0 + 1.0}, w, M.tol, I);
        integrate_triangle(sh, {x0, y0, x0 + 1.0, y0 + 1.0, x0, y0 + 1.0}, w, M.tol, I);
        return I;
    }
    Integral piece(int64_t p, int64_t s, const double* xs, const double* ys, int64_t start, int64_t n) const {
        Integral I;
        if (is_shaded(s)) integrate_polygon(shade_of(p, s), xs, ys, start, n, diffuse_weight(s), M.tol, I);
        return I;
    }

    void emit_pixel(int64_t p, int64_t s, double x0, double y0) {
        start_pixel(p);
        add(p, s, 1.0, square(p, s, x0, y0));
        covered = 1.0;
    }
    void emit_run(int64_t row, int64_t width, int64_t c0, int64_t c1, int64_t s) {
        for (int64_t c = c0; c <= c1; ++c) emit_pixel(row * width + c, s, double(c), double(row));
    }
    void emit_piece(int64_t p, int64_t s, const double* xs, const double* ys, int64_t start, int64_t n) {
        start_pixel(p);
        const double area = geometry::signed_area(xs, ys, start, n);
        add(p, s, area, piece(p, s, xs, ys, start, n));
        remember(xs, ys, start, n, area);
    }
    void emit_strip_piece(int64_t p, int64_t s, double area, const double* xs, const double* ys, int64_t start,
                          int64_t n) {
        start_pixel(p);
        add(p, s, area, piece(p, s, xs, ys, start, n));
        remember(xs, ys, start, n, area);
    }
    // an area without its shape (a clip left nothing): shaded at the pixel centre, its
    // largest possible error added to the bound
    void emit_area(int64_t p, int64_t s, double area, double x0, double y0) {
        start_pixel(p);
        Integral I;
        if (is_shaded(s)) {
            const Shade sh = shade_of(p, s);
            const Value v = shade_at(sh, x0 + 0.5, y0 + 0.5);
            I.value = {area * v.diffuse, area * v.spec};
            I.bound = area * (diffuse_weight(s) + sh.ks);
            I.evals = 1;
        }
        add(p, s, area, I);
        piece_start.push_back(-1);
        piece_n.push_back(0);
        piece_area.push_back(area);
        covered += area;
    }
    // s over the rest of the pixel: its integral over the square less its integrals over
    // the pieces emitted for this pixel so far
    void emit_rest(int64_t p, int64_t s, double x0, double y0) {
        start_pixel(p);
        const double rest = 1.0 - covered;
        if (!(rest > 0.0)) return;
        Integral I = square(p, s, x0, y0);
        if (is_shaded(s)) {
            const Shade sh = shade_of(p, s);
            for (size_t k = 0; k < piece_n.size(); ++k) {
                Integral J;
                if (piece_start[k] >= 0) {
                    integrate_polygon(sh, px.data(), py.data(), piece_start[k], piece_n[k], diffuse_weight(s), M.tol, J);
                } else {
                    const Value v = shade_at(sh, x0 + 0.5, y0 + 0.5);
                    J.value = {piece_area[k] * v.diffuse, piece_area[k] * v.spec};
                    J.bound = piece_area[k] * (diffuse_weight(s) + sh.ks);
                }
                I.value.diffuse -= J.value.diffuse;
                I.value.spec -= J.value.spec;
                I.bound += J.bound;
                I.evals += J.evals;
            }
        }
        add(p, s, rest, I);
        covered = 1.0;
    }
};

}  // namespace aaeval::shading
