// The Phong shade integrated over triangles: a collapsed (Duffy) Gauss-Legendre rule on
// each triangle, refined into quarters where the rule and its four quarters disagree
// (the disagreement is the error estimate kept for the pixel), and quartered ahead of
// that test where the triangle's normals spread wider than the highlight lobe
// near the lobe's peak (a lobe narrower than the rule's node spacing can fall between
// the nodes of both estimates, which would then agree on a wrong value).
#pragma once

#include <cmath>
#include <cstdint>

#include "shading/phong.hpp"

namespace aaeval::shading {

inline constexpr int RULE = 6;  // Gauss-Legendre points per axis of the collapsed square
inline constexpr int MAX_DEPTH = 12;  // subdivisions of one fan triangle (into quarters, or by a kink), at most

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

struct Tri {
    double ax, ay, bx, by, cx, cy;
    double area() const { return 0.5 * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)); }  // signed
};

// One row of the rule (RULE nodes at once) for a directional light: the same operations
// as shade_at node by node, written as loops over the row so the compiler vectorises them
// (the normal's square root and division, the lobe's squarings); each node's value is the
// one IEEE result shade_at gives (no contraction, no reassociation), only computed side by side.
inline void shade_row_directional(const Shade& s, const double* xs, const double* ys, double* dif, double* spec) {
    const double* G = s.G;
    const double L0 = s.light[0], L1 = s.light[1], L2 = s.light[2];
    double b[RULE];
    for (int j = 0; j < RULE; ++j) {
        const double v0 = G[0] * xs[j] + G[1] * ys[j] + G[2];
        const double v1 = G[3] * xs[j] + G[4] * ys[j] + G[5];
        const double v2 = G[6] * xs[j] + G[7] * ys[j] + G[8];
        const double inv = 1.0 / std::sqrt(v0 * v0 + v1 * v1 + v2 * v2);
        const double n0 = v0 * inv, n1 = v1 * inv, n2 = v2 * inv;
        const double ndl = n0 * L0 + n1 * L1 + n2 * L2;
        const double r = -(2.0 * ndl * n2 - L2);
        dif[j] = ndl > 0.0 ? ndl : 0.0;  // max(., 0), branch-free (a NaN gives 0 as fmax does)
        b[j] = r > 0.0 ? r : 0.0;
    }
    const double n = s.n;
    if (n == 0.0) {
        for (int j = 0; j < RULE; ++j) spec[j] = s.ks * 1.0;
    } else if (n == std::floor(n) && n < 65536.0) {  // lobe()'s repeated squaring, the row side by side
        double acc[RULE];
        for (int j = 0; j < RULE; ++j) acc[j] = 1.0;
        for (unsigned k = unsigned(n); k; k >>= 1) {
            if (k & 1u)
                for (int j = 0; j < RULE; ++j) acc[j] *= b[j];
            for (int j = 0; j < RULE; ++j) b[j] *= b[j];
        }
        for (int j = 0; j < RULE; ++j) spec[j] = s.ks * acc[j];
    } else {
        for (int j = 0; j < RULE; ++j) spec[j] = s.ks * std::pow(b[j], n);
    }
}

