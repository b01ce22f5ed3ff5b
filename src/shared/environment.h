// The HDR environment map (docs/pipeline.md#environment-map), written once for
// C++ and GLSL like sky.h: the sampling of an equirectangular (latitude-
// longitude) linear RGB map along a world-space direction, which replaces the
// procedural sky where one is given.
//
// Convention (+y up, right-handed): for the unit direction (x, y, z)
//   u = atan2(x, -z) / (2 pi) + 0.5 - rotation   (turns; wrapped to [0, 1))
//   v = acos(y) / pi = atan2(sqrt(x^2 + z^2), y) / pi   (0 the zenith, 1 the nadir)
// so the map's centre column (u = 0.5) looks along -z (the default camera's
// view), its top row is straight up, and texel (i, j) of a W x H map has its
// centre at u = (i + 0.5) / W, v = (j + 0.5) / H. `rotation` turns the picture
// about +y: what a direction of angle atan2(x, -z) = phi showed, the direction
// of phi + 2 pi rotation shows after it (seen from above, from -z toward +x).
// Bilinear between the four nearest texel centres (bilinear.h's mix),
// wrapping in u (the seam at u = 0 joins the first and last columns) and
// clamped in v (the poles).
//
// With a map the diffuse ambient light comes from it too: the irradiance
// E(n) of the map (the cosine-weighted integral of its radiance over the
// hemisphere around n) as 9 spherical-harmonic coefficients per colour,
// Ramamoorthi & Hanrahan 2001, "An Efficient Representation for Irradiance
// Environment Maps" (SIGGRAPH 2001): the map projected once on the real
// spherical harmonics Y_lm of bands l <= 2 (environmentShBasis below),
// L_lm = sum over texels of L Y_lm(d) dw, dw the texel's solid angle (the
// integral of sin(theta) dtheta dphi over it), then convolved with the clamped
// cosine, whose band factors are A0 = pi, A1 = 2 pi / 3, A2 = pi / 4, so
//   E(n) = sum_lm A_l L_lm Y_lm(n)      (their eq. 7 and 12),
// accurate to a few percent for any map (the cosine lobe has little energy
// above band 2). The host projects (environmentIrradianceSh, C++ only, in
// environment.cpp) with the rotation and the intensity applied, and stores
// A_l L_lm in EnvironmentMap::irradiance; both backends evaluate
// environmentIrradiance. A Lambertian surface of albedo a then reflects
// a E(n) / pi of it (environmentAmbient), in place of the studio's constant
// ambient when no map is given.
//
// Texel reads differ between the languages: C++ reads EnvironmentMap::texels,
// GLSL the storage buffer `environmentTexels` that a shader including this
// header declares first (a GLSL function cannot take a pointer). Both are
// RGB floats, row after row from the top, 3 W H of them.
// atan2 and acos are not those of the C library or of the GL driver (which
// differ in their last bits and do not vectorise): environmentAtan2 below is
// one polynomial, evaluated in the same order on both backends, `precise` in
// GLSL, so both sample the same texel weights to rounding.
#ifndef MENISCUS_SHARED_ENVIRONMENT_H
#define MENISCUS_SHARED_ENVIRONMENT_H

