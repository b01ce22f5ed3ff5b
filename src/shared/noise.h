// Gradient noise for the surface-noise stage (the NVIDIA SSFR patent's eqs.
// 14-17, docs/pipeline.md#noise-and-foam), written once for C++ and GLSL
// (src/shared/ is compiled by C++ and included by the GL shaders), so the CPU
// reference and the GL twin draw the same pattern bit for bit: every
// intermediate is `precise` in GLSL (no FMA contraction or reassociation),
// matching the CPU's plain IEEE float arithmetic.
//
// noise3 is Perlin's improved noise (K. Perlin, "Improving Noise", SIGGRAPH
// 2002): the quintic fade 6t^5 - 15t^4 + 10t^3 and his twelve edge gradients
// (sixteen cases, four repeated), but the gradient of a lattice point is chosen
// by the pcg3d hash of its integer coordinates (M. Jarzynski and M. Olano,
// "Hash Functions for GPU Rendering", JCGT 9(3), 2020) instead of a
// permutation table: no table to keep in step between C++ and GLSL, no period
// of 256 (the third coordinate is a particle id, and ids go far beyond 256),
// and unsigned arithmetic wraps the same way in both languages.
// fractalNoise3 sums octaves of it (the patent's "fractal Perlin noise").
#ifndef MENISCUS_SHARED_NOISE_H
#define MENISCUS_SHARED_NOISE_H

