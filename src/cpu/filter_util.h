// Small helpers shared by the smoothing filters (docs/pipeline.md#smoothing).
#pragma once

#include <algorithm>
#include <cmath>

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "shared/kernel_radius.h"

namespace meniscus::cpu {

// "No fluid" is +inf in every depth buffer.
inline bool isFluid(float z) { return z < INFINITY; }

// Kernel radius in whole pixels of a world length at eye depth z, shared with
// the GL shaders (src/shared/kernel_radius.h).
using shared::projectedRadiusPx;

// Runs fn(y) for every row y in [0, height) in parallel. Each row is written by
// exactly one task, so results do not depend on the thread count.
template <class Fn>
void forEachRow(int height, Fn&& fn) {
    tbb::parallel_for(tbb::blocked_range<int>(0, height, 4), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) fn(y);
    });
}

// Sizes a fresh output buffer of n elements (zero-filled), asking Linux for
// transparent huge pages first: a 1280x720 RGBA float image is 3,600 4-KiB
// page faults on first touch (several ms, all on the calling thread) but only
// a handful of 2-MiB ones. Only a hint; elsewhere a plain resize.
template <class T>
void resizeFresh(std::vector<T>& v, std::size_t n) {
    v.clear();
    v.reserve(n);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr std::uintptr_t kHuge = std::uintptr_t(2) << 20;
    const auto begin = reinterpret_cast<std::uintptr_t>(v.data());
    const std::uintptr_t lo = (begin + kHuge - 1) & ~(kHuge - 1), hi = (begin + n * sizeof(T)) & ~(kHuge - 1);
    if (hi > lo) madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
#endif
    v.resize(n);
}

}  // namespace meniscus::cpu
