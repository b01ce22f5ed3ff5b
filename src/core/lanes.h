// Four float lanes in GCC/Clang vector types (one SSE / NEON register: wider
// is slower on baseline x86-64), and the few helpers the vectorised loops of
// the CPU backend (cpu/filter_separable.h, cpu/splat.cpp) and of the core
// (core/anisotropy.cpp) share. Lanes are always summed in a fixed order by
// their users, so results do not depend on the thread count.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE__)
#include <xmmintrin.h>
#elif defined(__ARM_NEON) && defined(__aarch64__)
#include <arm_neon.h>
#endif

namespace meniscus::lanes {

inline constexpr int kLanes = 4;
using FloatV = float __attribute__((vector_size(4 * kLanes)));
using IntV = std::int32_t __attribute__((vector_size(4 * kLanes)));

inline FloatV loadV(const float* p) {
    FloatV v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
inline FloatV selectV(IntV mask, FloatV v) {  // v where mask is set, else +0
    IntV bits;
    std::memcpy(&bits, &v, sizeof v);
    bits &= mask;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}
// Lane-wise IEEE square root (correctly rounded, so equal to std::sqrt). A
// plain std::sqrt loop does not vectorise: it keeps the errno branch.
inline FloatV sqrtV(FloatV v) {
#if defined(__SSE__)
    __m128 m;
    std::memcpy(&m, &v, sizeof m);
    m = _mm_sqrt_ps(m);
    std::memcpy(&v, &m, sizeof v);
#elif defined(__ARM_NEON) && defined(__aarch64__)
    float32x4_t m;
    std::memcpy(&m, &v, sizeof m);
    m = vsqrtq_f32(m);
    std::memcpy(&v, &m, sizeof v);
#else
    for (int l = 0; l < kLanes; ++l) v[l] = std::sqrt(v[l]);
#endif
    return v;
}

}  // namespace meniscus::lanes
