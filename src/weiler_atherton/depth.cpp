// Step c of the hidden-surface loop: depth comparison (depth.hpp).
#include "depth.hpp"

#include "solver.hpp"

namespace wa {

// Whether every vertex of the piece lies behind polygon src's plane by more than twice
// the tie band: then so does every point of it, and of every part clipped from it (their
// vertices lie in it, and depth differences are affine), which step c drops.
bool wholly_behind(const ShapeView& s, i64 source, i64 src, const double* planes, double eps_z) {
    double da = planes[3 * source] - planes[3 * src];
    double db = planes[3 * source + 1] - planes[3 * src + 1];
    double dc = planes[3 * source + 2] - planes[3 * src + 2];
    for (i64 i = 0; i < s.n; ++i)
        if (!(da * s.x[i] + db * s.y[i] + dc > 2.0 * eps_z)) return false;
    return true;
}

// FRONT, BEHIND or 0 (planes cross inside the piece) relative to polygon src.
int relation(const ShapeView& s, i64 source, i64 src, const double* planes, double eps_z) {
    double da = planes[3 * source] - planes[3 * src];
    double db = planes[3 * source + 1] - planes[3 * src + 1];
    double dc = planes[3 * source + 2] - planes[3 * src + 2];
    bool front = false, behind = false;
    for (i64 i = 0; i < s.n; ++i) {
        double d = da * s.x[i] + db * s.y[i] + dc;
        if (d < -eps_z) front = true;
        else if (d > eps_z) behind = true;
    }
    if (front && behind) return 0;
    if (front) return FRONT;
    if (behind) return BEHIND;
    return source > src ? FRONT : BEHIND;  // one plane: later in file in front
}

}  // namespace wa
