// The Phong shade integrated over triangles: a collapsed (Duffy) Gauss-Legendre rule on
// each triangle, refined by longest-edge bisection where the rule and its two halves
// disagree (the disagreement is the error estimate kept for the pixel), and bisected
// ahead of that test where the triangle's normals spread wider than the highlight lobe
// near the lobe's peak (a lobe narrower than the rule's node spacing can fall between
// the nodes of both estimates, which would then agree on a wrong value).
#pragma once

#include <cmath>
#include <cstdint>

namespace aaeval::shading {

inline constexpr int RULE = 6;  // Gauss-Legendre points per axis of the collapsed square
inline constexpr int MAX_DEPTH = 20;  // bisections of one fan triangle, at most

// Gauss-Legendre nodes and weights on [0, 1], by Newton's method on P_RULE.
struct Rule {
    double t[RULE], w[RULE];
    Rule() {
        for (int i = 0; i < RULE; ++i) {
            double x = std::cos(M_PI * (i + 0.75) / (RULE + 0.5)), dp = 1.0;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1.0, p1 = x;
                for (int k = 2; k <= RULE; ++k) {
                    const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = RULE * (x * p1 - p0) / (x * x - 1.0);
                const double dx = p1 / dp;
                x -= dx;
                if (std::fabs(dx) < 1e-17) break;
            }
            t[i] = 0.5 * (1.0 - x);
            w[i] = 1.0 / ((1.0 - x * x) * dp * dp);  // 2 / ((1 - x^2) P'^2), halved for [0, 1]
        }
    }
};

inline const Rule& rule() {
    static const Rule r;
    return r;
}

// The shade's parameters for one polygon in one pixel: normal field N = normalise(G (x, y, 1)),
// the light (directional: unit vector; point: position, depth from the plane), and the
// (possibly clamped) exponent and specular coefficient.
struct Shade {
    const double* G;      // 3 x 3, row-major
    const double* plane;  // z = a x + b y + c
    bool point_light;
    const double* light;
    double n, ks;
    double sigma;  // angular width of the lobe in normal angle, 1 / (2 sqrt n) (inf when n = 0)
};

struct Value {
    double diffuse = 0.0, spec = 0.0;  // integrals of max(N.L, 0) and ks max(R.E, 0)^n
};

inline void unit_normal(const Shade& s, double x, double y, double* N) {
    const double* G = s.G;
    double v[3];
    for (int r = 0; r < 3; ++r) v[r] = G[3 * r] * x + G[3 * r + 1] * y + G[3 * r + 2];
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int r = 0; r < 3; ++r) N[r] = v[r] / len;
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

// the documented Phong terms at one point (E = (0, 0, -1))
inline Value shade_at(const Shade& s, double x, double y) {
    double N[3], L[3];
    unit_normal(s, x, y, N);
    light_at(s, x, y, L);
    const double ndl = N[0] * L[0] + N[1] * L[1] + N[2] * L[2];
    const double rde = std::fmax(-(2.0 * ndl * N[2] - L[2]), 0.0);
    Value v;
    v.diffuse = std::fmax(ndl, 0.0);
    v.spec = s.ks * (s.n == 0.0 ? 1.0 : std::pow(rde, s.n));
    return v;
}

struct Tri {
    double ax, ay, bx, by, cx, cy;
    double area() const { return 0.5 * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)); }  // signed
};

// The collapsed rule: (u, v) in [0, 1]^2 -> A + u (B - A) + u v (C - B), Jacobian 2 |T| u.
inline Value rule_on(const Shade& s, const Tri& T, int64_t& evals) {
    const Rule& R = rule();
    const double twice = 2.0 * T.area();
    Value sum;
    for (int i = 0; i < RULE; ++i) {
        const double u = R.t[i];
        const double px = T.ax + u * (T.bx - T.ax), py = T.ay + u * (T.by - T.ay);
        const double qx = u * (T.cx - T.bx), qy = u * (T.cy - T.by);
        double d = 0.0, sp = 0.0;
        for (int j = 0; j < RULE; ++j) {
            const Value f = shade_at(s, px + R.t[j] * qx, py + R.t[j] * qy);
            d += R.w[j] * f.diffuse;
            sp += R.w[j] * f.spec;
        }
        sum.diffuse += R.w[i] * u * d;
        sum.spec += R.w[i] * u * sp;
    }
    evals += RULE * RULE;
    sum.diffuse *= twice;
    sum.spec *= twice;
    return sum;
}