// The collapsed rule: (u, v) in [0, 1]^2 -> A + u (B - A) + u v (C - B), Jacobian 2 |T| u.
inline Value rule_on(const Shade& s, const Tri& T, int64_t& evals) {
    const Rule& R = rule();
    const double twice = 2.0 * T.area();
    Value sum;
    for (int i = 0; i < RULE; ++i) {
        const double u = R.t[i];
        const double px = T.ax + u * (T.bx - T.ax), py = T.ay + u * (T.by - T.ay);
        const double qx = u * (T.cx - T.bx), qy = u * (T.cy - T.by);
        double xs[RULE], ys[RULE], dif[RULE], spec[RULE];
        for (int j = 0; j < RULE; ++j) {
            xs[j] = px + R.t[j] * qx;
            ys[j] = py + R.t[j] * qy;
        }
        if (s.point_light) {
            for (int j = 0; j < RULE; ++j) {
                const Value f = shade_at(s, xs[j], ys[j]);
                dif[j] = f.diffuse;
                spec[j] = f.spec;
            }
        } else {
            shade_row_directional(s, xs, ys, dif, spec);
        }
        double d = 0.0, sp = 0.0;
        for (int j = 0; j < RULE; ++j) {
            d += R.w[j] * dif[j];
            sp += R.w[j] * spec[j];
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
// H = normalise(L + E)) is within 10 lobe widths of them: then it is quartered before any
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

// T's four halves-in-both-directions (the medial subdivision; orientation kept). Refining
// by longest-edge bisection instead halves one direction only: where the rule's error lies
// along the other, the halves carry the parent's error and agree with it, and the estimate
// |q - (q1 + q2)| read 5e-15 where the error was 3.7e-11 (a wide n = 50 highlight).
inline void quarter(const Tri& T, Tri* c) {
    const double abx = 0.5 * (T.ax + T.bx), aby = 0.5 * (T.ay + T.by);
    const double bcx = 0.5 * (T.bx + T.cx), bcy = 0.5 * (T.by + T.cy);
    const double cax = 0.5 * (T.cx + T.ax), cay = 0.5 * (T.cy + T.ay);
    c[0] = {T.ax, T.ay, abx, aby, cax, cay};
    c[1] = {abx, aby, T.bx, T.by, bcx, bcy};
    c[2] = {cax, cay, bcx, bcy, T.cx, T.cy};
    c[3] = {abx, aby, bcx, bcy, cax, cay};
}

// Adaptive integral over T given its rule value q: accepted once |q - (sum of the quarters)|
// is within tol per unit area (tol_area) of T, the quarters' sum kept with that difference
// as its bound (the quarters' own error is about 2^-12 of it for a smooth shade).
inline void adapt(const Shade& s, const Tri& T, const Value& q, double w_diffuse, double tol_area, int depth,
                  Integral& out) {
    Tri c[4];
    quarter(T, c);
    Value qc[4], sum;
    for (int i = 0; i < 4; ++i) {
        qc[i] = rule_on(s, c[i], out.evals);
        sum.diffuse += qc[i].diffuse;
        sum.spec += qc[i].spec;
    }
    const double err = w_diffuse * std::fabs(q.diffuse - sum.diffuse) + std::fabs(q.spec - sum.spec);
    const bool forced = depth < MAX_DEPTH && lobe_unresolved(s, T);
    if (!forced && (err <= tol_area * std::fabs(T.area()) + 1e-16 || depth >= MAX_DEPTH)) {
        out.value.diffuse += sum.diffuse;
        out.value.spec += sum.spec;
        out.bound += err;
        return;
    }
    for (int i = 0; i < 4; ++i) adapt(s, c[i], qc[i], w_diffuse, tol_area, depth + 1, out);
}

// --- kinks: where max(., 0) cuts the shade ----------------------------------------------
// max(N.L, 0) (the terminator) and max(R.E, 0)^n for small n have a kink (a jump in the
// gradient) inside a triangle. A Gauss rule is not exact there, and its error estimate
// is blind to a kink that cuts a corner no node of the rule or its halves falls in (the
// silhouette pixels of a cylinder lit from near the viewer were 2.4e-6 off with a bound
// of 1e-17). So a triangle is cut along each kink first, and every part is smooth.
// Kink functions, with the sign of the max's argument:
//   diffuse: k = (G p) . L, p = (x, y, 1) (N.L times |G p|): linear in (x, y) for a
//            directional light, so the cut is exact; curved for a point light;
//   specular (n < SPEC_KINK_N only; above it the lobe is C^15 at its kink and the rule
//            resolves it): k = L_z |G p|^2 - 2 (G p . L) (G p)_z (R.E times |G p|^2).
inline constexpr double SPEC_KINK_N = 16.0;

inline double kink_at(const Shade& s, int which, double x, double y) {
    const double* G = s.G;
    double v[3], L[3];
    for (int r = 0; r < 3; ++r) v[r] = G[3 * r] * x + G[3 * r + 1] * y + G[3 * r + 2];
    light_at(s, x, y, L);
    const double vl = v[0] * L[0] + v[1] * L[1] + v[2] * L[2];
    if (which == 0) return vl;
    return L[2] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - 2.0 * vl * v[2];
}

inline bool has_kink(const Shade& s, int which) {
    return which == 0 || (s.ks != 0.0 && s.n > 0.0 && s.n < SPEC_KINK_N);
}

// the point where the kink crosses the edge from (ax, ay), k = ka to (bx, by), k = kb (signs
// opposite): regula falsi (Illinois), exact in one step when k is linear along the edge
inline void kink_root(const Shade& s, int which, double ax, double ay, double ka, double bx, double by, double kb,
                      double& rx, double& ry) {
    double t0 = 0.0, t1 = 1.0, k0 = ka, k1 = kb, t = 0.5;
    int side = 0;
    for (int it = 0; it < 60; ++it) {
        t = (t0 * k1 - t1 * k0) / (k1 - k0);
        if (!(t > t0 && t < t1)) t = 0.5 * (t0 + t1);
        const double k = kink_at(s, which, ax + t * (bx - ax), ay + t * (by - ay));
        if (k == 0.0 || t1 - t0 < 1e-16) break;
        if ((k > 0.0) == (k0 > 0.0)) {
            t0 = t;
            k0 = k;
            if (side == -1) k1 *= 0.5;
            side = -1;
        } else {
            t1 = t;
            k1 = k;
            if (side == 1) k0 *= 0.5;
            side = 1;
        }
        if (std::fabs(k) < 1e-300) break;
    }
    rx = ax + t * (bx - ax);
    ry = ay + t * (by - ay);
}

// T cut along kinks which..1 and integrated part by part. A curved kink is cut along the
// chord between its edge crossings; the sliver between chord and curve (its width at the
// chord's middle, |k| / |grad k|, times 2/3 of the chord's length, times the shade's
// largest value there) is added to the bound, after bisecting T while it is above tolerance.
inline void integrate_smooth(const Shade& s, const Tri& T, double w_diffuse, double tol_area, int which, int depth,
                             Integral& out) {
    if (T.area() == 0.0) return;
    while (which < 2 && !has_kink(s, which)) ++which;
    if (which >= 2) {
        adapt(s, T, rule_on(s, T, out.evals), w_diffuse, tol_area, 0, out);
        return;
    }
    const double vx[3] = {T.ax, T.bx, T.cx}, vy[3] = {T.ay, T.by, T.cy};
    double k[3];
    int pos = 0, neg = 0;
    for (int i = 0; i < 3; ++i) {
        k[i] = kink_at(s, which, vx[i], vy[i]);
        pos += k[i] > 0.0;
        neg += k[i] < 0.0;
    }
    out.evals += 3;
    if (pos == 0 || neg == 0) {  // one side (a vertex on the kink counts as either)
        integrate_smooth(s, T, w_diffuse, tol_area, which + 1, depth, out);
        return;
    }
    // the lone vertex: the one whose sign the other two (or the other non-zero one) do not share
    int lone = 0;
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, l = (i + 2) % 3;
        const bool oi = k[i] > 0.0, oj = k[j] > 0.0, ol = k[l] > 0.0;
        if (k[i] != 0.0 && (k[j] == 0.0 || oj != oi) && (k[l] == 0.0 || ol != oi)) {
            lone = i;
            break;
        }
    }
    const int j = (lone + 1) % 3, l = (lone + 2) % 3;
    double r1x = vx[j], r1y = vy[j], r2x = vx[l], r2y = vy[l];
    if (k[j] != 0.0) kink_root(s, which, vx[lone], vy[lone], k[lone], vx[j], vy[j], k[j], r1x, r1y);
    if (k[l] != 0.0) kink_root(s, which, vx[lone], vy[lone], k[lone], vx[l], vy[l], k[l], r2x, r2y);
    out.evals += 2;
    // the chord's distance from the kink at its middle (zero for a straight kink)
    const double mx = 0.5 * (r1x + r2x), my = 0.5 * (r1y + r2y);
    const double h = 1e-6 * (std::fabs(r2x - r1x) + std::fabs(r2y - r1y)) + 1e-12;
    const double km = kink_at(s, which, mx, my);
    const double gx = (kink_at(s, which, mx + h, my) - kink_at(s, which, mx - h, my)) / (2.0 * h);
    const double gy = (kink_at(s, which, mx, my + h) - kink_at(s, which, mx, my - h)) / (2.0 * h);
    out.evals += 5;
    const double gap = std::fabs(km) / std::fmax(std::sqrt(gx * gx + gy * gy), 1e-300);
    const double chord = std::hypot(r2x - r1x, r2y - r1y);
    // in the sliver the max's argument is at most |k| at the chord's middle over |G p| (diffuse)
    // or |G p|^2 (specular, then raised to n): the sliver's area times that
    double v[3];
    for (int r = 0; r < 3; ++r) v[r] = s.G[3 * r] * mx + s.G[3 * r + 1] * my + s.G[3 * r + 2];
    const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    const double peak = which == 0 ? w_diffuse * std::fabs(km) / std::sqrt(vv) : s.ks * std::pow(std::fabs(km) / vv, s.n);
    const double sliver = (2.0 / 3.0) * gap * chord * peak;
    if (sliver > tol_area * std::fabs(T.area()) && gap > 1e-15 * chord && depth < MAX_DEPTH) {
        Tri t1, t2;
        bisect(T, t1, t2);
        integrate_smooth(s, t1, w_diffuse, tol_area, which, depth + 1, out);
        integrate_smooth(s, t2, w_diffuse, tol_area, which, depth + 1, out);
        return;
    }
    if (gap > 1e-15 * chord) out.bound += sliver;
    // lone side: (lone, r1, r2); the other: (r1, j, l) and (r1, l, r2), orientation kept
    integrate_smooth(s, {vx[lone], vy[lone], r1x, r1y, r2x, r2y}, w_diffuse, tol_area, which + 1, depth, out);
    integrate_smooth(s, {r1x, r1y, vx[j], vy[j], vx[l], vy[l]}, w_diffuse, tol_area, which + 1, depth, out);
    integrate_smooth(s, {r1x, r1y, vx[l], vy[l], r2x, r2y}, w_diffuse, tol_area, which + 1, depth, out);
}

// T integrated in coordinates whose origin is the whole-pixel corner below its first vertex
// (see shifted)
inline void integrate_triangle(const Shade& s, const Tri& T, double w_diffuse, double tol_area, Integral& out) {
    const double ox = std::floor(T.ax), oy = std::floor(T.ay);
    const Tri t{T.ax - ox, T.ay - oy, T.bx - ox, T.by - oy, T.cx - ox, T.cy - oy};
    integrate_smooth(shifted(s, ox, oy), t, w_diffuse, tol_area, 0, 0, out);
}

// A polygon xs, ys[start .. start + n) as the fan from its first vertex (signed triangles:
// exact for any simple outline, the shade being smooth on the whole plane of the pixel),
// in coordinates whose origin is the whole-pixel corner below its first vertex.
inline void integrate_polygon(const Shade& s, const double* xs, const double* ys, int64_t start, int64_t n,
                              double w_diffuse, double tol_area, Integral& out) {
    if (n < 3) return;
    const double ox = std::floor(xs[start]), oy = std::floor(ys[start]);
    const Shade l = shifted(s, ox, oy);
    for (int64_t i = 1; i + 1 < n; ++i) {
        const Tri T{xs[start] - ox, ys[start] - oy, xs[start + i] - ox, ys[start + i] - oy, xs[start + i + 1] - ox,
                    ys[start + i + 1] - oy};
        integrate_smooth(l, T, w_diffuse, tol_area, 0, 0, out);
    }
}

}  // namespace aaeval::shading
