// What the shading binding runs once its inputs are checked (module.cpp): the Catmull kernel
// (src/catmull: strips, sweep, pixel integrator) unchanged, over bands of rows on the thread
// pool, with ShadeSink (sink.hpp) as its sink.
#pragma once

#include <cstdint>

#include "catmull/bands.hpp"
#include "catmull/sweep.hpp"
#include "shading/sink.hpp"

namespace aaeval::shading {

// The box-filtered Phong image of the polygons with materials M into the images `out`
// (zeroed), each pixel with its error bound and its count of shade evaluations.
inline void render_exact(catmull::SortedPolygons& P, const Material& M, double eps_z, int64_t width, int64_t height,
                         int64_t threads, Images out) {
    catmull::sort_polygons(P);
    catmull::run_bands(height, threads, [&](int64_t, int64_t r0, int64_t r1) {
        ShadeSink sink(M, out);
        catmull::scan_rows(P, width, r0, r1, eps_z, false, true, sink);
    });
}

}  // namespace aaeval::shading
