// MomentSink, the Catmull kernel's sink for an exact filter: every visible piece's
// integrals (edge_integrals.hpp) times its colour, per knot cell, contracted row by row
// into pixels (contraction.hpp) when the caller asks for rows.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "common/geometry.hpp"
#include "catmull/contraction.hpp"
#include "catmull/edge_integrals.hpp"
#include "catmull/knot_grid.hpp"

namespace aaeval::catmull {

// The Catmull kernel's sink for an exact filter. The kernel runs on the scene moved by
// (1/2, 1/2) at (W + 1) x (H + 1) pixels, which are exactly the knot cells, so every visible
// piece lies in one cell; its integrals times its colour go to acc[n, m, a, b, channel].
// Cells on the image border are cut to the image first (samples lie only inside it).
// colors: n_colors rows (the background last); `emitted` holds what the current cell has
// received (for emit_rest). One sink per band: bands write disjoint rows of acc.
struct MomentSink {
    // integrals are linear in the pieces: a visible part may come as a piece less another
    // (sweep.hpp's two-layer case)
    static constexpr bool SIGNED_PIECES = true;
    static constexpr bool COLUMN_PARTS = true;
    double* acc;
    const double* colors;
    int64_t n_colors, width, height;
    Filter F;
    std::vector<double> out, emitted, phi, psi;
    int64_t pix = -1;
    BoxBuffers box;
    double sx[4], sy[4];
    std::vector<double> inner_integrals, done;
    bool have_inner = false;
    SidePhi sides;
    // row mode (rows_to): the current cell row's integrals in rowacc, contracted along x
    // (contract_x_row) into tx's row when the next row starts and at flush
    double* tx = nullptr;
    const double* e = nullptr;
    int64_t R = 0, cur_row = -1;
    std::vector<double> rowacc;
    uint8_t* written = nullptr;  // row mode: written[row] = 1 once the row is in tx
    // row mode: an interior cell whose one emission is a whole cell of one colour is only
    // marked (full[col] = its colour's row in colors, else NONE); its terms for the x
    // contraction are the same for every such cell of that colour (the same inputs, so
    // the same bits), found once per colour in a small cache (terms: 2R x k x 3 per slot)
    static constexpr int64_t NONE = -1;
    static constexpr int64_t SLOTS = 64;
    std::vector<int64_t> full, slot_key, touched;  // touched: columns add wrote in this row
    std::vector<double> slot_terms, cellbuf, fullbuf;
    bool identity = false;

    MomentSink(double* acc_, const double* colors_, int64_t n_colors_, int64_t width_, int64_t height_,
               const Filter& F_)
        : acc(acc_),
          colors(colors_),
          n_colors(n_colors_),
          width(width_),
          height(height_),
          F(F_),
          out(size_t(F_.k * F_.k)),
          emitted(size_t(F_.k * F_.k), 0.0),
          phi(size_t(F_.k)),
          psi(size_t(F_.k)) {}

    const double* color(int64_t s) const { return colors + 3 * (s < 0 ? n_colors + s : s); }

