// The simulator's parallel loops over particles (oneTBB), in fixed chunks so
// that sums come out the same for any thread count.
//
// Runtime dispatch: each chunk's loop is compiled twice, for the baseline
// x86-64 (SSE2) and, with everything it calls inlined into it, for AVX2 and
// FMA (the x86-64-v3 level, 2013 on); the second runs where the CPU has them
// (simdPath()). The same source and the same sums in the same order; FMA
// rounds a*b+c once, so the two paths' frames differ in the last bits (each
// path gives the same frames for any thread count). A Debian build is
// baseline x86-64, so without this the simulator's loops would never use the
// machine's vector units (measured: a step 5-15 % faster,
// docs/performance.md#simulator).
#pragma once

#include <cstddef>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace meniscus::sim {

inline constexpr std::size_t kParticleGrain = 512;

#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__)) && !defined(__AVX2__)
#define MENISCUS_SIM_AVX2_CLONES 1
#endif
// Whether the hand-written AVX2 loops (the neighbour build's eight-wide
// tests) exist in this build: with the clones, or a build for AVX2.
#if MENISCUS_SIM_AVX2_CLONES || (defined(__AVX2__) && defined(__FMA__))
#define MENISCUS_SIM_AVX2_LOOPS 1
#endif

enum class SimdPath { Baseline, Avx2Fma };
// The path the loops take: AVX2+FMA where the CPU has both (and the build is
// not already for them), unless MENISCUS_SIM_SIMD=baseline; setSimdPath
// overrides it (tests). simd.cpp.
SimdPath simdPath();
void setSimdPath(SimdPath path);
const char* simdPathName(SimdPath path);

template <class F>
void runBaseline(F& f, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) f(i);
}
#if MENISCUS_SIM_AVX2_CLONES
// flatten: f and all it calls are inlined here, so compiled for AVX2 and FMA
// (three-operand VEX forms, fused multiply-adds) and POPCNT, which every AVX2
// CPU has; a call that cannot be inlined stays baseline code, which is
// correct, only slower.
template <class F>
__attribute__((target("avx2,fma,popcnt"), flatten)) void runAvx2(F& f, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) f(i);
}
#endif

// f(i) for i in [b, e), on the active path.
template <class F>
void runRange(F& f, std::size_t b, std::size_t e) {
#if MENISCUS_SIM_AVX2_CLONES
    if (simdPath() == SimdPath::Avx2Fma) return runAvx2(f, b, e);
#endif
    runBaseline(f, b, e);
}

// The path as a type, for loops with a hand-written AVX2 form: f(i, path)
// picks it with if constexpr (path == SimdPath::Avx2Fma).
template <SimdPath P>
using OnPath = std::integral_constant<SimdPath, P>;

// f(i, OnPath<...>{}) for i in [b, e), on the active path.
template <class F>
void runRangeOnPath(F& f, std::size_t b, std::size_t e) {
    if (simdPath() == SimdPath::Avx2Fma) {
        auto wide = [&](std::size_t i) { f(i, OnPath<SimdPath::Avx2Fma>{}); };
#if MENISCUS_SIM_AVX2_CLONES
        return runAvx2(wide, b, e);
#else
        return runBaseline(wide, b, e);  // the build is for AVX2, or has no such path
#endif
    }
    auto narrow = [&](std::size_t i) { f(i, OnPath<SimdPath::Baseline>{}); };
    runBaseline(narrow, b, e);
}

template <class F>
void forAll(std::size_t n, F&& f) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kParticleGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) { runRange(f, r.begin(), r.end()); });
}

// Sum of f(i) over all particles, the same for any thread count.
template <class F>
double sumAll(std::size_t n, F&& f) {
    return tbb::parallel_deterministic_reduce(
        tbb::blocked_range<std::size_t>(0, n, kParticleGrain), 0.0,
        [&](const tbb::blocked_range<std::size_t>& r, double acc) {
            for (std::size_t i = r.begin(); i < r.end(); ++i) acc += double(f(i));
            return acc;
        },
        [](double a, double b) { return a + b; });
}

}  // namespace meniscus::sim