#ifdef __cplusplus
#include <bit>
#include <cstdint>
#include <glm/glm.hpp>
namespace meniscus::shared {
using uint = std::uint32_t;
using vec3 = glm::vec3;
using ivec3 = glm::ivec3;
using uvec3 = glm::uvec3;
// floor for |x| < 2^30 (noise3's range), exact, without the libm call a
// baseline x86-64 build makes for std::floor (no SSE4.1 round).
inline float noiseFloorF(float x) {
    const float t = float(int(x));
    return t > x ? t - 1.0f : t;
}
inline vec3 noiseFloor(vec3 p) { return vec3(noiseFloorF(p.x), noiseFloorF(p.y), noiseFloorF(p.z)); }
// Bit-exact selects and sign flips without branches (the gradient's choice is
// random per lattice point, so branches would mispredict half the time).
inline float noiseSelect(bool c, float a, float b) {
    const uint m = c ? ~0u : 0u;
    return std::bit_cast<float>((std::bit_cast<uint>(a) & m) | (std::bit_cast<uint>(b) & ~m));
}
inline float noiseFlipSign(float a, uint bit) { return std::bit_cast<float>(std::bit_cast<uint>(a) ^ (bit << 31u)); }
#define MENISCUS_NOISE_INLINE inline
#define MENISCUS_NOISE_EXACT const  // C++: plain IEEE float arithmetic already
#define MENISCUS_NOISE_EXACT_VAR
#else
// GLSL has a built-in noise3 (genType -> vec3, deprecated): a float noise3(vec3)
// is an overload differing in return type only, which glslang rejects (Mesa
// lets it hide the built-in). GLSL calls it by this name, unchanged in C++.
#define noise3 meniscusNoise3
#define MENISCUS_NOISE_INLINE
#define MENISCUS_NOISE_EXACT precise
#define MENISCUS_NOISE_EXACT_VAR precise
#define noiseFloor floor
#define noiseFloorF floor
float noiseSelect(bool c, float a, float b) { return uintBitsToFloat((floatBitsToUint(a) & (c ? ~0u : 0u)) | (floatBitsToUint(b) & (c ? 0u : ~0u))); }
float noiseFlipSign(float a, uint bit) { return uintBitsToFloat(floatBitsToUint(a) ^ (bit << 31u)); }
#endif

// pcg3d (Jarzynski & Olano 2020): three well-mixed 32-bit words from three.
MENISCUS_NOISE_INLINE uvec3 noiseHash3(uvec3 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v = v ^ (v >> 16u);
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    return v;
}

// Perlin's grad(): the dot product of (x, y, z) with one of his twelve edge
// directions (1, 1, 0) ... (0, -1, -1), picked by the low four bits of h.
MENISCUS_NOISE_INLINE float noiseGradient(uint h, float x, float y, float z) {
    uint c = h & 15u;
    float u = noiseSelect(c < 8u, x, y);
    float v = noiseSelect(c < 4u, y, noiseSelect(c == 12u || c == 14u, x, z));
    MENISCUS_NOISE_EXACT float su = noiseFlipSign(u, c & 1u);
    MENISCUS_NOISE_EXACT float sv = noiseFlipSign(v, (c >> 1u) & 1u);
    MENISCUS_NOISE_EXACT float g = su + sv;
    return g;
}

MENISCUS_NOISE_INLINE float noiseCornerValue(ivec3 cell, ivec3 corner, vec3 f) {
    uint h = noiseHash3(uvec3(cell + corner)).x;
    MENISCUS_NOISE_EXACT float dx = f.x - float(corner.x);
    MENISCUS_NOISE_EXACT float dy = f.y - float(corner.y);
    MENISCUS_NOISE_EXACT float dz = f.z - float(corner.z);
    return noiseGradient(h >> 28u, dx, dy, dz);  // the hash's best-mixed bits
}

// 6t^5 - 15t^4 + 10t^3, Horner's form.
MENISCUS_NOISE_INLINE float noiseFade(float t) {
    MENISCUS_NOISE_EXACT float a = t * 6.0f - 15.0f;
    MENISCUS_NOISE_EXACT float b = t * a + 10.0f;
    MENISCUS_NOISE_EXACT float c = t * t * t * b;
    return c;
}

// a + t (b - a), written out (GLSL's mix may be evaluated another way).
MENISCUS_NOISE_INLINE float noiseLerp(float a, float b, float t) {
    MENISCUS_NOISE_EXACT float d = b - a;
    MENISCUS_NOISE_EXACT float r = a + t * d;
    return r;
}

// Improved noise at p: 0 at every lattice point, |noise3| <= 1.04 or so,
// continuous with continuous first and second derivatives. Each coordinate
// must lie within +-2^30 (its lattice cell is an int; a caller maps particle
// ids into that range, e.g. modulo 2^20).
MENISCUS_NOISE_INLINE float noise3(vec3 p) {
    vec3 cellF = noiseFloor(p);
    ivec3 cell = ivec3(cellF);
    MENISCUS_NOISE_EXACT vec3 f = p - cellF;
    MENISCUS_NOISE_EXACT float u = noiseFade(f.x);
    MENISCUS_NOISE_EXACT float v = noiseFade(f.y);
    MENISCUS_NOISE_EXACT float w = noiseFade(f.z);
    MENISCUS_NOISE_EXACT float x00 = noiseLerp(noiseCornerValue(cell, ivec3(0, 0, 0), f), noiseCornerValue(cell, ivec3(1, 0, 0), f), u);
    MENISCUS_NOISE_EXACT float x10 = noiseLerp(noiseCornerValue(cell, ivec3(0, 1, 0), f), noiseCornerValue(cell, ivec3(1, 1, 0), f), u);
    MENISCUS_NOISE_EXACT float x01 = noiseLerp(noiseCornerValue(cell, ivec3(0, 0, 1), f), noiseCornerValue(cell, ivec3(1, 0, 1), f), u);
    MENISCUS_NOISE_EXACT float x11 = noiseLerp(noiseCornerValue(cell, ivec3(0, 1, 1), f), noiseCornerValue(cell, ivec3(1, 1, 1), f), u);
    MENISCUS_NOISE_EXACT float y0 = noiseLerp(x00, x10, v);
    MENISCUS_NOISE_EXACT float y1 = noiseLerp(x01, x11, v);
    return noiseLerp(y0, y1, w);
}

// Fractal sum of `octaves` octaves: octave k at frequency lacunarity^k and
// amplitude gain^k, divided by the sum of the amplitudes, so the result stays
// within noise3's range. Each octave is shifted by a fixed offset so that the
// lattice points of one (where it is 0) are not those of the next.
// Octave k's term of fractalNoise3 at frequency and amplitude (lacunarity^k,
// gain^k as the loop below multiplies them up). Separate so that a caller can
// run the octaves outside a loop over points (the CPU's vectorised sprites)
// and still add the same terms in the same order.
MENISCUS_NOISE_INLINE float fractalNoiseTerm(vec3 p, int k, float frequency, float amplitude) {
    MENISCUS_NOISE_EXACT float shift = 0.37f * float(k);
    MENISCUS_NOISE_EXACT vec3 q = vec3(p.x * frequency + shift, p.y * frequency + shift, p.z * frequency + shift);
    MENISCUS_NOISE_EXACT float t = amplitude * noise3(q);
    return t;
}

MENISCUS_NOISE_INLINE float fractalNoise3(vec3 p, int octaves, float lacunarity, float gain) {
    MENISCUS_NOISE_EXACT_VAR float sum = 0.0f;
    MENISCUS_NOISE_EXACT_VAR float norm = 0.0f;
    MENISCUS_NOISE_EXACT_VAR float amplitude = 1.0f;
    MENISCUS_NOISE_EXACT_VAR float frequency = 1.0f;
    for (int k = 0; k < octaves; ++k) {
        sum = sum + fractalNoiseTerm(p, k, frequency, amplitude);
        norm = norm + amplitude;
        amplitude = amplitude * gain;
        frequency = frequency * lacunarity;
    }
    return norm > 0.0f ? sum / norm : 0.0f;
}

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_NOISE_INLINE
#undef MENISCUS_NOISE_EXACT
#undef MENISCUS_NOISE_EXACT_VAR

#endif  // MENISCUS_SHARED_NOISE_H
