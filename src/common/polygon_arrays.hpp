// The one check of a scene's polygon arrays, made by every binding that takes them (catmull,
// shading, samplers; Weiler-Atherton's originals, whose vertices come as (N, 3) rows, by its
// record rule) before a kernel runs, so that every family accepts the same scenes.
#pragma once

#include <cstdint>
#include <string>

#include "common/arrays.hpp"
#include "common/polygons.hpp"

namespace aaeval::arrays {

// Coordinates and depth planes beyond this are refused: the kernels multiply two of them
// (cross products, plane depths) and the products must stay finite.
inline constexpr double MAX_MAGNITUDE = 1e100;

// Refuses unless every polygon's record (start[p], length[p]) is at least one vertex of the
// nv vertices.
inline void check_records(const char* who, const int64_t* start, const int64_t* length, int64_t n, int64_t nv) {
    for (int64_t p = 0; p < n; ++p)
        if (start[p] < 0 || length[p] < 1 || start[p] > nv || length[p] > nv - start[p])
            refuse(who, "polygon " + std::to_string(p) + " (start " + std::to_string(start[p]) + ", length " +
                            std::to_string(length[p]) + "): its vertex range is not inside the " + std::to_string(nv) +
                            " vertices");
}

// The polygons after checking: int64 start and length (n,), float64 x and y (nv,), planes
// (n, 3), all C order; every polygon at least one vertex inside the vertex arrays; every
// coordinate and plane finite and at most MAX_MAGNITUDE in magnitude. `who` prefixes the
// message (the module's name, or empty).
template <class A>
Polygons checked_polygons(const char* who, A& start, A& length, A& x, A& y, A& planes) {
    Polygons P;
    P.start = checked<const int64_t>(who, start, "start", 1, {-1});
    P.n = int64_t(start.shape(0));
    P.length = checked<const int64_t>(who, length, "length", 1, {P.n});
    P.x = checked<const double>(who, x, "x", 1, {-1});
    const int64_t nv = int64_t(x.shape(0));
    P.y = checked<const double>(who, y, "y", 1, {nv});
    P.planes = checked<const double>(who, planes, "planes", 2, {P.n, 3});
    check_records(who, P.start, P.length, P.n, nv);
    check_finite(who, P.x, size_t(nv), "x", MAX_MAGNITUDE, "1e100");
    check_finite(who, P.y, size_t(nv), "y", MAX_MAGNITUDE, "1e100");
    check_finite(who, P.planes, size_t(3 * P.n), "planes", MAX_MAGNITUDE, "1e100");
    return P;
}

}  // namespace aaeval::arrays
