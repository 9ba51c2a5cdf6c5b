// The exact filters' basis on a knot cell [m - 1/2, m + 1/2] x [n - 1/2, n + 1/2] (see
// aaeval/filters/integrate.py for the maths): the filter's description (Filter), the
// Gauss-Legendre nodes the edge integrals use, and the Gaussian's basis as polynomials
// (gauss_table) read at an edge's nodes four at a time (Nodes, mirrored_pair).
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>

namespace aaeval::catmull {

inline constexpr int64_t KIND_POLYNOMIAL = 1;
inline constexpr int64_t KIND_GAUSSIAN = 2;

// Gauss-Legendre nodes and weights on [0, 1] (numpy's leggauss, moved there): 4 points are
// exact for the degree-7 edge polynomials of cubic filters (and the tent's on the plain
// route); 12 for the Gaussian's edges.
inline constexpr double POLY_T[4] = {0x1.1c6490c2719ecp-4, 0x1.51ee013116102p-2, 0x1.5708ff6774f7fp-1,
                                     0x1.dc736de7b1cc2p-1};
inline constexpr double POLY_W[4] = {0x1.64340f7e7b666p-3, 0x1.4de5f840c24cdp-2, 0x1.4de5f840c24cdp-2,
                                     0x1.64340f7e7b666p-3};
inline constexpr double GAUSS_T[12] = {0x1.2e1c4e37a2fe0p-7, 0x1.88bc58023ba68p-5, 0x1.d73d4449dc328p-4,
                                       0x1.a6961f47f100ep-3, 0x1.43ab96faba732p-2, 0x1.bfe1681c273c7p-2,
                                       0x1.200f4bf1ec61cp-1, 0x1.5e2a3482a2c67p-1, 0x1.965a782e03bfcp-1,
                                       0x1.c5185776c479bp-1, 0x1.e7743a7fdc45ap-1, 0x1.fb478ec721740p-1};
inline constexpr double GAUSS_W[12] = {0x1.8275d9dea6d53p-6, 0x1.b60602bce61afp-5, 0x1.47d7258f22d96p-4,
                                       0x1.a0163e6b1ab6bp-4, 0x1.de3155c256aaep-4, 0x1.fe40ce6d4f022p-4,
                                       0x1.fe40ce6d4f022p-4, 0x1.de3155c256aaep-4, 0x1.a0163e6b1ab6bp-4,
                                       0x1.47d7258f22d96p-4, 0x1.b60602bce61afp-5, 0x1.8275d9dea6d53p-6};

// fast: the route the Catmull kernel's sink takes (render_filter in module.cpp), where
// piece_integrals takes the tent's four integrals in closed form, a cubic's edge nodes four
// at a time, and the Gaussian's basis from gauss (its polynomials, gauss_table below); the
// plain route (false, gauss null: the rings of accumulate_rings and the stage bindings)
// integrates by Gauss-Legendre one node at a time with erf and exp at every node.
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
// few units in the last place of erf and exp at every node (tests/filters/test_filters.py holds
// the images within 1e-9 of the quadrature oracle). The c's come in pairs +-c, and gauss_primitive is odd and the
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

}  // namespace aaeval::catmull
