// Exact integration of visible pieces against a separable pixel filter, on knot cells
// [m - 1/2, m + 1/2] x [n - 1/2, n + 1/2] (see aaeval/filters/integrate.py for the maths):
// piece_integrals (one polygon inside a cell, by Green's theorem with Gauss-Legendre along
// its edges), clip_box (a ring cut to a box), accumulate_rings (rings of any size cut on the
// knot grid) and MomentSink, the Catmull kernel's sink that accumulates every visible piece's
// integrals times its colour per cell.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/geometry.hpp"

namespace aaeval::catmull {

inline constexpr int64_t KIND_POLYNOMIAL = 1;
inline constexpr int64_t KIND_GAUSSIAN = 2;

// Gauss-Legendre nodes and weights on [0, 1] (numpy's leggauss, moved there): 4 points are
// exact for the degree-7 edge polynomials of cubic filters (and the tent's on the recorded
// route); 12 for the Gaussian's edges.
inline constexpr double POLY_T[4] = {0x1.1c6490c2719ecp-4, 0x1.51ee013116102p-2, 0x1.5708ff6774f7fp-1, 0x1.dc736de7b1cc2p-1};
inline constexpr double POLY_W[4] = {0x1.64340f7e7b666p-3, 0x1.4de5f840c24cdp-2, 0x1.4de5f840c24cdp-2, 0x1.64340f7e7b666p-3};
inline constexpr double GAUSS_T[12] = {0x1.2e1c4e37a2fe0p-7, 0x1.88bc58023ba68p-5, 0x1.d73d4449dc328p-4, 0x1.a6961f47f100ep-3, 0x1.43ab96faba732p-2, 0x1.bfe1681c273c7p-2, 0x1.200f4bf1ec61cp-1, 0x1.5e2a3482a2c67p-1, 0x1.965a782e03bfcp-1, 0x1.c5185776c479bp-1, 0x1.e7743a7fdc45ap-1, 0x1.fb478ec721740p-1};
inline constexpr double GAUSS_W[12] = {0x1.8275d9dea6d53p-6, 0x1.b60602bce61afp-5, 0x1.47d7258f22d96p-4, 0x1.a0163e6b1ab6bp-4, 0x1.de3155c256aaep-4, 0x1.fe40ce6d4f022p-4, 0x1.fe40ce6d4f022p-4, 0x1.de3155c256aaep-4, 0x1.a0163e6b1ab6bp-4, 0x1.47d7258f22d96p-4, 0x1.b60602bce61afp-5, 0x1.8275d9dea6d53p-6};

// fast: the route a render takes (route_filter in module.cpp), where piece_integrals takes
// the tent's four integrals in closed form, a cubic's edge nodes four at a time, and the
// Gaussian's basis from gauss (its polynomials, gauss_table below); the recorded route (false,
// gauss null) keeps Gauss-Legendre one node at a time and erf and exp at every node.
struct Filter {
    int64_t kind, radius, k;
    double alpha, bias;
    bool fast = false;
    std::shared_ptr<const struct GaussTable> gauss = nullptr;
};

// An antiderivative of exp(alpha t^2) - bias.
inline double gauss_primitive(double t, double alpha, double bias) {
    const double c = std::sqrt(-alpha);
    return (0.8862269254527580 / c) * std::erf(c * t) - bias * t;  // sqrt(pi)/2
}

// The Gaussian's fast route, for its 4 basis functions per axis (radius 2; other radii keep
// erf and exp). On a cell, u and v in [-1/2, 1/2], Phi_a(u) = gauss_primitive(u + c_a) and
// psi_b(v) = exp(alpha (v + c_b)^2) - bias (c = -3/2, -1/2, 1/2, 3/2) are smooth functions on
// an interval of length 1: their Chebyshev interpolants of degree GAUSS_DEGREE are within a
// few units in the last place (tests/test_same_bits.py holds the route within 1e-13 of erf
// and exp at every node). The c's come in pairs +-c, and gauss_primitive is odd and the
// Gaussian even, so each pair is one polynomial p(x) = E(x^2) + x O(x^2) read at x and -x:
// Phi_{-c}(u) = -Phi_c(-u), psi_{-c}(v) = psi_c(-v). Horner's rule on E and O costs a fraction
// of the 8 erf and exp calls per node, and its bits depend on nothing but IEEE adds and
// multiplies. The fit runs in long double.
inline constexpr int GAUSS_DEGREE = 20;
inline constexpr int GAUSS_EVEN = GAUSS_DEGREE / 2 + 1, GAUSS_ODD = (GAUSS_DEGREE + 1) / 2;

struct GaussTable {
    // [h]: the pair c = +-(h + 1/2); even and odd coefficients, the constant term first
    double phi_even[2][GAUSS_EVEN], phi_odd[2][GAUSS_ODD];
    double psi_even[2][GAUSS_EVEN], psi_odd[2][GAUSS_ODD];
};

// the monomial coefficients (in s, constant first) of f's Chebyshev interpolant on [-1/2, 1/2]
template <class F>
inline void chebyshev_monomials(F f, long double* mono) {
    constexpr int N = GAUSS_DEGREE + 1;
    const long double pi = 3.141592653589793238462643383279502884L;
    long double T[N][N] = {};  // T[n][d]: the coefficient of x^d in T_n
    T[0][0] = 1.0L;
    T[1][1] = 1.0L;
    for (int n = 1; n + 1 < N; ++n)
        for (int d = 0; d < N; ++d) T[n + 1][d] = (d > 0 ? 2.0L * T[n][d - 1] : 0.0L) - T[n - 1][d];
    long double values[N], cheb[N];
    for (int j = 0; j < N; ++j) values[j] = f(0.5L * std::cos(pi * (j + 0.5L) / N));  // s = x / 2
    for (int n = 0; n < N; ++n) {
        long double sum = 0.0L;
        for (int j = 0; j < N; ++j) sum += values[j] * std::cos(pi * n * (j + 0.5L) / N);
        cheb[n] = (n == 0 ? 1.0L : 2.0L) * sum / N;
    }
    long double scale = 1.0L;  // x = 2 s: the coefficient of s^d is 2^d times that of x^d
    for (int d = 0; d < N; ++d, scale *= 2.0L) {
        long double m = 0.0L;
        for (int n = d; n < N; ++n) m += cheb[n] * T[n][d];
        mono[d] = m * scale;
    }
}

inline GaussTable gauss_table(double alpha, double bias) {
    const long double a = alpha, b = bias;
    const long double gc = std::sqrt(-a);
    const long double gk = std::sqrt(3.141592653589793238462643383279502884L) / (2.0L * gc);
    GaussTable G;
    long double mono[GAUSS_DEGREE + 1];
    for (int h = 0; h < 2; ++h) {
        const long double c = h + 0.5L;
        chebyshev_monomials([&](long double s) { return gk * std::erf(gc * (s + c)) - b * (s + c); }, mono);
        for (int j = 0; j < GAUSS_EVEN; ++j) G.phi_even[h][j] = double(mono[2 * j]);
        for (int j = 0; j < GAUSS_ODD; ++j) G.phi_odd[h][j] = double(mono[2 * j + 1]);
        chebyshev_monomials([&](long double s) { return std::exp(a * (s + c) * (s + c)) - b; }, mono);
        for (int j = 0; j < GAUSS_EVEN; ++j) G.psi_even[h][j] = double(mono[2 * j]);
        for (int j = 0; j < GAUSS_ODD; ++j) G.psi_odd[h][j] = double(mono[2 * j + 1]);
    }
    return G;
}

// An edge's 12 nodes as three vectors of 4 (GCC's vector extension: element-wise IEEE
// operations, so the bits of scalar code, in vector registers wherever the machine has them)
typedef double v4 __attribute__((vector_size(32)));
struct Nodes {
    v4 r[3];
};

// p(x) = E(x^2) + x O(x^2) at the 12 nodes: hi = p(x), lo = sign * p(-x)
inline void mirrored_pair(const double* E, const double* O, const Nodes& x, double sign, Nodes& hi, Nodes& lo) {
    Nodes x2, e, o;
    for (int r = 0; r < 3; ++r) {
        x2.r[r] = x.r[r] * x.r[r];
        e.r[r] = v4{} + E[GAUSS_EVEN - 1];
        o.r[r] = v4{} + O[GAUSS_ODD - 1];
    }
    for (int j = GAUSS_EVEN - 2; j >= 0; --j)
        for (int r = 0; r < 3; ++r) e.r[r] = e.r[r] * x2.r[r] + E[j];
    for (int j = GAUSS_ODD - 2; j >= 0; --j)
        for (int r = 0; r < 3; ++r) o.r[r] = o.r[r] * x2.r[r] + O[j];
    for (int r = 0; r < 3; ++r) {
        const v4 xo = x.r[r] * o.r[r];
        hi.r[r] = e.r[r] + xo;
        lo.r[r] = sign * (e.r[r] - xo);
    }
}

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
// rounding of the recorded route's, tests/test_same_bits.py)
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

// Scratch for clip_box: two halves of 16 n + 16 vertices each (a line clip adds at most one
// vertex per edge: 4 clips stay below 16 n).
struct BoxBuffers {
    std::vector<double> x, y;
    std::vector<uint8_t> f, flags;
    int64_t half = 0;
    void reserve_for(int64_t n) {
        if (half < 16 * n + 16) {
            half = 16 * n + 16;
            x.resize(size_t(2 * half));
            y.resize(size_t(2 * half));
            f.resize(size_t(2 * half));
        }
    }
};

struct Ring {
    int64_t start, n;
};

// Sutherland-Hodgman clip of one ring to [x0, x1] x [y0, y1]; (start, count) in the buffers,
// count 0 when less than a polygon is left. A concave ring may come back with zero-width
// bridges along the box's sides; they bound no area and cancel in every edge integral.
inline Ring clip_box(const double* xs, const double* ys, int64_t start, int64_t n, double x0, double x1, double y0,
                     double y1, BoxBuffers& B) {
    B.reserve_for(n);
    const int64_t half = B.half;
    double* bx = B.x.data();
    double* by = B.y.data();
    uint8_t* bf = B.f.data();
    B.flags.assign(size_t(n), 0);
    int64_t m = geometry::clip_side(xs + start, ys + start, B.flags.data(), 0, n, 1.0, 0.0, -x0, 1, bx, by, bf, 0);
    if (m < 3) return {0, 0};
    m = geometry::clip_side(bx, by, bf, 0, m, 1.0, 0.0, -x1, -1, bx, by, bf, half);
    if (m < 3) return {0, 0};
    m = geometry::clip_side(bx, by, bf, half, m, 0.0, 1.0, -y0, 1, bx, by, bf, 0);
    if (m < 3) return {0, 0};
    m = geometry::clip_side(bx, by, bf, 0, m, 0.0, 1.0, -y1, -1, bx, by, bf, half);
    if (m < 3) return {0, 0};
    return {half, m};
}

inline int64_t floor_index(double v) {
    const double f = std::floor(v);
    if (!(f > -4.0e18)) return -int64_t(4000000000000000000LL);
    if (f > 4.0e18) return int64_t(4000000000000000000LL);
    return int64_t(f);
}

// Cut every ring on the knot grid (inside the image) and accumulate its integrals per cell:
// acc[n, m, a, b, c] += weights[r, c] * integrals[a, b] of ring r's part in cell (m, n)
// (acc of shape (H + 1, W + 1, k, k, nch)). Rings are signed: holes subtract.
inline void accumulate_rings(const double* xs, const double* ys, const int64_t* starts, const int64_t* lengths,
                             int64_t n_rings, const double* weights, int64_t nch, int64_t width, int64_t height,
                             const Filter& F, double* acc) {
    const int64_t k = F.k;
    std::vector<double> out(static_cast<size_t>(k * k)), phi(static_cast<size_t>(k)), psi(static_cast<size_t>(k));
    BoxBuffers band, cell;
    for (int64_t r = 0; r < n_rings; ++r) {
        const int64_t s = starts[r];
        const int64_t n = lengths[r];
        if (n < 3) continue;
        double xmin = xs[s], xmax = xs[s], ymin = ys[s], ymax = ys[s];
        for (int64_t i = s + 1; i < s + n; ++i) {
            if (xs[i] < xmin) xmin = xs[i];
            if (xs[i] > xmax) xmax = xs[i];
            if (ys[i] < ymin) ymin = ys[i];
            if (ys[i] > ymax) ymax = ys[i];
        }
        const int64_t m0 = geometry::pymax(int64_t(0), floor_index(xmin + 0.5));
        const int64_t m1 = geometry::pymin(width, floor_index(xmax + 0.5));
        const int64_t n0 = geometry::pymax(int64_t(0), floor_index(ymin + 0.5));
        const int64_t n1 = geometry::pymin(height, floor_index(ymax + 0.5));
        for (int64_t row = n0; row <= n1; ++row) {
            const double y0 = geometry::pymax(double(row) - 0.5, 0.0);
            const double y1 = geometry::pymin(double(row) + 0.5, double(height));
            // the band of this cell row, then each cell of it
            const Ring b = clip_box(xs, ys, s, n, 0.0, double(width), y0, y1, band);
            if (b.n < 3) continue;
            const double* bx = band.x.data();
            double bmin = bx[b.start], bmax = bx[b.start];
            for (int64_t i = b.start + 1; i < b.start + b.n; ++i) {
                if (bx[i] < bmin) bmin = bx[i];
                if (bx[i] > bmax) bmax = bx[i];
            }
            const int64_t c0 = geometry::pymax(m0, floor_index(bmin + 0.5));
            const int64_t c1 = geometry::pymin(m1, floor_index(bmax + 0.5));
            for (int64_t col = c0; col <= c1; ++col) {
                const double x0 = geometry::pymax(double(col) - 0.5, 0.0);
                const double x1 = geometry::pymin(double(col) + 0.5, double(width));
                const Ring c = clip_box(band.x.data(), band.y.data(), b.start, b.n, x0, x1, y0, y1, cell);
                if (c.n < 3) continue;
                piece_integrals(cell.x.data(), cell.y.data(), c.start, c.n, double(col), double(row), F, out.data(),
                                phi.data(), psi.data());
                double* cellacc = acc + ((row * (width + 1) + col) * k * k) * nch;
                for (int64_t a = 0; a < k; ++a)
                    for (int64_t bb = 0; bb < k; ++bb)
                        for (int64_t ch = 0; ch < nch; ++ch)
                            cellacc[(a * k + bb) * nch + ch] += weights[r * nch + ch] * out[size_t(a * k + bb)];
            }
        }
    }
}

// Pixels from knot cells (combine_cells in aaeval/filters/integrate.py): pixel i takes piece
// p = m - i - 1 (p = -R .. R-1) of the filter from cell m; separable, x contracted first
// (contract_x_row: a row of cells (W + 1, k, k, nch) into t (k, W, nch)), then y
// (contract_y_rows: rows of t into pixel rows (W, nch)). e: (2R, k), the cell-local
// coefficients. The sums run in the order numpy's einsum took them in (each term's basis sum
// from 0, then the pieces in turn from 0), so the bits are numpy's; cells outside the image
// add nothing (numpy added zeros, which change no sum).
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

#define AAEVAL_KC_DISPATCH(fn, k, nch, ...)                                  \
    do {                                                                     \
        if ((k) == 2 && (nch) == 3) return fn<2, 3>(__VA_ARGS__);            \
        if ((k) == 4 && (nch) == 3) return fn<4, 3>(__VA_ARGS__);            \
        if ((k) == 2 && (nch) == 4) return fn<2, 4>(__VA_ARGS__);            \
        if ((k) == 4 && (nch) == 4) return fn<4, 4>(__VA_ARGS__);            \
        return fn<0, 0>(__VA_ARGS__);                                        \
    } while (0)

inline void contract_x_row(const double* cells, const double* e, int64_t R, int64_t k, int64_t nch, int64_t width,
                           double* t) {
    AAEVAL_KC_DISPATCH(contract_x_row_k, k, nch, cells, e, R, k, nch, width, t);
}
inline void contract_y_rows(const double* t, int64_t n0, int64_t n1, const double* e, int64_t R, int64_t k,
                            int64_t nch, int64_t width, int64_t j0, int64_t j1, double* image) {
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

// The Catmull kernel's sink for an exact filter. The kernel runs on the scene moved by
// (1/2, 1/2) at (W + 1) x (H + 1) pixels, which are exactly the knot cells, so every visible
// piece lies in one cell; its integrals times its colour go to acc[n, m, a, b, channel].
// Cells on the image border are cut to the image first (samples lie only inside it).
// colors: n_colors rows (the background last); `emitted` holds what the current cell has
// received (for emit_rest). One sink per band: bands write disjoint rows of acc.
struct MomentSink {
    // integrals are linear in the pieces: a visible part may come as a piece less another
    // (sweep.hpp's two-layer case); signed_pieces off gives the integrator's pieces instead
    // (the recorded route, tests/test_same_bits.py)
    static constexpr bool SIGNED_PIECES = true;
    static constexpr bool COLUMN_PARTS = true;
    bool signed_pieces = true;
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
        : acc(acc_), colors(colors_), n_colors(n_colors_), width(width_), height(height_), F(F_),
          out(size_t(F_.k * F_.k)), emitted(size_t(F_.k * F_.k), 0.0), phi(size_t(F_.k)), psi(size_t(F_.k)) {}

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
        if (F.k == 2) contract_row_k<2>();
        else if (F.k == 4) contract_row_k<4>();
        else contract_row_k<0>();
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
        if (scale == 1.0) {  // most pieces: 1.0 * o is o (the same bits without the product)
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
        return {row, col, geometry::pymax(double(col), 0.5), geometry::pymin(double(col) + 1.0, double(width) + 0.5),
                geometry::pymax(double(row), 0.5), geometry::pymin(double(row) + 1.0, double(height) + 0.5)};
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
        piece_integrals(box.x.data(), box.y.data(), r.start, r.n, ox, oy, F, out.data(), phi.data(), psi.data(), &sides);
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
        sx[0] = w.x0; sy[0] = w.y0;
        sx[1] = w.x1; sy[1] = w.y0;
        sx[2] = w.x1; sy[2] = w.y1;
        sx[3] = w.x0; sy[3] = w.y1;
        piece_integrals(sx, sy, 0, 4, double(w.col) + 0.5, double(w.row) + 0.5, F, out.data(), phi.data(), psi.data(), &sides);
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

