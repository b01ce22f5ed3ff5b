// (x, y, z, 0) copies of per-particle vectors for the pressure solvers'
// neighbour loops. With SSE2 (every x86-64) a neighbour's position or
// velocity is then one 16-byte load and one vector operation instead of three
// of each: those loops are bound by instructions, not memory (halving the
// list entries to 8 bytes did not speed them). Without SSE2 the same
// arithmetic runs lane by lane, in the same order.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <glm/glm.hpp>

#include "sim/parallel.h"

namespace meniscus::sim {

// In parallel: serial, the five copies of a DFSPH step held the other threads
// idle for about 1 % of it.
inline void pack(std::span<const glm::vec3> in, std::vector<glm::vec4>& out) {
    out.resize(in.size());
    forAll(in.size(), [&](std::size_t i) { out[i] = glm::vec4(in[i], 0.0f); });
}
inline void unpack(const std::vector<glm::vec4>& in, std::span<glm::vec3> out) {
    forAll(out.size(), [&](std::size_t i) { out[i] = glm::vec3(in[i]); });
}

// Four floats in a register (or, without SSE2, in a glm::vec4).
#if defined(__SSE2__)
struct F4 {
    __m128 m;
};
inline F4 load4(const glm::vec4& p) { return {_mm_loadu_ps(&p.x)}; }
inline void store4(glm::vec4& p, F4 a) { _mm_storeu_ps(&p.x, a.m); }
inline F4 splat(float s) { return {_mm_set1_ps(s)}; }
inline F4 zero4() { return {_mm_setzero_ps()}; }
inline F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.m, b.m)}; }
inline F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.m, b.m)}; }
inline F4 operator*(F4 a, F4 b) { return {_mm_mul_ps(a.m, b.m)}; }
inline F4 load4(const float* p) { return {_mm_loadu_ps(p)}; }
inline void store4(float* p, F4 a) { _mm_storeu_ps(p, a.m); }
// (a, b, c, d) in lanes 0..3, from registers (not through memory, whose
// four small stores and one wide load would stall on store forwarding).
inline F4 set4(float a, float b, float c, float d) { return {_mm_setr_ps(a, b, c, d)}; }
inline F4 operator/(F4 a, F4 b) { return {_mm_div_ps(a.m, b.m)}; }
inline F4 sqrt4(F4 a) { return {_mm_sqrt_ps(a.m)}; }
// Lane masks (all bits set where true) and a choice by one.
inline F4 less(F4 a, F4 b) { return {_mm_cmplt_ps(a.m, b.m)}; }
inline F4 lessEq(F4 a, F4 b) { return {_mm_cmple_ps(a.m, b.m)}; }
inline F4 both(F4 m1, F4 m2) { return {_mm_and_ps(m1.m, m2.m)}; }
inline F4 select(F4 mask, F4 a, F4 b) { return {_mm_or_ps(_mm_and_ps(mask.m, a.m), _mm_andnot_ps(mask.m, b.m))}; }
// ((a0 + a1) + a2) + a3.
inline float sum4(F4 a) {
    alignas(16) float v[4];
    _mm_store_ps(v, a.m);
    return ((v[0] + v[1]) + v[2]) + v[3];
}
#else
struct F4 {
    glm::vec4 m;
};
inline F4 load4(const glm::vec4& p) { return {p}; }
inline void store4(glm::vec4& p, F4 a) { p = a.m; }
inline F4 splat(float s) { return {glm::vec4(s)}; }
inline F4 zero4() { return {glm::vec4(0.0f)}; }
inline F4 operator+(F4 a, F4 b) { return {a.m + b.m}; }
inline F4 operator-(F4 a, F4 b) { return {a.m - b.m}; }
inline F4 operator*(F4 a, F4 b) { return {a.m * b.m}; }
inline F4 load4(const float* p) { return {glm::vec4(p[0], p[1], p[2], p[3])}; }
inline void store4(float* p, F4 a) {
    for (int l = 0; l < 4; ++l) p[l] = a.m[l];
}
inline F4 set4(float a, float b, float c, float d) { return {glm::vec4(a, b, c, d)}; }
inline F4 operator/(F4 a, F4 b) { return {a.m / b.m}; }
inline F4 sqrt4(F4 a) { return {glm::sqrt(a.m)}; }
// Lane masks (1 where true) and a choice by one.
inline F4 less(F4 a, F4 b) { return {glm::vec4(glm::lessThan(a.m, b.m))}; }
inline F4 lessEq(F4 a, F4 b) { return {glm::vec4(glm::lessThanEqual(a.m, b.m))}; }
inline F4 both(F4 m1, F4 m2) { return {m1.m * m2.m}; }
inline F4 select(F4 mask, F4 a, F4 b) {
    F4 out;
    for (int l = 0; l < 4; ++l) out.m[l] = mask.m[l] != 0.0f ? a.m[l] : b.m[l];
    return out;
}
inline float sum4(F4 a) { return ((a.m[0] + a.m[1]) + a.m[2]) + a.m[3]; }
#endif
inline F4 load4(const glm::vec3& p) { return load4(glm::vec4(p, 0.0f)); }

// Two dot products at once: a.b and c.d, each summed (a0 b0 + a2 b2) +
// (a1 b1 + a3 b3).
inline void dot2(F4 a, F4 b, F4 c, F4 d, float& ab, float& cd) {
#if defined(__SSE2__)
    const __m128 p = _mm_mul_ps(a.m, b.m), q = _mm_mul_ps(c.m, d.m);
    const __m128 t = _mm_add_ps(_mm_unpacklo_ps(p, q), _mm_unpackhi_ps(p, q));  // p0+p2, q0+q2, p1+p3, q1+q3
    const __m128 u = _mm_add_ps(t, _mm_movehl_ps(t, t));
    ab = _mm_cvtss_f32(u);
    cd = _mm_cvtss_f32(_mm_shuffle_ps(u, u, 1));
#else
    const glm::vec4 p = a.m * b.m, q = c.m * d.m;
    ab = (p[0] + p[2]) + (p[1] + p[3]);
    cd = (q[0] + q[2]) + (q[1] + q[3]);
#endif
}
inline glm::vec3 toVec3(F4 a) {
    glm::vec4 p;
    store4(p, a);
    return glm::vec3(p);
}

// Sum of term(e) over the entries e of a list, in two interleaved partial
// sums (even and odd entries) added at the end: one running sum would make
// each add wait for the last (a 4-cycle chain per neighbour).
template <class List, class Term>
F4 sumPairs(const List& list, const Term& term) {
    F4 even = zero4(), odd = zero4();
    const std::size_t n = list.size();
    std::size_t q = 0;
    for (; q + 1 < n; q += 2) {
        even = even + term(list[q]);
        odd = odd + term(list[q + 1]);
    }
    if (q < n) even = even + term(list[q]);
    return even + odd;
}

}  // namespace meniscus::sim