#include "bilinear.h"  // bilinearMix
#include "sky.h"       // groundShare

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
namespace meniscus::shared {
using vec3 = glm::vec3;
using std::abs;
using std::floor;
using std::max;
using std::min;
using std::sqrt;
// The map as the stages see it: the texels (null: no map, the procedural sky),
// its size, the rotation in turns and the intensity multiplier.
struct EnvironmentMap {
    const float* texels = nullptr;
    int width = 0, height = 0;
    float rotation = 0.0f;   // turns about +y (degrees / 360)
    float intensity = 1.0f;  // multiplies every texel
    // The irradiance's coefficients A_l L_lm (environmentShBasis' order), of
    // the map as seen (rotated, times the intensity): environmentIrradianceSh.
    glm::vec3 irradiance[9] = {};
    bool enabled() const { return texels != nullptr && width > 0 && height > 0; }
};
#define MENISCUS_ENV_INLINE inline
#define MENISCUS_ENV_EXACT const
#define MENISCUS_ENV_TEXEL(env, i) (env).texels[i]
#else
// GLSL: the same fields without the pointer (the texels are the includer's
// `environmentTexels` buffer).
struct EnvironmentMap {
    int width, height;
    float rotation, intensity;
    vec3 irradiance[9];
};
#define MENISCUS_ENV_INLINE
#define MENISCUS_ENV_EXACT precise
#define MENISCUS_ENV_TEXEL(env, i) environmentTexels[i]
#endif

#define MENISCUS_ENV_PI 3.14159265358979f

// atan2(y, x) in radians, (-pi, pi], branch-free: the octant reduced to
// t = min/max in [0, 1], atan(t) by the odd degree-11 minimax polynomial of
// Abramowitz & Stegun 4.4.49's kind (max error about 1e-5 rad, far below a
// texel of any map this reads), then the octant restored. atan2(0, 0) = 0.
MENISCUS_ENV_INLINE float environmentAtan2(float y, float x) {
    MENISCUS_ENV_EXACT float ax = abs(x);
    MENISCUS_ENV_EXACT float ay = abs(y);
    MENISCUS_ENV_EXACT float hi = max(ax, ay);
    MENISCUS_ENV_EXACT float lo = min(ax, ay);
    MENISCUS_ENV_EXACT float t = hi > 0.0f ? lo / hi : 0.0f;
    MENISCUS_ENV_EXACT float s = t * t;
    MENISCUS_ENV_EXACT float p =
        ((((-0.0117212f * s + 0.05265332f) * s - 0.11643287f) * s + 0.19354346f) * s - 0.33262347f) * s + 0.99997726f;
    MENISCUS_ENV_EXACT float r0 = p * t;
    MENISCUS_ENV_EXACT float r1 = ay > ax ? 0.5f * MENISCUS_ENV_PI - r0 : r0;
    MENISCUS_ENV_EXACT float r2 = x < 0.0f ? MENISCUS_ENV_PI - r1 : r1;
    return y < 0.0f ? -r2 : r2;
}

// The map's (u, v) of a world direction (need not be unit; zero: the zenith),
// u not yet wrapped. See the convention above.
MENISCUS_ENV_INLINE float environmentU(float dx, float dz, float rotation) {
    return environmentAtan2(dx, -dz) * (0.5f / MENISCUS_ENV_PI) + 0.5f - rotation;
}
MENISCUS_ENV_INLINE float environmentV(float dx, float dy, float dz) {
    MENISCUS_ENV_EXACT float r = sqrt(dx * dx + dz * dz);
    return environmentAtan2(r, dy) * (1.0f / MENISCUS_ENV_PI);
}

// The texel (i, j) of the map, i already wrapped and j clamped.
MENISCUS_ENV_INLINE vec3 environmentTexel(EnvironmentMap env, int i, int j) {
    const int k = 3 * (j * env.width + i);
    return vec3(MENISCUS_ENV_TEXEL(env, k), MENISCUS_ENV_TEXEL(env, k + 1), MENISCUS_ENV_TEXEL(env, k + 2));
}

// Linear RGB radiance of the map along a world direction (dx, dy, dz), need
// not be unit: bilinear, wrapped in u, clamped in v, times the intensity.
MENISCUS_ENV_INLINE vec3 environmentMapRadiance(float dx, float dy, float dz, EnvironmentMap env) {
    MENISCUS_ENV_EXACT float u = environmentU(dx, dz, env.rotation);
    MENISCUS_ENV_EXACT float v = environmentV(dx, dy, dz);
    // Continuous texel coordinates with the texel centres at integers.
    MENISCUS_ENV_EXACT float fu = (u - floor(u)) * float(env.width) - 0.5f;
    MENISCUS_ENV_EXACT float fv = min(max(v * float(env.height) - 0.5f, 0.0f), float(env.height - 1));
    MENISCUS_ENV_EXACT float iu = floor(fu);
    MENISCUS_ENV_EXACT float iv = floor(fv);
    MENISCUS_ENV_EXACT float tu = fu - iu;
    MENISCUS_ENV_EXACT float tv = fv - iv;
    // fu lies in [-0.5, W - 0.5): i0 in [-1, W - 1], wrapped; a float rounding
    // of u - floor(u) to 1 is caught by the same wrap.
    int i0 = int(iu);
    i0 = i0 < 0 ? i0 + env.width : (i0 >= env.width ? i0 - env.width : i0);
    const int i1 = i0 + 1 >= env.width ? 0 : i0 + 1;
    const int j0 = min(int(iv), env.height - 1);
    const int j1 = min(j0 + 1, env.height - 1);
    MENISCUS_ENV_EXACT vec3 c00 = environmentTexel(env, i0, j0);
    MENISCUS_ENV_EXACT vec3 c10 = environmentTexel(env, i1, j0);
    MENISCUS_ENV_EXACT vec3 c01 = environmentTexel(env, i0, j1);
    MENISCUS_ENV_EXACT vec3 c11 = environmentTexel(env, i1, j1);
    MENISCUS_ENV_EXACT vec3 c = bilinearMix(c00, c10, c01, c11, tu, tv);
    return c * env.intensity;
}

// What the liquid mirrors along a reflected direction with a map: the map,
// turning below the horizon toward `behind` (what the liquid shows through
// itself) by sky.h's groundShare, for the reason reflectionRadiance gives (the
// screen-space pipeline has no scene below the horizon to reflect), and so the
// colour stays affine in `behind` with the same share the layer split uses.
MENISCUS_ENV_INLINE vec3 environmentReflection(float dx, float dy, float dz, EnvironmentMap env, vec3 behind) {
    MENISCUS_ENV_EXACT vec3 e = environmentMapRadiance(dx, dy, dz, env);
    MENISCUS_ENV_EXACT float g = groundShare(dx, dy, dz);
    return e * (1.0f - g) + behind * g;
}

// The real spherical harmonic k = l (l + 1) + m, bands l <= 2, at the unit
// direction (x, y, z) (Ramamoorthi & Hanrahan 2001, eq. 3, taken in the world
// axes as they are: the paper's z is up, here y is, which does not matter as
// long as the projection and the evaluation share the frame):
// Y00; Y1-1, Y10, Y11; Y2-2, Y2-1, Y20, Y21, Y22.
MENISCUS_ENV_INLINE float environmentShBasis(int k, float x, float y, float z) {
    return k == 0   ? 0.282095f
           : k == 1 ? 0.488603f * y
           : k == 2 ? 0.488603f * z
           : k == 3 ? 0.488603f * x
           : k == 4 ? 1.092548f * (x * y)
           : k == 5 ? 1.092548f * (y * z)
           : k == 6 ? 0.315392f * (3.0f * (z * z) - 1.0f)
           : k == 7 ? 1.092548f * (x * z)
                    : 0.546274f * (x * x - y * y);
}

// The irradiance E(n) of the map (times its intensity, with its rotation)
// at the unit normal (nx, ny, nz): sum of irradiance[k] Y_k(n), from the
// coefficients the host projected; at least 0 (the band-limited fit can ring
// a little below 0 over a black region).
MENISCUS_ENV_INLINE vec3 environmentIrradiance(float nx, float ny, float nz, EnvironmentMap env) {
    vec3 e = vec3(0.0f, 0.0f, 0.0f);
    for (int k = 0; k < 9; ++k) e = e + env.irradiance[k] * environmentShBasis(k, nx, ny, nz);
    return vec3(max(e.x, 0.0f), max(e.y, 0.0f), max(e.z, 0.0f));
}

// The diffuse ambient a Lambertian surface of albedo 1 with unit normal n
// reflects under the map: E(n) / pi (a constant map of radiance L gives L).
MENISCUS_ENV_INLINE vec3 environmentAmbient(float nx, float ny, float nz, EnvironmentMap env) {
    return environmentIrradiance(nx, ny, nz, env) * (1.0f / MENISCUS_ENV_PI);
}

#ifdef __cplusplus
// The coefficients A_l L_lm of environmentIrradiance for the W x H map
// `texels` (RGB, row after row from the top, this file's convention) turned
// by `rotation` (turns about +y) and times `intensity`, into out[9].
void environmentIrradianceSh(const float* texels, int width, int height, float rotation, float intensity,
                             vec3 out[9]);
#endif

#ifdef __cplusplus
}  // namespace meniscus::shared
#endif
#undef MENISCUS_ENV_PI
#undef MENISCUS_ENV_INLINE
#undef MENISCUS_ENV_EXACT
#undef MENISCUS_ENV_TEXEL

#endif  // MENISCUS_SHARED_ENVIRONMENT_H
