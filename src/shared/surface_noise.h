// The surface-noise stage's formulas (docs/pipeline.md#noise-and-foam; the
// NVIDIA SSFR patent US 8,947,430, eqs. 14-17), written once for C++ and GLSL
// (src/shared/ is compiled by C++ and included by the GL shaders), so the CPU
// reference (src/cpu/surface_noise.cpp) and the GL twin
// (shaders/noise_splat.comp, noise_resolve.comp) compute every contribution
// with the same operations bit for bit (`precise` in GLSL: no FMA contraction
// or reassociation).
//
// Each particle near the surface splats a sprite of the patent's eq. 15,
//   I(x, y) = A_i  exp(-|s|^2 / (2 sigma^2))  fractalNoise3(f s, id)  exp(-(delta_i / falloff)^2),
// s the pixel's offset from the particle's projected centre in sprite radii
// (|s| < 1), id the particle's id, delta_i the depth of the particle's front
// (eye depth of its centre minus r) below the smoothed surface sampled at its
// projected centre (the patent's d), and A_i its turbulence factor. N(x, y) is
// the sum over particles (eq. 16). Sums are kept in fixed point
// (kNoiseFixedScale units, 32-bit wrap-around adds), so they are exact and do
// not depend on the order particles are visited in (GL atomics, CPU tiles).
#ifndef MENISCUS_SHARED_SURFACE_NOISE_H
#define MENISCUS_SHARED_SURFACE_NOISE_H

#include "noise.h"

