// Integrals of a separable filter's basis over one polygon inside a knot cell, by Green's
// theorem along the polygon's edges: piece_integrals (the whole polygon) and
// column_part_integrals (a strip piece's part in one pixel column, without cutting it out).
#pragma once

#include <cmath>
#include <cstdint>

#include "common/geometry.hpp"
#include "catmull/filter_basis.hpp"

namespace aaeval::catmull {

// Integrals of phi_a(u) psi_b(v) over one polygon xs/ys[start .. start+n) lying in the cell
// centred at (ox, oy), written to out[a * k + b]; u = x - ox, v = y - oy. Polynomial:
// phi_a = u^a, psi_b = v^b; Gaussian: phi_a(u) = k(u + a - radius + 1/2), the same in v.
// phi, psi: scratch of k entries (piece_integrals_k below). An edge on a cell's side at u = +-1/2 (du = 0) has the same phi at every node: those
// values are found once per sink (sides), not per node.
struct SidePhi {
    bool have = false;
    double lo[64], hi[64];  // phi_a(-1/2), phi_a(+1/2)
};

// Edge i of the polygon xs/ys[start .. start+n) in cell coordinates (u = x - ox, v = y - oy):
// its start (u0, v0) and its step to the next vertex (du, dv), the last edge closing the ring
struct Edge {
    double u0, v0, du, dv;
};
inline Edge edge_at(const double* xs, const double* ys, int64_t start, int64_t n, int64_t i, double ox, double oy) {
    const int64_t j = i + 1 < n ? start + i + 1 : start;  // the next vertex (no division)
    const double u0 = xs[start + i] - ox;
    const double v0 = ys[start + i] - oy;
    return {u0, v0, xs[j] - ox - u0, ys[j] - oy - v0};
}

// phi on a vertical cell side u0 = -1/2 or +1/2, found once per sink: what the node loop
// computes at u = u0 + t * 0 = u0
template <bool POLY>
inline const double* side_phi(double u0, int64_t k, const Filter& F, SidePhi* sides) {
    if (!sides->have) {
        double ulo = -0.5, uhi = 0.5;
        for (int64_t a = 0; a < k; ++a) {
            if (POLY) {
                sides->lo[a] = ulo / double(a + 1);
                sides->hi[a] = uhi / double(a + 1);
                ulo *= -0.5;
                uhi *= 0.5;
            } else {
                const double c = double(a - F.radius) + 0.5;
                sides->lo[a] = gauss_primitive(-0.5 + c, F.alpha, F.bias);
                sides->hi[a] = gauss_primitive(0.5 + c, F.alpha, F.bias);
            }
        }
        sides->have = true;
    }
    return u0 == -0.5 ? sides->lo : sides->hi;
}

// KT: k known at compile time (0: F.k), so that the basis loops unroll; POLY: the
// polynomial basis (else the Gaussian's), so that each node loop is straight code. Every
// entry's sum runs in the same order either way (the same bits).
template <int KT, bool POLY>
inline void piece_integrals_k(const double* xs, const double* ys, int64_t start, int64_t n, double ox, double oy,
                              const Filter& F, double* out_, double* phi_, double* psi_, SidePhi* sides) {
    const int64_t k = KT ? KT : F.k;
    // with k known, the sums live in local arrays (no aliasing with the vertices: they stay
    // in registers) and go to out_ at the end
    double lout[KT ? KT * KT : 1], lphi[KT ? KT : 1], lpsi[KT ? KT : 1];
    double* out = KT ? lout : out_;
    double* phi = KT ? lphi : phi_;
    double* psi = KT ? lpsi : psi_;
    for (int64_t a = 0; a < k * k; ++a) out[a] = 0.0;
    const double* nodes = POLY ? POLY_T : GAUSS_T;
    const double* weights = POLY ? POLY_W : GAUSS_W;
    const int nq = POLY ? 4 : 12;
    // gauss_primitive's constants, found once per call (the same values, so the same bits)
    const double gc = POLY ? 0.0 : std::sqrt(-F.alpha);
    const double gk = POLY ? 0.0 : 0.8862269254527580 / gc;
    auto accumulate = [&](double w) {
        for (int64_t a = 0; a < k; ++a) {
            const double wa = w * phi[a];
            for (int64_t b = 0; b < k; ++b) out[a * k + b] += wa * psi[b];
        }
    };
    for (int64_t i = 0; i < n; ++i) {
        const auto [u0, v0, du, dv] = edge_at(xs, ys, start, n, i, ox, oy);
        if (dv == 0.0) continue;  // the integral of Phi dv vanishes along a horizontal edge
        if (sides != nullptr && du == 0.0 && (u0 == -0.5 || u0 == 0.5)) {
            // an edge on a cell's vertical side: phi is the same at every node
            const double* side = side_phi<POLY>(u0, k, F, sides);
            for (int64_t a = 0; a < k; ++a) phi[a] = side[a];
            for (int q = 0; q < nq; ++q) {
                const double v = v0 + nodes[q] * dv;
                const double w = weights[q] * dv;
                if (POLY) {
                    double vp = 1.0;
                    for (int64_t a = 0; a < k; ++a) {
                        psi[a] = vp;
                        vp *= v;
                    }
                } else {
                    for (int64_t a = 0; a < k; ++a) {
                        const double c = double(a - F.radius) + 0.5;
                        psi[a] = std::exp(F.alpha * (v + c) * (v + c)) - F.bias;
                    }
                }
                accumulate(w);
            }
            continue;
        }
        for (int q = 0; q < nq; ++q) {
            const double u = u0 + nodes[q] * du;
            const double v = v0 + nodes[q] * dv;
            const double w = weights[q] * dv;
            if (POLY) {
                double up = u, vp = 1.0;
                for (int64_t a = 0; a < k; ++a) {
                    phi[a] = up / double(a + 1);
                    psi[a] = vp;
                    up *= u;
                    vp *= v;
                }
            } else {
                for (int64_t a = 0; a < k; ++a) {
                    const double c = double(a - F.radius) + 0.5;
                    const double t = u + c;
                    phi[a] = gk * std::erf(gc * t) - F.bias * t;  // gauss_primitive(t, alpha, bias)
                    psi[a] = std::exp(F.alpha * (v + c) * (v + c)) - F.bias;
                }
            }
            accumulate(w);
        }
    }
    if (KT)
        for (int64_t a = 0; a < k * k; ++a) out_[a] = out[a];
}

// piece_integrals_k<4, false> on the Gaussian's fast route (F.gauss): every edge's basis
// values at its 12 nodes from the polynomials (mirrored_pair), its terms summed per node
// lane and the lanes added at the end (the node sums in another order: the same within
// rounding)
inline void gauss_piece_integrals(const double* xs, const double* ys, int64_t start, int64_t n, double ox, double oy,
                                  const Filter& F, double* out, SidePhi* sides) {
    const GaussTable& G = *F.gauss;
    Nodes T, W, sum[16];
    for (int r = 0; r < 3; ++r) {
        T.r[r] = v4{GAUSS_T[4 * r], GAUSS_T[4 * r + 1], GAUSS_T[4 * r + 2], GAUSS_T[4 * r + 3]};
        W.r[r] = v4{GAUSS_W[4 * r], GAUSS_W[4 * r + 1], GAUSS_W[4 * r + 2], GAUSS_W[4 * r + 3]};
        for (int ab = 0; ab < 16; ++ab) sum[ab].r[r] = v4{};
    }
    for (int64_t i = 0; i < n; ++i) {
        const auto [u0, v0, du, dv] = edge_at(xs, ys, start, n, i, ox, oy);
        if (dv == 0.0) continue;
        Nodes u, v, w, phi[4], psi[4];
        for (int r = 0; r < 3; ++r) {  // the node loop's u, v and weight
            u.r[r] = u0 + T.r[r] * du;
            v.r[r] = v0 + T.r[r] * dv;
            w.r[r] = W.r[r] * dv;
        }
        if (sides != nullptr && du == 0.0 && (u0 == -0.5 || u0 == 0.5)) {
            const double* side = side_phi<false>(u0, 4, F, sides);  // on a cell's side: Phi known
            for (int a = 0; a < 4; ++a)
                for (int r = 0; r < 3; ++r) phi[a].r[r] = v4{} + side[a];
        } else {
            for (int h = 0; h < 2; ++h)  // Phi_{2+h}(u) = p(u), Phi_{1-h}(u) = -p(-u)
                mirrored_pair(G.phi_even[h], G.phi_odd[h], u, -1.0, phi[2 + h], phi[1 - h]);
        }
        for (int h = 0; h < 2; ++h)  // psi_{2+h}(v) = p(v), psi_{1-h}(v) = p(-v)
            mirrored_pair(G.psi_even[h], G.psi_odd[h], v, 1.0, psi[2 + h], psi[1 - h]);
        for (int a = 0; a < 4; ++a)
            for (int r = 0; r < 3; ++r) {
                const v4 wa = w.r[r] * phi[a].r[r];
                for (int b = 0; b < 4; ++b) sum[a * 4 + b].r[r] += wa * psi[b].r[r];
            }
    }
    for (int ab = 0; ab < 16; ++ab) {
        double total = 0.0;
        for (int r = 0; r < 3; ++r)
            for (int l = 0; l < 4; ++l) total += sum[ab].r[r][l];
        out[ab] = total;
    }
}

// piece_integrals_k<4, true> on the fast route (the cubics): an edge's 4 Gauss-Legendre nodes
// as one vector of 4 (Nodes' v4), every basis value and term computed for the 4 at once, the
// node sums kept per lane and added at the end (the same sums in another order: within
// rounding of the plain route's)
inline void cubic_piece_integrals(const double* xs, const double* ys, int64_t start, int64_t n, double ox, double oy,
                                  double* out) {
    const v4 T{POLY_T[0], POLY_T[1], POLY_T[2], POLY_T[3]};
    const v4 Wq{POLY_W[0], POLY_W[1], POLY_W[2], POLY_W[3]};
    v4 sum[16];
    for (int ab = 0; ab < 16; ++ab) sum[ab] = v4{};
    for (int64_t i = 0; i < n; ++i) {
        const auto [u0, v0, du, dv] = edge_at(xs, ys, start, n, i, ox, oy);
        if (dv == 0.0) continue;  // the integral of Phi dv vanishes along a horizontal edge
        const v4 u = u0 + T * du, v = v0 + T * dv, w = Wq * dv;
        const v4 u2 = u * u, u3 = u2 * u;
        const v4 wphi[4] = {w * u, w * (u2 / 2.0), w * (u3 / 3.0), w * ((u3 * u) / 4.0)};  // w Phi_a(u)
        const v4 v2 = v * v;
        const v4 psi[4] = {v4{} + 1.0, v, v2, v2 * v};
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) sum[a * 4 + b] += wphi[a] * psi[b];
    }
    for (int ab = 0; ab < 16; ++ab) out[ab] = ((sum[ab][0] + sum[ab][1]) + sum[ab][2]) + sum[ab][3];
}

