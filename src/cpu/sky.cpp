// Procedural sky gradient (docs/pipeline.md#scene); the formula lives in
// src/shared/sky.h (written once for this backend and the GL shaders) and is
// inlined through sky.h (skyColorRgb) so the shading stage can vectorise it.
#include "cpu/sky.h"

namespace meniscus::cpu {

glm::vec3 skyColor(const glm::vec3& dirWorld, const glm::vec3& sunDir) {
    glm::vec3 c;
    skyColorRgb(dirWorld.x, dirWorld.y, dirWorld.z, sunDir, &c.r, &c.g, &c.b);
    return c;
}

}  // namespace meniscus::cpu