    // write rows of t (k, W, 3) to tx_ (H + 1 of them, zero where no cell of a row is
    // reached) instead of cells to acc; e_: (2R, k)
    void rows_to(double* tx_, const double* e_, int64_t R_) {
        tx = tx_;
        e = e_;
        R = R_;
        rowacc.assign(size_t((width + 1) * F.k * F.k * 3), 0.0);
        full.assign(size_t(width + 1), NONE);
        slot_key.assign(size_t(SLOTS), NONE);
        slot_terms.assign(size_t(SLOTS * 2 * R * F.k * 3), 0.0);
        cellbuf.assign(size_t(2 * R * F.k * 3), 0.0);
        fullbuf.assign(size_t(F.k * F.k * 3), 0.0);
        identity = is_identity(e, R, F.k);
    }
    int64_t color_row(int64_t src) const { return src < 0 ? n_colors + src : src; }
    // cell values a whole interior cell of colour row ci holds: 0 + (1 * inner) * c, as add
    // writes them into a zero cell
    void full_cell_values(int64_t ci, double* cell) const {
        const double* c = colors + 3 * ci;
        const int64_t kk = F.k * F.k;
        for (int64_t ab = 0; ab < kk; ++ab) {
            const double v = 1.0 * inner_integrals[size_t(ab)];
            for (int ch = 0; ch < 3; ++ch) cell[ab * 3 + ch] = 0.0 + v * c[ch];
        }
    }
    // the x-contraction terms (2R x k x 3) of a whole interior cell of colour row ci
    template <int KT>
    const double* full_terms(int64_t ci) {
        const int64_t k = KT ? KT : F.k;
        const int64_t slot = ci & (SLOTS - 1);
        double* terms = slot_terms.data() + slot * 2 * R * k * 3;
        if (slot_key[size_t(slot)] != ci) {
            double* cell = fullbuf.data();
            full_cell_values(ci, cell);
            for (int64_t pr = 0; pr < 2 * R; ++pr)
                cell_terms_k<KT, 3>(cell, e + pr * k, pr, k, 3, identity, terms + pr * k * 3);
            slot_key[size_t(slot)] = ci;
        }
        return terms;
    }
    // contract_row_k's adds of cell m's terms for a cell whose 2R = KT pixels m - R .. m + R - 1
    // all lie in the image: by basis row b, each b's 2R pixels being contiguous in t (k, W, 3),
    // the last of them (p = -R) receiving its first term (written). Every pixel gets the one
    // operation it got pixel by pixel: the same bits, in vector registers.
    template <int KT>
    void scatter_inner_cell(double* __restrict__ t, const double* __restrict__ terms, int64_t m) const {
        constexpr int64_t kn = KT * 3, P = KT;  // 2R = KT terms, pixel q = p's R - 1 - p
        const int64_t i0 = m - P / 2;
        for (int64_t b = 0; b < KT; ++b) {
            double* __restrict__ tb = t + b * width * 3 + i0 * 3;
            for (int64_t q = 0; q < P - 1; ++q)
                for (int64_t ch = 0; ch < 3; ++ch) tb[q * 3 + ch] += terms[(P - 1 - q) * kn + b * 3 + ch];
            for (int64_t ch = 0; ch < 3; ++ch) tb[(P - 1) * 3 + ch] = terms[b * 3 + ch];
        }
    }
    // the current row contracted along x into tx's row: contract_x_row's sums in its order,
    // walked by cell (cell m adds its term for piece p to pixel m - 1 - p; a pixel still
    // receives its cells' terms in the order of p), each cell's terms found once
    template <int KT>
    void contract_row_k() {
        const int64_t k = KT ? KT : F.k;
        const int64_t kn = k * 3;
        double* __restrict__ t = tx + cur_row * width * kn;  // restrict: apart from the terms
        // a pixel's first term is written, not added to a zero (0 + x is x, but for the sign
        // of a zero, which every later sum loses): only the pixels before R - 1, whose
        // first cells lie left of the image, start from zeros
        for (int64_t b = 0; b < k; ++b)  // t: (k, W, 3)
            for (int64_t x = 0; x < geometry::pymin(R - 1, width) * 3; ++x) t[b * width * 3 + x] = 0.0;
        std::vector<double>& own = cellbuf;  // scratch: 2R x k x 3 terms of a partial cell
        if (own.size() < size_t(2 * R * kn + k * kn)) own.resize(size_t(2 * R * kn + k * kn));
        int64_t last_ci = NONE;
        const double* last_terms = nullptr;
        for (int64_t m = 0; m <= width; ++m) {
            const double* terms;
            const int64_t ci = full[size_t(m)];
            if (ci != NONE) {
                if (ci != last_ci) {
                    last_terms = full_terms<KT>(ci);
                    last_ci = ci;
                }
                terms = last_terms;
            } else {
                const double* cell = rowacc.data() + m * k * kn;
                // only the pieces p whose pixel m - 1 - p lies in the image
                for (int64_t p = -R; p < R; ++p) {
                    const int64_t i = m - 1 - p;
                    if (i < 0 || i >= width) continue;
                    cell_terms_k<KT, 3>(cell, e + (p + R) * k, p + R, k, 3, identity, own.data() + (p + R) * kn);
                }
                terms = own.data();
            }
            if (KT && 2 * R == KT && m >= R && m + R <= width) {
                scatter_inner_cell<KT>(t, terms, m);
                continue;
            }
            for (int64_t p = R - 1; p >= -R; --p) {  // pixel i = m - 1 - p ascending
                const int64_t i = m - 1 - p;
                if (i < 0 || i >= width) continue;
                const double* __restrict__ sp = terms + (p + R) * kn;
                if (p == -R) {  // pixel i's first cell (m = i + 1 - R)
                    for (int64_t b = 0; b < k; ++b) {
                        double* __restrict__ tb = t + b * width * 3 + i * 3;
                        tb[0] = sp[b * 3];
                        tb[1] = sp[b * 3 + 1];
                        tb[2] = sp[b * 3 + 2];
                    }
                    continue;
                }
                for (int64_t b = 0; b < k; ++b) {
                    double* __restrict__ tb = t + b * width * 3 + i * 3;
                    tb[0] += sp[b * 3];
                    tb[1] += sp[b * 3 + 1];
                    tb[2] += sp[b * 3 + 2];
                }
            }
        }
    }
    void flush() {
        if (tx == nullptr || cur_row < 0) return;
        if (written != nullptr) written[cur_row] = 1;
        if (F.k == 2)
            contract_row_k<2>();
        else if (F.k == 4)
            contract_row_k<4>();
        else
            contract_row_k<0>();
        const int64_t kk3 = F.k * F.k * 3;
        for (int64_t col : touched) std::fill(rowacc.begin() + col * kk3, rowacc.begin() + (col + 1) * kk3, 0.0);
        touched.clear();
        std::fill(full.begin(), full.end(), NONE);
        cur_row = -1;
    }

