// Pixels from knot cells: each pixel's filtered value is a contraction of the cells'
// integrals with the filter's cell-local coefficients, along x then along y.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/geometry.hpp"

namespace aaeval::catmull {

// Pixels from knot cells (combine_cells in aaeval/filters/integrate.py): pixel i takes piece
// p = m - i - 1 (p = -R .. R-1) of the filter from cell m; separable, x contracted first
// (contract_x_row: a row of cells (W + 1, k, k, nch) into t (k, W, nch)), then y
// (contract_y_rows: rows of t into pixel rows (W, nch)). e: (2R, k), the cell-local
// coefficients. The sums run in one fixed order (each term's basis sum from 0, then the
// pieces in turn from 0), so the bits do not depend on the band or the thread; cells
// outside the image are skipped (they would add zeros, which change no sum).
// s[b, ch] = sum over a, in order from 0, of cell[a, b, ch] * ep[a] (ep: row pr of e): one
// cell's term for one pixel. identity (e = I, the Gaussian): 0 + the one term times 1 (the
// zeros change nothing). The a loop runs outside, so that the inner one runs along memory.
template <int KT, int CT>
inline void cell_terms_k(const double* cell, const double* ep, int64_t pr, int64_t k_, int64_t nch_, bool identity,
                         double* s) {
    const int64_t k = KT ? KT : k_;
    const int64_t nch = CT ? CT : nch_;
    if (identity) {
        const double* cp = cell + pr * k * nch;
        for (int64_t j = 0; j < k * nch; ++j) s[j] = 0.0 + cp[j];
        return;
    }
    if (KT && CT) {  // in a local array (kept in registers), then written out
        double l[KT && CT ? KT * CT : 1];
        for (int64_t j = 0; j < k * nch; ++j) l[j] = 0.0;
        for (int64_t a = 0; a < k; ++a) {
            const double ea = ep[a];
            const double* ca = cell + a * k * nch;
            for (int64_t j = 0; j < k * nch; ++j) l[j] += ca[j] * ea;
        }
        for (int64_t j = 0; j < k * nch; ++j) s[j] = l[j];
        return;
    }
    for (int64_t j = 0; j < k * nch; ++j) s[j] = 0.0;
    for (int64_t a = 0; a < k; ++a) {
        const double ea = ep[a];
        const double* ca = cell + a * k * nch;
        for (int64_t j = 0; j < k * nch; ++j) s[j] += ca[j] * ea;
    }
}

inline bool is_identity(const double* e, int64_t R, int64_t k) {
    if (2 * R != k) return false;
    for (int64_t p = 0; p < 2 * R; ++p)
        for (int64_t a = 0; a < k; ++a)
            if (e[p * k + a] != (p == a ? 1.0 : 0.0)) return false;
    return true;
}

template <int KT, int CT>
inline void contract_x_row_k(const double* cells, const double* e, int64_t R, int64_t k_, int64_t nch_, int64_t width,
                             double* t) {
    const int64_t k = KT ? KT : k_;
    const int64_t nch = CT ? CT : nch_;
    const bool identity = is_identity(e, R, k);
    for (int64_t x = 0; x < width * k * nch; ++x) t[x] = 0.0;
    const int64_t plane = width * nch;  // t: (k, W, nch), basis b's plane first
    for (int64_t i = 0; i < width; ++i) {
        for (int64_t p = -R; p < R; ++p) {
            const int64_t m = i + 1 + p;
            if (m < 0 || m > width) continue;
            const double* cell = cells + m * k * k * nch;
            const double* ep = e + (p + R) * k;
            double s[KT && CT ? KT * CT : 64 * 64];
            cell_terms_k<KT, CT>(cell, ep, p + R, k, nch, identity, s);
            for (int64_t b = 0; b < k; ++b)
                for (int64_t ch = 0; ch < nch; ++ch) t[b * plane + i * nch + ch] += s[b * nch + ch];
        }
    }
}

// pixel rows j0 .. j1 from t's rows n0 .. n1 (t: rows of (k, W, nch), row n0 first)
template <int KT, int CT>
inline void contract_y_rows_k(const double* t, int64_t n0, int64_t n1, const double* e, int64_t R, int64_t k_,
                              int64_t nch_, int64_t width, int64_t j0, int64_t j1, double* image) {
    const int64_t k = KT ? KT : k_;
    const int64_t nch = CT ? CT : nch_;
    const int64_t plane = width * nch;
    const int64_t rowlen = k * plane;
    std::vector<double> sum(static_cast<size_t>(plane));
    double* __restrict__ S = sum.data();  // restrict: the loops below vectorise
    for (int64_t j = j0; j < j1; ++j) {
        double* __restrict__ out = image + j * plane;
        bool first = true;  // the first sum is written, not added to zeros (S is never -0.0)
        for (int64_t q = -R; q < R; ++q) {
            const int64_t n = j + 1 + q;
            if (n < n0 || n > n1) continue;
            const double* tr = t + (n - n0) * rowlen;
            const double* eq = e + (q + R) * k;
            // every pixel's sum over b in order from 0, then added to the pixel
            {  // b = 0 starts the sum from zero in the same pass (0.0 + the term, as before)
                const double e0 = eq[0];
                for (int64_t x = 0; x < plane; ++x) S[x] = 0.0 + tr[x] * e0;
            }
            for (int64_t b = 1; b < k; ++b) {
                const double eb = eq[b];
                const double* __restrict__ tb = tr + b * plane;
                for (int64_t x = 0; x < plane; ++x) S[x] += tb[x] * eb;
            }
            if (first)
                for (int64_t x = 0; x < plane; ++x) out[x] = S[x];
            else
                for (int64_t x = 0; x < plane; ++x) out[x] += S[x];
            first = false;
        }
        if (first)
            for (int64_t x = 0; x < plane; ++x) out[x] = 0.0;
    }
}

#define AAEVAL_KC_DISPATCH(fn, k, nch, ...)                       \
    do {                                                          \
        if ((k) == 2 && (nch) == 3) return fn<2, 3>(__VA_ARGS__); \
        if ((k) == 4 && (nch) == 3) return fn<4, 3>(__VA_ARGS__); \
        if ((k) == 2 && (nch) == 4) return fn<2, 4>(__VA_ARGS__); \
        if ((k) == 4 && (nch) == 4) return fn<4, 4>(__VA_ARGS__); \
        return fn<0, 0>(__VA_ARGS__);                             \
    } while (0)

inline void contract_x_row(const double* cells, const double* e, int64_t R, int64_t k, int64_t nch, int64_t width,
                           double* t) {
    AAEVAL_KC_DISPATCH(contract_x_row_k, k, nch, cells, e, R, k, nch, width, t);
}
inline void contract_y_rows(const double* t, int64_t n0, int64_t n1, const double* e, int64_t R, int64_t k, int64_t nch,
                            int64_t width, int64_t j0, int64_t j1, double* image) {
    AAEVAL_KC_DISPATCH(contract_y_rows_k, k, nch, t, n0, n1, e, R, k, nch, width, j0, j1, image);
}
#undef AAEVAL_KC_DISPATCH

// pixel rows j0 .. j1 of the image (H, W, nch) from the whole acc (H + 1, W + 1, k, k, nch)
inline void combine_rows(const double* acc, const double* e, int64_t R, int64_t k, int64_t nch, int64_t width,
                         int64_t height, int64_t j0, int64_t j1, double* image, std::vector<double>& tx) {
    if (j1 <= j0) return;
    const int64_t n0 = geometry::pymax(int64_t(0), j0 + 1 - R);
    const int64_t n1 = geometry::pymin(height, j1 - 1 + R);  // cell rows needed, inclusive
    const int64_t rowlen = width * k * nch;
    tx.assign(size_t(geometry::pymax(int64_t(0), n1 - n0 + 1) * rowlen), 0.0);
    for (int64_t n = n0; n <= n1; ++n)
        contract_x_row(acc + n * (width + 1) * k * k * nch, e, R, k, nch, width, tx.data() + (n - n0) * rowlen);
    contract_y_rows(tx.data(), n0, n1, e, R, k, nch, width, j0, j1, image);
}

}  // namespace aaeval::catmull
