// The procedural sky (SPEC §3.1): background where no geometry is hit and the
// environment map that the fluid reflects. Shared by the scene and shading stages.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace meniscus::cpu {

// Linear RGB radiance of the sky along a world-space direction (need not be unit).
glm::vec3 skyColor(const glm::vec3& dirWorld);

// The same function on scalars, branch-free and inline so that the shading
// stage's per-row loops can vectorise it; skyColor calls it, so both agree bit
// for bit. Ground below the horizon, a bright horizon band fading to a deep
// zenith blue, and a soft sun glow so reflections carry a highlight.
inline void skyColorRgb(float dx, float dy, float dz, float* r, float* g, float* b) {
    const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
    const bool ok = len > 0.0f;
    const float inv = 1.0f / len;  // one division, not three (shading calls this twice per pixel)
    const float x = ok ? dx * inv : 0.0f, y = ok ? dy * inv : 1.0f, z = ok ? dz * inv : 0.0f;
    // Above the horizon mix toward the zenith by sqrt(y), below toward the ground
    // within 15 degrees or so; both branches computed, one selected.
    const bool up = y >= 0.0f;
    const float t = up ? std::sqrt(std::max(y, 0.0f)) : std::min(1.0f, -4.0f * y);
    const float u = 1.0f - t;
    const float cr = 0.78f * u + (up ? 0.16f : 0.30f) * t;
    const float cg = 0.85f * u + (up ? 0.34f : 0.28f) * t;
    const float cb = 0.93f * u + (up ? 0.70f : 0.26f) * t;
    // Sun glow toward the default key light (the same direction as ShadingParams),
    // s^64 by squarings rather than pow.
    constexpr float sx = -0.4f, sy = 1.0f, sz = 0.55f;
    const float sInv = 1.0f / std::sqrt(sx * sx + sy * sy + sz * sz);
    const float s = std::max(0.0f, x * (sx * sInv) + y * (sy * sInv) + z * (sz * sInv));
    const float s2 = s * s, s4 = s2 * s2, s8 = s4 * s4, s16 = s8 * s8, s32 = s16 * s16;
    const float glow = 0.6f * (s32 * s32);
    *r = cr + 1.0f * glow;
    *g = cg + 0.95f * glow;
    *b = cb + 0.85f * glow;
}

}  // namespace meniscus::cpu
