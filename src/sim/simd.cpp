// Which of the loops' two compilations runs (parallel.h).
#include <atomic>
#include <cstdlib>
#include <cstring>

#include "meniscus/sim.h"
#include "sim/parallel.h"

namespace meniscus::sim {

namespace {

#if MENISCUS_SIM_AVX2_CLONES
bool hasAvx2Fma() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("popcnt");
}
#endif

SimdPath detect() {
#if MENISCUS_SIM_AVX2_CLONES
    const char* env = std::getenv("MENISCUS_SIM_SIMD");
    if (env && std::strcmp(env, "baseline") == 0) return SimdPath::Baseline;
    if (hasAvx2Fma()) return SimdPath::Avx2Fma;
    return SimdPath::Baseline;
#elif defined(__AVX2__) && defined(__FMA__)
    return SimdPath::Avx2Fma;  // the whole build is for them (-march)
#else
    return SimdPath::Baseline;
#endif
}

std::atomic<int>& chosen() {
    static std::atomic<int> path{int(detect())};
    return path;
}

}  // namespace

SimdPath simdPath() { return SimdPath(chosen().load(std::memory_order_relaxed)); }

void setSimdPath(SimdPath path) {
#if MENISCUS_SIM_AVX2_CLONES
    if (path == SimdPath::Avx2Fma && !(hasAvx2Fma())) return;
    chosen().store(int(path), std::memory_order_relaxed);
#else
    (void)path;  // one compilation only
#endif
}

const char* simdPathName(SimdPath path) { return path == SimdPath::Avx2Fma ? "avx2+fma" : "baseline (sse2)"; }

const char* vectorPath() { return simdPathName(simdPath()); }

}  // namespace meniscus::sim