    // add scale * out (one piece's integrals) to cell p in src's colour
    template <int KT>
    void add_k(int64_t p, int64_t src, double scale) {
        if (p != pix) {
            pix = p;
            std::fill(emitted.begin(), emitted.end(), 0.0);
        }
        const int64_t wc = width + 1;
        const Cell at = locate(p);
        const int64_t row = at.row;
        const int64_t col = at.col;
        const int64_t k = KT ? KT : F.k;
        const double* c = color(src);
        double* cellacc;
        if (tx != nullptr) {
            if (row != cur_row) {
                flush();
                cur_row = row;
            }
            cellacc = rowacc.data() + col * k * k * 3;
            if (touched.empty() || touched.back() != col) touched.push_back(col);  // cells come in order
            if (full[size_t(col)] != NONE) {  // a marked whole cell receives more: write it out
                full_cell_values(full[size_t(col)], cellacc);
                full[size_t(col)] = NONE;
            }
        } else {
            cellacc = acc + (row * wc + col) * k * k * 3;
        }
        double* em = emitted.data();
        const double* o = out.data();
        const double c0 = c[0], c1 = c[1], c2 = c[2];  // held in registers across the stores
        if (scale == 1.0) {                            // most pieces: 1.0 * o is o (the same bits without the product)
            for (int64_t ab = 0; ab < k * k; ++ab) {
                const double v = o[ab];
                em[ab] += v;
                cellacc[ab * 3] += v * c0;
                cellacc[ab * 3 + 1] += v * c1;
                cellacc[ab * 3 + 2] += v * c2;
            }
            return;
        }
        for (int64_t ab = 0; ab < k * k; ++ab) {
            const double v = scale * o[ab];
            em[ab] += v;
            cellacc[ab * 3] += v * c0;
            cellacc[ab * 3 + 1] += v * c1;
            cellacc[ab * 3 + 2] += v * c2;
        }
    }
    void add(int64_t p, int64_t src, double scale) {
        if (F.k == 2) return add_k<2>(p, src, scale);
        if (F.k == 4) return add_k<4>(p, src, scale);
        add_k<0>(p, src, scale);
    }
    // cell p's row and column, p = row * (W + 1) + col: one division per cell, not per call
    // (a cell's calls come together)
    struct Cell {
        int64_t row, col;
    };
    int64_t located = -1;
    Cell at_located{0, 0};
    Cell locate(int64_t p) {
        if (p != located) {
            located = p;
            at_located.row = p / (width + 1);
            at_located.col = p - at_located.row * (width + 1);
        }
        return at_located;
    }
    struct Window {
        int64_t row, col;
        double x0, x1, y0, y1;
    };
    // cell p's row, column and its square cut to the image (shifted coordinates)
    Window window(int64_t p) {
        const Cell at = locate(p);
        const int64_t row = at.row;
        const int64_t col = at.col;
        return {row,
                col,
                geometry::pymax(double(col), 0.5),
                geometry::pymin(double(col) + 1.0, double(width) + 0.5),
                geometry::pymax(double(row), 0.5),
                geometry::pymin(double(row) + 1.0, double(height) + 0.5)};
    }
    // out = the piece's integrals, cut to the image if its cell is on the border
    void integrate_piece(int64_t p, const double* xs, const double* ys, int64_t start, int64_t n) {
        const Window w = window(p);
        const double ox = double(w.col) + 0.5;
        const double oy = double(w.row) + 0.5;
        if (w.col > 0 && w.row > 0 && w.col < width && w.row < height) {
            piece_integrals(xs, ys, start, n, ox, oy, F, out.data(), phi.data(), psi.data(), &sides);
            return;
        }
        const Ring r = clip_box(xs, ys, start, n, w.x0, w.x1, w.y0, w.y1, box);
        if (r.n < 3) {
            std::fill(out.begin(), out.end(), 0.0);
            return;
        }
        piece_integrals(box.x.data(), box.y.data(), r.start, r.n, ox, oy, F, out.data(), phi.data(), psi.data(),
                        &sides);
    }
    // out = the integrals over the whole cell (cut to the image). An interior cell is the
    // unit square around its centre: every input of the quadrature (u0 = -1/2, du = 1, ...)
    // and so every bit of the result is the same for all of them, found once.
    void cell_integrals(int64_t p) {
        const Window w = window(p);
        const bool inner = w.col > 0 && w.row > 0 && w.col < width && w.row < height;
        if (inner && have_inner) {
            out = inner_integrals;
            return;
        }
        sx[0] = w.x0;
        sy[0] = w.y0;
        sx[1] = w.x1;
        sy[1] = w.y0;
        sx[2] = w.x1;
        sy[2] = w.y1;
        sx[3] = w.x0;
        sy[3] = w.y1;
        piece_integrals(sx, sy, 0, 4, double(w.col) + 0.5, double(w.row) + 0.5, F, out.data(), phi.data(), psi.data(),
                        &sides);
        if (inner) {
            inner_integrals = out;
            have_inner = true;
        }
    }

