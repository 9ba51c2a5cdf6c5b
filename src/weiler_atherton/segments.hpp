// Where two segments cross: the clipper's crossing points and the self-crossing check.
#pragma once

#include <cmath>

#include "shape.hpp"

namespace wa {

struct Crossing { bool hit; double x, y; };


// Where two segments cross strictly inside both (each end farther than eps from the
// other line); hit false otherwise.
inline Crossing proper_crossing(double p0x, double p0y, double p1x, double p1y, double q0x, double q0y, double q1x,
                         double q1y, double eps) {
    double dpx = p1x - p0x, dpy = p1y - p0y, dqx = q1x - q0x, dqy = q1y - q0y;
    double d0 = dpx * (q0y - p0y) - dpy * (q0x - p0x);
    double d1 = dpx * (q1y - p0y) - dpy * (q1x - p0x);
    if ((d0 >= 0.0 && d1 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0)) return {false, 0.0, 0.0};
    double e0 = dqx * (p0y - q0y) - dqy * (p0x - q0x);
    double e1 = dqx * (p1y - q0y) - dqy * (p1x - q0x);
    if ((e0 >= 0.0 && e1 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0)) return {false, 0.0, 0.0};
    double lp = std::hypot(dpx, dpy), lq = std::hypot(dqx, dqy);
    if (!((d0 > eps * lp && d1 < -eps * lp) || (d0 < -eps * lp && d1 > eps * lp))) return {false, 0.0, 0.0};
    if (!((e0 > eps * lq && e1 < -eps * lq) || (e0 < -eps * lq && e1 > eps * lq))) return {false, 0.0, 0.0};
    double tp = e0 / (e0 - e1), tq = d0 / (d0 - d1);
    // the point from the shorter parametrisation's nearer end (less rounding)
    if (pmin(tp, 1 - tp) * lp <= pmin(tq, 1 - tq) * lq) {
        if (tp <= 0.5) return {true, p0x + tp * dpx, p0y + tp * dpy};
        return {true, p1x - (1 - tp) * dpx, p1y - (1 - tp) * dpy};
    }
    if (tq <= 0.5) return {true, q0x + tq * dqx, q0y + tq * dqy};
    return {true, q1x - (1 - tq) * dqx, q1y - (1 - tq) * dqy};
}

}  // namespace wa
