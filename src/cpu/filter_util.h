// Small helpers shared by the smoothing filters (SPEC §3.5).
#pragma once

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace meniscus::cpu {

// "No fluid" is +inf in every depth buffer.
inline bool isFluid(float z) { return z < INFINITY; }

// Kernel radius in whole pixels for a world-space length projected at eye
// depth z with focal length f (pixels): ceil(worldM * f / z), in [0, maxPx].
inline int projectedRadiusPx(float worldM, float focalPx, float z, int maxPx) {
    const float px = worldM * focalPx / z;
    if (!(px > 0.0f)) return 0;
    return std::min(maxPx, int(std::ceil(px)));
}

// Runs fn(y) for every row y in [0, height) in parallel. Each row is written by
// exactly one task, so results do not depend on the thread count.
template <class Fn>
void forEachRow(int height, Fn&& fn) {
    tbb::parallel_for(tbb::blocked_range<int>(0, height, 4), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) fn(y);
    });
}

}  // namespace meniscus::cpu
