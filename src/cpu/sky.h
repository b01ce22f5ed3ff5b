// The procedural sky (docs/pipeline.md#scene): background where no geometry is
// hit and the environment map that the fluid reflects. Shared by the scene and
// shading stages.
#pragma once

#include <glm/glm.hpp>

#include "shared/sky.h"

namespace meniscus::cpu {

// Linear RGB radiance of the sky along a world-space direction (need not be
// unit) with its sun toward `sunDir` (unit: shared::sunDirection of the light).
glm::vec3 skyColor(const glm::vec3& dirWorld, const glm::vec3& sunDir);

// The same function on scalars, branch-free and inline so that the shading
// stage's per-row loops can vectorise it; skyColor calls it, so both agree bit
// for bit. The formula is written once, in src/shared/sky.h, for this backend
// and the GL shaders alike.
inline void skyColorRgb(float dx, float dy, float dz, const glm::vec3& sunDir, float* r, float* g, float* b) {
    const glm::vec3 c = shared::skyRadiance(dx, dy, dz, sunDir);
    *r = c.x;
    *g = c.y;
    *b = c.z;
}

// What the liquid mirrors along a reflected direction: the sky above the
// horizon, the colour (br, bg, bb) the liquid shows through itself below it
// (shared::reflectionRadiance), inline for the same reason.
inline void reflectionRgb(float dx, float dy, float dz, const glm::vec3& sunDir, float br, float bg, float bb, float* r,
                          float* g, float* b) {
    const glm::vec3 c = shared::reflectionRadiance(dx, dy, dz, sunDir, glm::vec3(br, bg, bb));
    *r = c.x;
    *g = c.y;
    *b = c.z;
}

}  // namespace meniscus::cpu
