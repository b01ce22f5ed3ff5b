// Procedural sky gradient: ground below the horizon, a bright horizon band
// fading to a deep zenith blue, and a soft sun glow so reflections carry a
// highlight. Linear RGB.
#include "cpu/sky.h"

#include <algorithm>
#include <cmath>

namespace meniscus::cpu {

glm::vec3 skyColor(const glm::vec3& dirWorld) {
    const float len = glm::length(dirWorld);
    const glm::vec3 d = len > 0.0f ? dirWorld / len : glm::vec3(0.0f, 1.0f, 0.0f);
    const glm::vec3 horizon(0.78f, 0.85f, 0.93f), zenith(0.16f, 0.34f, 0.70f), ground(0.30f, 0.28f, 0.26f);
    glm::vec3 c;
    if (d.y >= 0.0f)
        c = glm::mix(horizon, zenith, std::sqrt(d.y));
    else
        c = glm::mix(horizon, ground, std::min(1.0f, -4.0f * d.y));
    // Sun glow toward the default key light (the same direction as ShadingParams).
    const glm::vec3 sun = glm::normalize(glm::vec3(-0.4f, 1.0f, 0.55f));
    const float s = std::max(0.0f, glm::dot(d, sun));
    const float s2 = s * s, s4 = s2 * s2, s8 = s4 * s4, s16 = s8 * s8, s32 = s16 * s16;  // s^64 without pow:
    return c + glm::vec3(1.0f, 0.95f, 0.85f) * (0.6f * (s32 * s32));                   // called per fluid pixel
}

}  // namespace meniscus::cpu