// The tent's integrals (1, v, u, u v over the polygon: out[a * 2 + b] = the integral of u^a v^b)
// by the shoelace formulas for area and moments, term c_i = u_i v_{i+1} - u_{i+1} v_i per edge,
// instead of Gauss-Legendre along the edges: the same integrals, a third of the arithmetic.
inline void tent_piece_integrals(const double* xs, const double* ys, int64_t start, int64_t n, double ox, double oy,
                                 double* out) {
    double area = 0.0, mu = 0.0, mv = 0.0, muv = 0.0;
    for (int64_t i = 0; i < n; ++i) {
        const int64_t j = i + 1 < n ? start + i + 1 : start;
        const double u0 = xs[start + i] - ox, v0 = ys[start + i] - oy;
        const double u1 = xs[j] - ox, v1 = ys[j] - oy;
        const double c = u0 * v1 - u1 * v0;
        area += c;
        mu += (u0 + u1) * c;
        mv += (v0 + v1) * c;
        muv += (2.0 * (u0 * v0 + u1 * v1) + u0 * v1 + u1 * v0) * c;
    }
    out[0] = area / 2.0;
    out[1] = mv / 6.0;
    out[2] = mu / 6.0;
    out[3] = muv / 24.0;
}

// One edge of a strip piece cut to the column [lo, hi] in cell coordinates: (ua, va) to
// (ub, vb); false if it adds nothing (vertical, or outside the column). An end inside the
// column is the vertex itself (the line through it would give the same value).
struct ColumnEdge {
    double ua, va, ub, vb;
};
AAEVAL_INLINE bool column_edge(const double* xs, const double* ys, int64_t start, int64_t n, int64_t i, double lo,
                               double hi, double ox, double oy, ColumnEdge& e) {
    const int64_t j = i + 1 < n ? start + i + 1 : start;
    const double x0 = xs[start + i], x1 = xs[j];
    const double xa = geometry::pymin(geometry::pymax(x0, lo), hi);
    const double xb = geometry::pymin(geometry::pymax(x1, lo), hi);
    if (xa == xb) return false;  // vertical (du = 0), or outside the column
    const double y0 = ys[start + i], y1 = ys[j];
    double ya = y0, yb = y1;
    if (xa != x0 || xb != x1) {
        const double slope = (y1 - y0) / (x1 - x0);
        if (xa != x0) ya = y0 + slope * (xa - x0);
        if (xb != x1) yb = y0 + slope * (xb - x0);
    }
    e = {xa - ox, ya - oy, xb - ox, yb - oy};
    return true;
}

