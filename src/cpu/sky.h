// The procedural sky (SPEC §3.1): background where no geometry is hit and the
// environment map that the fluid reflects. Shared by the scene and shading stages.
#pragma once

#include <glm/glm.hpp>

namespace meniscus::cpu {

// Linear RGB radiance of the sky along a world-space direction (need not be unit).
glm::vec3 skyColor(const glm::vec3& dirWorld);

}  // namespace meniscus::cpu