    void emit_pixel(int64_t p, int64_t src, double, double) {
        if (tx != nullptr && p != pix) {  // row mode, the cell's first emission
            const Cell at = locate(p);
            const int64_t row = at.row;
            const int64_t col = at.col;
            if (col > 0 && row > 0 && col < width && row < height) {
                if (!have_inner) cell_integrals(p);
                if (row != cur_row) {
                    flush();
                    cur_row = row;
                }
                pix = p;
                for (size_t ab = 0; ab < emitted.size(); ++ab) emitted[ab] = 0.0 + 1.0 * inner_integrals[ab];
                full[size_t(col)] = color_row(src);
                return;
            }
        }
        cell_integrals(p);
        add(p, src, 1.0);
    }
    void emit_run(int64_t row, int64_t w, int64_t c0, int64_t c1, int64_t src) {
        for (int64_t c = c0; c <= c1; ++c) emit_pixel(row * w + c, src, double(c), double(row));
    }
    void emit_piece(int64_t p, int64_t src, const double* xs, const double* ys, int64_t start, int64_t n) {
        integrate_piece(p, xs, ys, start, n);
        add(p, src, 1.0);
    }
    void emit_signed_piece(int64_t p, int64_t src, double sign, const double* xs, const double* ys, int64_t start,
                           int64_t n) {
        integrate_piece(p, xs, ys, start, n);
        add(p, src, sign);
    }
    // a front strip piece's part in its pixel column, integrated without being cut out
    // (column_part_integrals) where the filter has that form and the cell lies inside the
    // image (a border cell is cut to the image first); false: the caller clips the part
    bool emit_column_part(int64_t p, int64_t src, const double* xs, const double* ys, int64_t start, int64_t n,
                          int64_t col) {
        const Cell at = locate(p);
        if (!(at.col > 0 && at.row > 0 && at.col < width && at.row < height)) return false;
        if (!column_part_integrals(xs, ys, start, n, col, double(at.col) + 0.5, double(at.row) + 0.5, F, out.data()))
            return false;
        add(p, src, 1.0);
        return true;
    }
    // the strip coverage's area is the polygon's own: its integrals come from the polygon
    void emit_strip_piece(int64_t p, int64_t src, double, const double* xs, const double* ys, int64_t start,
                          int64_t n) {
        integrate_piece(p, xs, ys, start, n);
        add(p, src, 1.0);
    }
    // reached only for a front piece whose clip to its column left nothing (area ~ 0), since
    // the sink runs with centroids on: its area counts as the whole cell's share
    void emit_area(int64_t p, int64_t src, double area, double, double) {
        cell_integrals(p);
        add(p, src, area);
    }
    void emit_rest(int64_t p, int64_t src, double, double) {
        if (p != pix) {
            pix = p;
            std::fill(emitted.begin(), emitted.end(), 0.0);
        }
        done = emitted;
        cell_integrals(p);
        for (size_t i = 0; i < out.size(); ++i) out[i] -= done[i];
        add(p, src, 1.0);
    }
};

}  // namespace aaeval::catmull