inline double angle_between(const double* a, const double* b) {
    const double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

// Whether the triangle's normals spread wider than the lobe while the lobe's peak (normal
// H = normalise(L + E)) is within 10 lobe widths of them: then it is bisected before any
// error test.
inline bool lobe_unresolved(const Shade& s, const Tri& T) {
    if (!(s.sigma < 1.0) || s.ks == 0.0) return false;
    const double gx = (T.ax + T.bx + T.cx) / 3.0, gy = (T.ay + T.by + T.cy) / 3.0;
    double Nc[3], Nv[3], L[3], H[3];
    unit_normal(s, gx, gy, Nc);
    double radius = 0.0;
    const double vx[3] = {T.ax, T.bx, T.cx}, vy[3] = {T.ay, T.by, T.cy};
    for (int k = 0; k < 3; ++k) {
        unit_normal(s, vx[k], vy[k], Nv);
        radius = std::fmax(radius, angle_between(Nc, Nv));
    }
    if (radius <= s.sigma) return false;
    light_at(s, gx, gy, L);
    H[0] = L[0];
    H[1] = L[1];
    H[2] = L[2] - 1.0;
    const double len = std::sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    if (len == 0.0) return false;
    for (double& h : H) h /= len;
    return angle_between(Nc, H) - radius < 10.0 * s.sigma;
}

// The triangle's two halves, split at the midpoint of its longest edge (orientation kept).
inline void bisect(const Tri& T, Tri& t1, Tri& t2) {
    const double ab = (T.bx - T.ax) * (T.bx - T.ax) + (T.by - T.ay) * (T.by - T.ay);
    const double bc = (T.cx - T.bx) * (T.cx - T.bx) + (T.cy - T.by) * (T.cy - T.by);
    const double ca = (T.ax - T.cx) * (T.ax - T.cx) + (T.ay - T.cy) * (T.ay - T.cy);
    if (ab >= bc && ab >= ca) {
        const double mx = 0.5 * (T.ax + T.bx), my = 0.5 * (T.ay + T.by);
        t1 = {T.ax, T.ay, mx, my, T.cx, T.cy};
        t2 = {mx, my, T.bx, T.by, T.cx, T.cy};
    } else if (bc >= ca) {
        const double mx = 0.5 * (T.bx + T.cx), my = 0.5 * (T.by + T.cy);
        t1 = {T.ax, T.ay, T.bx, T.by, mx, my};
        t2 = {T.ax, T.ay, mx, my, T.cx, T.cy};
    } else {
        const double mx = 0.5 * (T.cx + T.ax), my = 0.5 * (T.cy + T.ay);
        t1 = {T.ax, T.ay, T.bx, T.by, mx, my};
        t2 = {mx, my, T.bx, T.by, T.cx, T.cy};
    }
}

struct Integral {
    Value value;
    double bound = 0.0;  // estimated error of value, in the image's units (diffuse weighted by w_diffuse)
    int64_t evals = 0;
};

// Adaptive integral over T given its rule value q: accepted once |q - (q1 + q2)| is within
// tol per unit area (tol_area) of T, the halves' sum kept with that difference as its bound.
inline void adapt(const Shade& s, const Tri& T, const Value& q, double w_diffuse, double tol_area, int depth,
                  Integral& out) {
    Tri t1, t2;
    bisect(T, t1, t2);
    const Value q1 = rule_on(s, t1, out.evals), q2 = rule_on(s, t2, out.evals);
    const double err = w_diffuse * std::fabs(q.diffuse - q1.diffuse - q2.diffuse) + std::fabs(q.spec - q1.spec - q2.spec);
    const bool forced = depth < MAX_DEPTH && lobe_unresolved(s, T);
    if (!forced && (err <= tol_area * std::fabs(T.area()) + 1e-16 || depth >= MAX_DEPTH)) {
        out.value.diffuse += q1.diffuse + q2.diffuse;
        out.value.spec += q1.spec + q2.spec;
        out.bound += err;
        return;
    }
    adapt(s, t1, q1, w_diffuse, tol_area, depth + 1, out);
    adapt(s, t2, q2, w_diffuse, tol_area, depth + 1, out);
}

inline void integrate_triangle(const Shade& s, const Tri& T, double w_diffuse, double tol_area, Integral& out) {
    if (T.area() == 0.0) return;
    adapt(s, T, rule_on(s, T, out.evals), w_diffuse, tol_area, 0, out);
}

// A polygon xs, ys[start .. start + n) as the fan from its first vertex (signed triangles:
// exact for any simple outline, the shade being smooth on the whole plane of the pixel).
inline void integrate_polygon(const Shade& s, const double* xs, const double* ys, int64_t start, int64_t n,
                              double w_diffuse, double tol_area, Integral& out) {
    for (int64_t i = 1; i + 1 < n; ++i) {
        const Tri T{xs[start], ys[start], xs[start + i], ys[start + i], xs[start + i + 1], ys[start + i + 1]};
        integrate_triangle(s, T, w_diffuse, tol_area, out);
    }
}

}  // namespace aaeval::shading
