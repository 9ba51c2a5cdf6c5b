// The scene format's one depth rule (docs/scene_format.md, "Near ties";
// aaeval/scenes/depth.py): at a point, every polygon within eps of the smallest depth is
// tied with the nearest, and of the tied ones the one listed latest is visible.
#pragma once

#include <algorithm>
#include <cstdint>

namespace aaeval::samplers {

// Whether a polygon at depth z, listed after every polygon seen so far at this point, is
// visible; the caller keeps min(nearest, z) as the nearest depth (the band is relative to
// the minimum and must not drift towards the back).
inline bool nearer_or_tied(double z, double nearest, double eps) { return z <= nearest + eps; }

// Reorders order[0..n) (positions sorted front to back on depth) so that each run of
// positions within eps of the run's first depth lists the latest index first. Runs are
// taken from the front: a run ends at the first depth more than eps behind its first.
// Short runs are sorted by insertion, long ones by a stable merge sort on the same key:
// the same permutation (both are stable), without the quadratic cost on deep stacks.
inline void tied_latest_first(int64_t* order, int64_t n, const double* depth, const int64_t* index, double eps) {
    int64_t a = 0;
    while (a < n) {
        int64_t b = a + 1;
        while (b < n && depth[order[b]] <= depth[order[a]] + eps) ++b;
        if (b - a > 16) {
            std::stable_sort(order + a, order + b, [index](int64_t x, int64_t y) { return index[x] > index[y]; });
        } else {
            for (int64_t i = a + 1; i < b; ++i) {
                int64_t item = order[i];
                int64_t j = i - 1;
                while (j >= a && index[order[j]] < index[item]) {
                    order[j + 1] = order[j];
                    --j;
                }
                order[j + 1] = item;
            }
        }
        a = b;
    }
}

}  // namespace aaeval::samplers
