// The kernel radius of a world-space length seen at a given eye depth, written
// once for C++ and GLSL (src/shared/ is compiled by C++ and included by the GL
// shaders): the filters size their kernels with it on both backends
// (src/cpu/filter_util.h, shaders/filter_narrow_range.glsl). In GLSL the
// division is `precise`, matching the CPU's IEEE arithmetic.
#ifndef MENISCUS_SHARED_KERNEL_RADIUS_H
#define MENISCUS_SHARED_KERNEL_RADIUS_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
namespace meniscus::shared {
using std::ceil;
using std::min;
#define MENISCUS_RADIUS_INLINE inline
#define MENISCUS_RADIUS_EXACT const
#else
#define MENISCUS_RADIUS_INLINE
#define MENISCUS_RADIUS_EXACT precise
#endif

// Kernel radius in whole pixels for a world length worldM (metres) projected
// at eye depth z with focal length focalPx: ceil(worldM * focalPx / z) in
// [0, maxPx] (0 for a NaN or non-positive size, maxPx for +inf).
MENISCUS_RADIUS_INLINE int projectedRadiusPx(float worldM, float focalPx, float z, int maxPx) {
    MENISCUS_RADIUS_EXACT float px = worldM * focalPx / z;
    if (!(px > 0.0f)) return 0;
    return int(min(ceil(px), float(maxPx)));
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_RADIUS_INLINE
#undef MENISCUS_RADIUS_EXACT

#endif  // MENISCUS_SHARED_KERNEL_RADIUS_H
