// The procedural sky (docs/pipeline.md#scene), written once for C++ and GLSL
// (src/shared/ is compiled by C++ and included by the GL shaders): the
// background where no studio geometry is hit and the environment map the fluid
// reflects. cpu::skyColorRgb (src/cpu/sky.h) and the GL scene and shading
// shaders all call skyRadiance (its sun is the user's light direction), so the
// two backends evaluate the same operations in the same order; in GLSL every
// intermediate is `precise` (no FMA contraction or reassociation), matching the
// CPU's plain IEEE arithmetic.
// Branch-free (both candidates computed, one selected) so that the CPU's
// per-row loops vectorise it. An HDR environment map (environment.h,
// --environment) takes the sky's place where one is given.
#ifndef MENISCUS_SHARED_SKY_H
#define MENISCUS_SHARED_SKY_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
#include <limits>
#include <glm/glm.hpp>
namespace meniscus::shared {
using vec3 = glm::vec3;
using std::max;
using std::min;
using std::sqrt;
#define MENISCUS_SKY_INLINE inline
#define MENISCUS_SKY_EXACT const  // C++: plain IEEE float arithmetic already
#else
#define MENISCUS_SKY_INLINE
#define MENISCUS_SKY_EXACT precise
#endif

// The sky's colour far below the horizon (linear RGB, a brownish ground).
#define MENISCUS_SKY_GROUND vec3(0.30f, 0.28f, 0.26f)

// The ground's share of the environment along a world-space direction (need
// not be unit): 0 at and above the horizon, min(1, -4 y) below it for the unit
// direction's y, so the ground takes over within 15 degrees or so.
MENISCUS_SKY_INLINE float groundShareOfY(float y) { return y >= 0.0f ? 0.0f : min(1.0f, -4.0f * y); }
MENISCUS_SKY_INLINE float groundShare(float dx, float dy, float dz) {
    MENISCUS_SKY_EXACT float len = sqrt(dx * dx + dy * dy + dz * dz);
    MENISCUS_SKY_EXACT float inv = 1.0f / len;
    return groundShareOfY(len > 0.0f ? dy * inv : 1.0f);  // environmentRadiance's y, the same bits
}

// Linear RGB radiance of the environment along a world-space direction (dx, dy,
// dz), which need not be unit: a bright horizon band fading to a deep zenith
// blue above the horizon, and toward `ground` within 15 degrees or so below
// it, plus a soft sun glow around `sun` (unit, world space, toward the sun:
// sunDirection of the key light) so reflections carry a highlight.
MENISCUS_SKY_INLINE vec3 environmentRadiance(float dx, float dy, float dz, vec3 sun, vec3 ground) {
    MENISCUS_SKY_EXACT float len = sqrt(dx * dx + dy * dy + dz * dz);
    bool ok = len > 0.0f;
    MENISCUS_SKY_EXACT float inv = 1.0f / len;  // one division, not three (shading calls this twice per pixel)
    MENISCUS_SKY_EXACT float x = ok ? dx * inv : 0.0f;
    MENISCUS_SKY_EXACT float y = ok ? dy * inv : 1.0f;
    MENISCUS_SKY_EXACT float z = ok ? dz * inv : 0.0f;
    // Above the horizon mix toward the zenith by sqrt(y), below toward the ground
    // (groundShareOfY); both computed, one selected.
    bool up = y >= 0.0f;
    MENISCUS_SKY_EXACT float t = up ? sqrt(max(y, 0.0f)) : groundShareOfY(y);
    MENISCUS_SKY_EXACT float u = 1.0f - t;
    MENISCUS_SKY_EXACT float cr = 0.78f * u + (up ? 0.16f : ground.x) * t;
    MENISCUS_SKY_EXACT float cg = 0.85f * u + (up ? 0.34f : ground.y) * t;
    MENISCUS_SKY_EXACT float cb = 0.93f * u + (up ? 0.70f : ground.z) * t;
    // Sun glow toward the key light, s^64 by squarings rather than pow.
    MENISCUS_SKY_EXACT float s = max(0.0f, x * sun.x + y * sun.y + z * sun.z);
    MENISCUS_SKY_EXACT float s2 = s * s;
    MENISCUS_SKY_EXACT float s4 = s2 * s2;
    MENISCUS_SKY_EXACT float s8 = s4 * s4;
    MENISCUS_SKY_EXACT float s16 = s8 * s8;
    MENISCUS_SKY_EXACT float s32 = s16 * s16;
    MENISCUS_SKY_EXACT float glow = 0.6f * (s32 * s32);
    return vec3(cr + 1.0f * glow, cg + 0.95f * glow, cb + 0.85f * glow);
}

// The sky: the background where no studio geometry is hit.
MENISCUS_SKY_INLINE vec3 skyRadiance(float dx, float dy, float dz, vec3 sun) {
    return environmentRadiance(dx, dy, dz, sun, MENISCUS_SKY_GROUND);
}

// What the liquid mirrors along a reflected world direction. Above the horizon
// the sky. Below it the reflected ray heads into the scene (the floor, the
// liquid further back), which the screen-space pipeline does not have; there
// `behind`, the colour the liquid shows through itself at this pixel, takes the
// ground's place. A reflected ray turns below the horizon mostly at grazing
// incidence (a crest's top edge, the flank of a wave over liquid behind it),
// where it runs on almost along the view ray and so meets about what the view
// ray meets. With the sky's brown ground instead, Fresnel (near 1 there) drew
// those edges as brown and grey lines over the blue liquid. The colour stays
// affine in what lies behind (shared/fluids.h): groundShare of this direction
// is the reflection's share of `behind`.
MENISCUS_SKY_INLINE vec3 reflectionRadiance(float dx, float dy, float dz, vec3 sun, vec3 behind) {
    return environmentRadiance(dx, dy, dz, sun, behind);
}

#ifdef __cplusplus
// The sky's sun for a light direction (ShadingParams::lightDirWorld, toward
// the light, need not be unit): that direction normalised, the zenith when it
// is zero or not finite. Computed once per image on the host (the GL shaders
// get it as a uniform), so both backends see the same bits.
inline vec3 sunDirection(const vec3& lightDirWorld) {
    const float len = sqrt(lightDirWorld.x * lightDirWorld.x + lightDirWorld.y * lightDirWorld.y +
                           lightDirWorld.z * lightDirWorld.z);
    if (!(len > 0.0f) || !(len < std::numeric_limits<float>::infinity())) return vec3(0.0f, 1.0f, 0.0f);
    return lightDirWorld * (1.0f / len);
}

}  // namespace meniscus::shared
#endif
#undef MENISCUS_SKY_GROUND
#undef MENISCUS_SKY_INLINE
#undef MENISCUS_SKY_EXACT

#endif  // MENISCUS_SHARED_SKY_H