#ifdef __cplusplus
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
namespace meniscus::shared {
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using ivec4 = glm::ivec4;
using std::abs;
using std::floor;
using std::max;
using std::min;
using std::sqrt;
#define MENISCUS_SN_INLINE inline
#define MENISCUS_SN_CONST inline constexpr
#define MENISCUS_SN_EXACT const
inline float snIntBitsToFloat(std::int32_t b) { return std::bit_cast<float>(b); }
inline std::int32_t snFloatBitsToInt(float f) { return std::bit_cast<std::int32_t>(f); }
// GLSL's clamp for finite x (glm::clamp compiles to branches, which stop
// GCC vectorising the CPU's loops).
inline float clamp(float x, float lo, float hi) { return std::min(std::max(x, lo), hi); }
#else
#define MENISCUS_SN_INLINE
#define MENISCUS_SN_CONST const
#define MENISCUS_SN_EXACT precise
#define snIntBitsToFloat intBitsToFloat
#define snFloatBitsToInt floatBitsToInt
#endif

// One unit of the fixed-point sums is 1 / kNoiseFixedScale: a contribution is
// rounded by at most 7.6e-6, and an int32 holds sums up to 32,768.
MENISCUS_SN_CONST float kNoiseFixedScale = 65536.0f;
// A contribution is clamped to +-kNoiseMaxFixed units (2^22, a noise of 64)
// before it is rounded (noiseRoundToInt's range), whatever the parameters.
MENISCUS_SN_CONST float kNoiseMaxFixed = 4194304.0f;
// Particles whose weight A_i exp(-(delta/falloff)^2) is below this are left
// out: deeper than 2 falloffs at A_i = 1, their sprite would change N by under
// 0.02, which neither the bumps nor the foam show (a lattice's second layer
// sits 2 radii down, weight e^-4: on frame 21, 17,200 sprites instead of
// 20,600 at a cut of 1e-3).
MENISCUS_SN_CONST float kNoiseMinWeight = 0.02f;
// Ids enter the noise as id mod kNoiseIdPeriod: its lattice coordinate stays
// an exact float through the octaves' frequencies.
MENISCUS_SN_CONST int kNoiseIdPeriod = 65536;

// x rounded to the nearest integer (ties to even) for |x| <= 2^22: adding
// 1.5 * 2^23 leaves the integer in the low bits of the sum's mantissa. Bit
// operations only, no float-to-int conversion or floor: the same in GLSL,
// and loops over it vectorise on the CPU.
MENISCUS_SN_INLINE int noiseRoundToInt(float x) {
    MENISCUS_SN_EXACT float t = x + 12582912.0f;
    return snFloatBitsToInt(t) - 0x4b400000;
}

// e^x for x <= 0 (Cephes expf: x = n ln2 + r, |r| <= ln2/2, degree-6
// polynomial, times 2^n built in the exponent bits): relative error < 2e-7,
// and the same bits in C++ and GLSL, which a library exp would not give.
// Arguments below -87 give e^-87.
MENISCUS_SN_INLINE float noiseExp(float xIn) {
    MENISCUS_SN_EXACT float x = clamp(xIn, -87.0f, 0.0f);  // (never NaN here)
    MENISCUS_SN_EXACT float t = x * 1.44269504088896341f;
    int k = noiseRoundToInt(t);
    MENISCUS_SN_EXACT float n = float(k);
    MENISCUS_SN_EXACT float r0 = x - n * 0.693359375f;
    MENISCUS_SN_EXACT float r = r0 - n * -2.12194440e-4f;
    MENISCUS_SN_EXACT float p0 = 1.9875691500e-4f;
    MENISCUS_SN_EXACT float p1 = p0 * r + 1.3981999507e-3f;
    MENISCUS_SN_EXACT float p2 = p1 * r + 8.3334519073e-3f;
    MENISCUS_SN_EXACT float p3 = p2 * r + 4.1665795894e-2f;
    MENISCUS_SN_EXACT float p4 = p3 * r + 1.6666665459e-1f;
    MENISCUS_SN_EXACT float p5 = p4 * r + 5.0000001201e-1f;
    MENISCUS_SN_EXACT float rr = r * r;
    MENISCUS_SN_EXACT float e = p5 * rr + r + 1.0f;
    MENISCUS_SN_EXACT float scale = snIntBitsToFloat((k + 127) << 23);
    MENISCUS_SN_EXACT float v = e * scale;
    return v;
}

// Where particle i's sprite lies on screen: its projected centre (pixels,
// column and row from the top-left corner), its radius in pixels, and the
// pixels whose centres lie within that radius' square, [x0, x1) x [y0, y1)
// clipped to the image. `c` is the view-space centre (eye depth -c.z, which
// must exceed 0), f the focal length in pixels.
struct NoiseSprite {
    vec2 centre;
    float radiusPx;
    ivec4 rect;  // x0, y0, x1, y1
};
MENISCUS_SN_INLINE NoiseSprite noiseSprite(vec3 c, float f, int W, int H, float spriteRadiusM) {
    MENISCUS_SN_EXACT float z = -c.z;
    MENISCUS_SN_EXACT float fz = f / z;
    MENISCUS_SN_EXACT float cx = 0.5f * float(W) + c.x * fz;
    MENISCUS_SN_EXACT float cy = 0.5f * float(H) - c.y * fz;  // +y view is up, rows go down
    MENISCUS_SN_EXACT float R = spriteRadiusM * fz;
    NoiseSprite s;
    s.centre = vec2(cx, cy);
    s.radiusPx = R;
    // Pixel i is inside when |i + 1/2 - centre| < R; clamped before the int
    // conversion so a sprite far off screen converts safely.
    MENISCUS_SN_EXACT float lx = floor(cx - R - 0.5f) + 1.0f;
    MENISCUS_SN_EXACT float hx = floor(cx + R - 0.5f) + 1.0f;
    MENISCUS_SN_EXACT float ly = floor(cy - R - 0.5f) + 1.0f;
    MENISCUS_SN_EXACT float hy = floor(cy + R - 0.5f) + 1.0f;
    s.rect = ivec4(int(clamp(lx, 0.0f, float(W))), int(clamp(ly, 0.0f, float(H))), int(clamp(hx, 0.0f, float(W))),
                   int(clamp(hy, 0.0f, float(H))));
    return s;
}

// Particle i's weight A_i exp(-(delta / falloff)^2): z its centre's eye depth,
// d the smoothed surface's eye depth at its projected centre (+inf: no fluid
// there, weight 0), r the particle radius, falloffM the depth scale (metres).
MENISCUS_SN_INLINE float noiseParticleWeight(float z, float d, float r, float falloffM, float amplitude) {
    if (!(d < 3.0e38f)) return 0.0f;
    MENISCUS_SN_EXACT float delta = ((z - r) - d) / falloffM;
    MENISCUS_SN_EXACT float w = amplitude * noiseExp(-(delta * delta));
    return w;
}

// The offset s of pixel (px, py) (its centre at px + 1/2, py + 1/2) from the
// sprite's centre, in sprite radii, y up; the sprite covers |s| < 1.
MENISCUS_SN_INLINE vec2 noiseSpriteOffset(NoiseSprite sp, int px, int py) {
    MENISCUS_SN_EXACT float sx = ((float(px) + 0.5f) - sp.centre.x) / sp.radiusPx;
    MENISCUS_SN_EXACT float sy = (sp.centre.y - (float(py) + 0.5f)) / sp.radiusPx;
    return vec2(sx, sy);
}

// The sprite's Gaussian exp(-|s|^2 / (2 sigma^2)) at |s|^2 = s2, sigma in sprite radii.
MENISCUS_SN_INLINE float noiseSpriteGaussian(float s2, float sigma) {
    MENISCUS_SN_EXACT float a = s2 / (2.0f * sigma * sigma);
    return noiseExp(-a);
}

// weight * gaussian * noise in fixed point, rounded to the nearest unit.
MENISCUS_SN_INLINE int noiseToFixed(float weight, float gaussian, float noise) {
    MENISCUS_SN_EXACT float v = weight * gaussian * noise * kNoiseFixedScale;
    MENISCUS_SN_EXACT float cl = clamp(v, -kNoiseMaxFixed, kNoiseMaxFixed);
    return noiseRoundToInt(cl);
}

// The fixed-point contribution of a sprite to pixel (px, py), 0 outside the
// sprite's disc: weight exp(-|s|^2 / (2 sigma^2)) fractalNoise3(frequency s, id).
// (The CPU runs the same pieces with the octaves outside its loop over a
// row of pixels: src/cpu/surface_noise.cpp, tested equal to this.)
MENISCUS_SN_INLINE int noiseContribution(NoiseSprite sp, int px, int py, float weight, float idz, float frequency,
                                         int octaves, float lacunarity, float gain, float sigma) {
    MENISCUS_SN_EXACT vec2 s = noiseSpriteOffset(sp, px, py);
    MENISCUS_SN_EXACT float s2 = s.x * s.x + s.y * s.y;
    if (!(s2 < 1.0f)) return 0;
    MENISCUS_SN_EXACT float g = noiseSpriteGaussian(s2, sigma);
    MENISCUS_SN_EXACT float n = fractalNoise3(vec3(s.x * frequency, s.y * frequency, idz), octaves, lacunarity, gain);
    return noiseToFixed(weight, g, n);
}

// The noise value of a fixed-point sum.
MENISCUS_SN_INLINE float noiseFromFixed(int sum) {
    MENISCUS_SN_EXACT float v = float(sum) / kNoiseFixedScale;
    return v;
}

// dN along one axis at a pixel from its neighbours' values nm (before) and
// np (after): central where both neighbours are the same surface (okm, okp:
// fluid, their depth within the normals' jump of this pixel's), one-sided
// where only one is, 0 where neither.
MENISCUS_SN_INLINE float noiseDerivative(float nm, float n0, float np, bool okm, bool okp) {
    MENISCUS_SN_EXACT float central = (np - nm) * 0.5f;
    MENISCUS_SN_EXACT float after = np - n0;
    MENISCUS_SN_EXACT float before = n0 - nm;
    return okm && okp ? central : (okp ? after : (okm ? before : 0.0f));
}

// The normal perturbed by the noise's gradient (the patent: "adding the
// partial derivatives of N(x, y) to the calculated normals"): N read as a
// height of bump sprite radii over the surface, so in view space n' =
// normalize(n - bump (dN/ds_x, dN/ds_y, 0)) with s in sprite radii (up
// positive); dNdx, dNdRow are per pixel (columns right, rows down) and
// spritePx the sprite radius in pixels at the pixel's depth.
MENISCUS_SN_INLINE vec3 noisePerturbedNormal(vec3 n, float dNdx, float dNdRow, float spritePx, float bump) {
    MENISCUS_SN_EXACT float gx = dNdx * spritePx;
    MENISCUS_SN_EXACT float gy = -(dNdRow * spritePx);
    if (gx == 0.0f && gy == 0.0f) return n;  // flat noise: the normal as it was, bit for bit
    MENISCUS_SN_EXACT vec3 m = vec3(n.x - bump * gx, n.y - bump * gy, n.z);
    MENISCUS_SN_EXACT float len2 = m.x * m.x + m.y * m.y + m.z * m.z;
    if (!(len2 > 0.0f)) return n;
    MENISCUS_SN_EXACT float inv = 1.0f / sqrt(len2);
    MENISCUS_SN_EXACT vec3 o = vec3(m.x * inv, m.y * inv, m.z * inv);
    return o;
}

// The foam cover of a pixel from |N| (the patent's grey-white tint by the
// noise's magnitude): 0 below threshold, rising by `gain` per unit of |N| to 1.
MENISCUS_SN_INLINE float noiseFoamCover(float noise, float threshold, float gain) {
    MENISCUS_SN_EXACT float a = (abs(noise) - threshold) * gain;
    return clamp(a, 0.0f, 1.0f);
}

// The shaded colour c under foam of cover `cover` (noiseFoamCover): foam is
// a diffuse grey-white layer, lit like the opaque materials (`ambient` of sky
// fill plus the key light's n.l), over the liquid's colour.
MENISCUS_SN_INLINE vec3 noiseWithFoam(vec3 c, float cover, float nl, vec3 foam, float ambient) {
    MENISCUS_SN_EXACT float lit = ambient + (1.0f - ambient) * max(nl, 0.0f);
    MENISCUS_SN_EXACT float keep = 1.0f - cover;
    MENISCUS_SN_EXACT float fl = lit * cover;
    MENISCUS_SN_EXACT vec3 o = vec3(c.x * keep + foam.x * fl, c.y * keep + foam.y * fl, c.z * keep + foam.z * fl);
    return o;
}

// noiseWithFoam with the foam's light given per colour, `lit` (with an HDR
// map: its ambient E(n) / pi plus the key light's share, environment.h and
// docs/pipeline.md#environment-map).
MENISCUS_SN_INLINE vec3 noiseWithFoamLit(vec3 c, float cover, vec3 lit, vec3 foam) {
    MENISCUS_SN_EXACT float keep = 1.0f - cover;
    MENISCUS_SN_EXACT vec3 fl = lit * cover;
    MENISCUS_SN_EXACT vec3 o =
        vec3(c.x * keep + foam.x * fl.x, c.y * keep + foam.y * fl.y, c.z * keep + foam.z * fl.z);
    return o;
}

#ifdef __cplusplus
// The noise's third coordinate of a particle (host side; both backends read
// it per particle): its id modulo kNoiseIdPeriod, as a float.
inline float noiseIdCoordinate(std::int64_t id) {
    constexpr std::int64_t period = kNoiseIdPeriod;
    return float(((id % period) + period) % period);
}
}  // namespace meniscus::shared
#endif
#undef MENISCUS_SN_INLINE
#undef MENISCUS_SN_CONST
#undef MENISCUS_SN_EXACT

#endif  // MENISCUS_SHARED_SURFACE_NOISE_H