// The tent's four integrals of a strip piece's column part (column_part_integrals): minus
// the integral of u^a v^(b+1) / (b+1) du along each cut edge, in closed form.
inline void tent_column_part(const double* xs, const double* ys, int64_t start, int64_t n, double lo, double hi,
                             double ox, double oy, double* out) {
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    ColumnEdge e;
    for (int64_t i = 0; i < n; ++i) {
        if (!column_edge(xs, ys, start, n, i, lo, hi, ox, oy, e)) continue;
        const auto [ua, va, ub, vb] = e;
        const double du = ub - ua;
        s0 += du * (va + vb);
        s1 += du * (va * va + va * vb + vb * vb);
        s2 += du * (2.0 * (ua * va + ub * vb) + ua * vb + ub * va);
        s3 += du * (ua * ((3.0 * va + 2.0 * vb) * va + vb * vb) + ub * (va * va + (2.0 * va + 3.0 * vb) * vb));
    }
    out[0] = -s0 / 2.0;  // out[a * 2 + b]: the integral of u^a v^b
    out[1] = -s1 / 6.0;
    out[2] = -s2 / 6.0;
    out[3] = -s3 / 24.0;
}

// A cubic's sixteen: 4 Gauss-Legendre nodes per cut edge as one vector (degree 7 at most)
inline void cubic_column_part(const double* xs, const double* ys, int64_t start, int64_t n, double lo, double hi,
                              double ox, double oy, double* out) {
    const v4 T{POLY_T[0], POLY_T[1], POLY_T[2], POLY_T[3]};
    const v4 Wq{POLY_W[0], POLY_W[1], POLY_W[2], POLY_W[3]};
    v4 sum[16];
    for (int ab = 0; ab < 16; ++ab) sum[ab] = v4{};
    ColumnEdge e;
    for (int64_t i = 0; i < n; ++i) {
        if (!column_edge(xs, ys, start, n, i, lo, hi, ox, oy, e)) continue;
        const double du = e.ub - e.ua;
        const v4 u = e.ua + T * du, v = e.va + T * (e.vb - e.va), w = Wq * du;
        const v4 u2 = u * u;
        const v4 phi[4] = {v4{} + 1.0, u, u2, u2 * u};
        const v4 v2 = v * v;
        const v4 wpsi[4] = {w * v, w * (v2 / 2.0), w * ((v2 * v) / 3.0), w * ((v2 * v2) / 4.0)};  // w Psi_b(v)
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) sum[a * 4 + b] += phi[a] * wpsi[b];
    }
    for (int ab = 0; ab < 16; ++ab) out[ab] = -(((sum[ab][0] + sum[ab][1]) + sum[ab][2]) + sum[ab][3]);
}

