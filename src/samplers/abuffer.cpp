// Carpenter 1984 A-buffer: per pixel, every polygon reaching a subsample is a fragment (a
// 4 x 8 bit coverage mask and the z range of its plane over the polygon inside the pixel),
// resolved front to back with the paper's blend where two z ranges overlap
// (aaeval/renderers/abuffer.py explains the method).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "samplers/depth.hpp"
#include "samplers/sampling.hpp"

namespace aaeval::samplers {

namespace {

constexpr int64_t SUBSAMPLES = 32;
constexpr int64_t SUB_COLS = 8;
constexpr int64_t SUB_ROWS = 4;
constexpr int64_t FULL_MASK = (int64_t(1) << SUBSAMPLES) - 1;

inline int64_t popcount(int64_t v) { return __builtin_popcountll(static_cast<uint64_t>(v)); }

// The 32-bit masks of the polygon over pixels c0..c1 of a row into masks[c0..c1]: bit
// 8 j + i of pixel col is the subcell centre ((8 col + i + 1/2)/8, row + (j + 1/2)/4).
void coverage_masks(EdgeBuffers& E, int64_t m, int64_t row, int64_t width, int64_t c0, int64_t c1,
                    std::vector<int64_t>& masks) {
    std::fill(masks.begin() + c0, masks.begin() + c1 + 1, 0);
    for (int64_t j = 0; j < SUB_ROWS; ++j) {
        const int64_t nc =
            crossings(E, m, static_cast<double>(row) + (static_cast<double>(j) + 0.5) / static_cast<double>(SUB_ROWS));
        for (int64_t t = 0; t < nc - 1; t += 2) {
            int64_t g0, g1;
            grid_range(E.xc[t], E.xc[t + 1], SUB_COLS, width * SUB_COLS, g0, g1);
            for (int64_t g = g0; g < g1; ++g) {
                const int64_t col = g / SUB_COLS;
                masks[col] |= int64_t(1) << (j * SUB_COLS + g - col * SUB_COLS);
            }
        }
    }
}

// Min and max of z = a x + b y + c over the polygon inside the pixel square.
void z_range(const EdgeBuffers& E, int64_t m, int64_t col, int64_t row, double a, double b, double c, double& zlo,
             double& zhi) {
    zlo = INF;
    zhi = -INF;
    const double x0b = static_cast<double>(col), x1b = static_cast<double>(col) + 1.0;
    const double y0b = static_cast<double>(row), y1b = static_cast<double>(row) + 1.0;
    for (int64_t e = 0; e < m; ++e) {
        // Liang-Barsky: the part of the edge inside the square
        const double px = E.x0[e], py = E.y0[e];
        const double dx = E.x1[e] - px, dy = E.y1[e] - py;
        double t0 = 0.0, t1 = 1.0;
        bool ok = true;
        for (int side = 0; side < 4; ++side) {
            double pp, qq;
            if (side == 0) {
                pp = -dx;
                qq = px - x0b;
            } else if (side == 1) {
                pp = dx;
                qq = x1b - px;
            } else if (side == 2) {
                pp = -dy;
                qq = py - y0b;
            } else {
                pp = dy;
                qq = y1b - py;
            }
            if (pp == 0.0) {
                if (qq < 0.0) {
                    ok = false;
                    break;
                }
            } else {
                const double t = qq / pp;
                if (pp < 0.0)
                    t0 = pymax(t0, t);
                else
                    t1 = pymin(t1, t);
                if (t0 > t1) {
                    ok = false;
                    break;
                }
            }
        }
        if (!ok) continue;
        for (double t : {t0, t1}) {
            const double z = a * (px + t * dx) + b * (py + t * dy) + c;
            zlo = pymin(zlo, z);
            zhi = pymax(zhi, z);
        }
    }
    for (double cy : {y0b, y1b}) {
        for (double cx : {x0b, x1b}) {
            if (inside(E, m, cx, cy)) {
                const double z = a * cx + b * cy + c;
                zlo = pymin(zlo, z);
                zhi = pymax(zhi, z);
            }
        }
    }
    if (zlo > zhi) {  // a sliver touching no edge or corner test: use the centre
        zlo = zhi = a * (static_cast<double>(col) + 0.5) + b * (static_cast<double>(row) + 0.5) + c;
    }
}

bool same_plane(const double* planes, int64_t p, int64_t q, int64_t col, int64_t row, double eps_z) {
    const double x0 = static_cast<double>(col), y0 = static_cast<double>(row);
    const double cxs[3] = {x0, x0 + 1.0, x0};
    const double cys[3] = {y0, y0, y0 + 1.0};
    for (int i = 0; i < 3; ++i) {
        const double zp = planes[3 * p] * cxs[i] + planes[3 * p + 1] * cys[i] + planes[3 * p + 2];
        const double zq = planes[3 * q] * cxs[i] + planes[3 * q + 1] * cys[i] + planes[3 * q + 2];
        if (std::fabs(zp - zq) > eps_z) return false;
    }
    return true;
}

struct Fragments {
    std::vector<int64_t> col, mask, poly;
    std::vector<double> zmin, zmax;
    void clear() {
        col.clear();
        mask.clear();
        poly.clear();
        zmin.clear();
        zmax.clear();
    }
};

// Front-to-back resolution of one pixel's sorted fragments order[0..n) into out[3].
void resolve_pixel(const int64_t* order, int64_t n, const Fragments& F, const double* planes, double eps_z,
                   const double* colors, const double* background, int64_t col, int64_t row, double* out) {
    int64_t free = FULL_MASK;
    double acc0 = 0.0, acc1 = 0.0, acc2 = 0.0;
    for (int64_t a = 0; a < n; ++a) {
        const int64_t f = order[a];
        const int64_t claim = F.mask[f] & free;
        if (claim == 0) continue;
        const int64_t pf = F.poly[f];
        int64_t g = -1;
        for (int64_t b = a + 1; b < n; ++b) {
            if (F.mask[order[b]] & claim) {
                g = order[b];
                break;
            }
        }
        double w_front = static_cast<double>(popcount(claim));
        double w_back = 0.0;
        int64_t pg = 0;
        if (g >= 0 && F.zmin[g] < F.zmax[f]) {
            pg = F.poly[g];
            const double shared = static_cast<double>(popcount(claim & F.mask[g]));
            double front;
            if (same_plane(planes, pf, pg, col, row, eps_z)) {
                front = pf > pg ? 1.0 : 0.0;
            } else {
                const double span = (F.zmax[f] - F.zmin[f]) + (F.zmax[g] - F.zmin[g]);
                front = span > 0.0 ? (F.zmax[g] - F.zmin[f]) / span : 0.5;
                front = pymin(1.0, pymax(0.0, front));
            }
            w_back = shared * (1.0 - front);
            w_front -= w_back;
        }
        acc0 += w_front * colors[3 * pf] + w_back * colors[3 * pg];
        acc1 += w_front * colors[3 * pf + 1] + w_back * colors[3 * pg + 1];
        acc2 += w_front * colors[3 * pf + 2] + w_back * colors[3 * pg + 2];
        free &= ~claim;
        if (free == 0) break;
    }
    const double w_bg = static_cast<double>(popcount(free));
    out[0] = (acc0 + w_bg * background[0]) / static_cast<double>(SUBSAMPLES);
    out[1] = (acc1 + w_bg * background[1]) / static_cast<double>(SUBSAMPLES);
    out[2] = (acc2 + w_bg * background[2]) / static_cast<double>(SUBSAMPLES);
}

// Sorts one pixel's fragments on (zmin ascending, polygon descending). Insertion sort is
// quadratic in the depth of the pixel; a stable merge sort on the same key gives the same
// permutation whenever the key is a strict weak order, i.e. when no zmin is NaN, so deep
// pixels take it and a pixel with a NaN keeps the insertion sort, whose order a NaN does
// not make undefined.
void sort_pixel(int64_t* order, int64_t n, const Fragments& F) {
    const double* zmin = F.zmin.data();
    const int64_t* poly = F.poly.data();
    auto before = [zmin, poly](int64_t f, int64_t o) {  // f goes before o
        return zmin[o] > zmin[f] || (zmin[o] == zmin[f] && poly[o] < poly[f]);
    };
    bool merge = n > 16;
    for (int64_t i = 0; merge && i < n; ++i) merge = !std::isnan(zmin[order[i]]);
    if (merge) {
        std::stable_sort(order, order + n, before);
        return;
    }
    for (int64_t a = 1; a < n; ++a) {
        const int64_t f = order[a];
        int64_t b = a - 1;
        while (b >= 0 && before(f, order[b])) {
            order[b + 1] = order[b];
            --b;
        }
        order[b + 1] = f;
    }
}

}  // namespace

void abuffer_image(int64_t width, int64_t height, const Polygons& P, double eps_z, const double* colors,
                   const double* background, double* image) {
    std::vector<int64_t> row_start, polys;
    row_buckets(height, P, row_start, polys);
    EdgeBuffers E(P);
    std::vector<int64_t> masks(width, 0);
    Fragments F;
    std::vector<int64_t> per_col(width + 1), order, fill(width);
    for (int64_t r = 0; r < height; ++r) {
        F.clear();
        for (int64_t q = row_start[r]; q < row_start[r + 1]; ++q) {
            const int64_t p = polys[q];
            double xlo, xhi;
            const int64_t m = strip_edges(P, p, static_cast<double>(r), static_cast<double>(r) + 1.0, E, xlo, xhi);
            if (m == 0) continue;
            const int64_t c0 = pymax(int64_t(0), to_i64(std::floor(xlo)));
            const int64_t c1 = pymin(width - 1, to_i64(std::floor(xhi)));
            if (c0 > c1) continue;
            coverage_masks(E, m, r, width, c0, c1, masks);
            for (int64_t col = c0; col <= c1; ++col) {
                const int64_t mask = masks[col];
                if (mask == 0) continue;
                double zlo, zhi;
                z_range(E, m, col, r, P.planes[3 * p], P.planes[3 * p + 1], P.planes[3 * p + 2], zlo, zhi);
                F.col.push_back(col);
                F.mask.push_back(mask);
                F.zmin.push_back(zlo);
                F.zmax.push_back(zhi);
                F.poly.push_back(p);
            }
        }
        // bucket the row's fragments by column, then sort each pixel's on (zmin, -polygon)
        // and put each run within eps_z of its nearest zmin latest polygon first
        const int64_t nf = static_cast<int64_t>(F.col.size());
        std::fill(per_col.begin(), per_col.end(), 0);
        for (int64_t f = 0; f < nf; ++f) per_col[F.col[f] + 1] += 1;
        for (int64_t col = 0; col < width; ++col) per_col[col + 1] += per_col[col];
        order.resize(nf);
        std::copy(per_col.begin(), per_col.end() - 1, fill.begin());
        for (int64_t f = 0; f < nf; ++f) order[fill[F.col[f]]++] = f;
        for (int64_t col = 0; col < width; ++col) {
            const int64_t lo = per_col[col], hi = per_col[col + 1];
            sort_pixel(order.data() + lo, hi - lo, F);
            tied_latest_first(order.data() + lo, hi - lo, F.zmin.data(), F.poly.data(), eps_z);
            resolve_pixel(order.data() + lo, hi - lo, F, P.planes, eps_z, colors, background, col, r,
                          image + (r * width + col) * 3);
        }
    }
}

}  // namespace aaeval::samplers
