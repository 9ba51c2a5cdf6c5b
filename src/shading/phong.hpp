// The Phong model as the exact renderer evaluates it at one point of one polygon: the
// normal field interpolated by G, the light (directional or a point), the diffuse term
// max(N.L, 0) and the specular lobe ks max(R.E, 0)^n with E = (0, 0, -1). The quadrature
// (quadrature.hpp) integrates it over a pixel's pieces.
#pragma once

#include <cmath>
#include <cstdint>

namespace aaeval::shading {

// The shade's parameters for one polygon in one pixel: normal field N = normalise(G (x, y, 1)),
// the light (directional: unit vector; point: position, depth from the plane), and the
// (possibly clamped) exponent and specular coefficient.
struct Shade {
    double G[9];      // 3 x 3, row-major
    double plane[3];  // z = a x + b y + c
    bool point_light;
    double light[3];
    double n, ks;
    double sigma;  // angular width of the lobe in normal angle, 1 / (2 sqrt n) (inf when n = 0)
};

// The same shade in coordinates whose origin is (ox, oy): (x, y) there is (x + ox, y + oy)
// here. In image coordinates G's constant column is about the image position times its slope
// (74 at x = 250 on a thin cylinder), and G (x, y, 1) cancels it down to a unit normal: its
// rounding (1e-14 of the normal, 1e-11 of a lobe with n = 1000) is noise the error estimate
// cannot refine away, and it drove pixels to 700,000 evaluations. Near the origin nothing
// cancels.
inline Shade shifted(const Shade& s, double ox, double oy) {
    Shade l = s;
    for (int r = 0; r < 3; ++r) l.G[3 * r + 2] = s.G[3 * r] * ox + s.G[3 * r + 1] * oy + s.G[3 * r + 2];
    l.plane[2] = s.plane[0] * ox + s.plane[1] * oy + s.plane[2];
    if (s.point_light) {
        l.light[0] = s.light[0] - ox;
        l.light[1] = s.light[1] - oy;
    }
    return l;
}

struct Value {
    double diffuse = 0.0, spec = 0.0;  // integrals of max(N.L, 0) and ks max(R.E, 0)^n
};

inline void unit_normal(const Shade& s, double x, double y, double* N) {
    const double* G = s.G;
    double v[3];
    for (int r = 0; r < 3; ++r) v[r] = G[3 * r] * x + G[3 * r + 1] * y + G[3 * r + 2];
    const double inv = 1.0 / std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);  // one division, not three
    for (int r = 0; r < 3; ++r) N[r] = v[r] * inv;
}

inline void light_at(const Shade& s, double x, double y, double* L) {
    if (!s.point_light) {
        L[0] = s.light[0];
        L[1] = s.light[1];
        L[2] = s.light[2];
        return;
    }
    const double z = s.plane[0] * x + s.plane[1] * y + s.plane[2];
    double d[3] = {s.light[0] - x, s.light[1] - y, s.light[2] - z};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int r = 0; r < 3; ++r) L[r] = d[r] / len;
}

// x^n for x in [0, 1]: by repeated squaring where n is a whole number below 2^16 (the
// shipped exponents; about a tenth of std::pow's time, which dominated the evaluations),
// std::pow otherwise (a clamp's fractional n'). Both are within a few ulps of x^n.
inline double lobe(double x, double n) {
    if (n == 0.0) return 1.0;
    if (n == std::floor(n) && n < 65536.0) {
        unsigned k = unsigned(n);
        double r = 1.0, b = x;
        while (k) {
            if (k & 1u) r *= b;
            b *= b;
            k >>= 1;
        }
        return r;
    }
    return std::pow(x, n);
}

// the documented Phong terms at one point (E = (0, 0, -1))
inline Value shade_at(const Shade& s, double x, double y) {
    double N[3], L[3];
    unit_normal(s, x, y, N);
    light_at(s, x, y, L);
    const double ndl = N[0] * L[0] + N[1] * L[1] + N[2] * L[2];
    const double rde = std::fmax(-(2.0 * ndl * N[2] - L[2]), 0.0);
    Value v;
    v.diffuse = std::fmax(ndl, 0.0);
    v.spec = s.ks * lobe(rde, s.n);
    return v;
}

}  // namespace aaeval::shading