// The part of a strip piece (a polygon inside the row strip) in pixel column [col, col + 1],
// integrated without cutting it out: by Green's theorem in the other form, the integral of
// phi_a(u) psi_b(v) over a region is minus the integral of phi_a(u) Psi_b(v) du along its
// boundary (Psi_b an antiderivative of psi_b), to which the column's vertical sides add
// nothing (du = 0): only the piece's own edges count, each cut to the column's x range as
// strip_coverage cuts them. For the tent and the cubics on the fast route; false for a
// filter without this form (the caller clips). (ox, oy): the cell's centre, as piece_integrals.
inline bool column_part_integrals(const double* xs, const double* ys, int64_t start, int64_t n, int64_t col, double ox,
                                  double oy, const Filter& F, double* out) {
    if (!F.fast || F.kind != KIND_POLYNOMIAL || (F.k != 2 && F.k != 4)) return false;
    const double lo = double(col), hi = double(col) + 1.0;
    if (F.k == 2)
        tent_column_part(xs, ys, start, n, lo, hi, ox, oy, out);
    else
        cubic_column_part(xs, ys, start, n, lo, hi, ox, oy, out);
    return true;
}

inline void piece_integrals(const double* xs, const double* ys, int64_t start, int64_t n, double ox, double oy,
                            const Filter& F, double* out, double* phi, double* psi, SidePhi* sides = nullptr) {
    if (F.gauss) return gauss_piece_integrals(xs, ys, start, n, ox, oy, F, out, sides);
    if (F.fast && F.kind == KIND_POLYNOMIAL && F.k == 2) return tent_piece_integrals(xs, ys, start, n, ox, oy, out);
    if (F.fast && F.kind == KIND_POLYNOMIAL && F.k == 4) return cubic_piece_integrals(xs, ys, start, n, ox, oy, out);
    if (F.kind == KIND_POLYNOMIAL) {
        if (F.k == 2) return piece_integrals_k<2, true>(xs, ys, start, n, ox, oy, F, out, phi, psi, sides);
        if (F.k == 4) return piece_integrals_k<4, true>(xs, ys, start, n, ox, oy, F, out, phi, psi, sides);
        return piece_integrals_k<0, true>(xs, ys, start, n, ox, oy, F, out, phi, psi, sides);
    }
    if (F.k == 4) return piece_integrals_k<4, false>(xs, ys, start, n, ox, oy, F, out, phi, psi, sides);
    piece_integrals_k<0, false>(xs, ys, start, n, ox, oy, F, out, phi, psi, sides);
}

}  // namespace aaeval::catmull
