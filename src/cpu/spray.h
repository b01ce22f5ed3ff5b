// CPU spray drops (docs/pipeline.md#classification,
// docs/pipeline.md#noise-and-foam): the particles classified as spray drawn as
// small lit, semi-transparent drops stretched along their velocity, composited
// with depth over the shaded image. Formulas: src/shared/spray.h.
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"
#include "shared/environment.h"

namespace meniscus::cpu {

// Lays the drops (world positions and velocities, m/s; velocities may be
// empty: round drops) over `color` in place, each hidden where the fluid's
// `depth` or the `sceneDepth` (when given, camera-sized) is nearer than the
// drop's centre, and returns their cover per pixel (0 = none). The drops'
// colour is lit by lightDirWorld and the ambient, the studio's or, with an
// HDR `environment`, its irradiance (shared::sprayLight, the GL twin's too).
// Exact: the same image for any thread count.
Image<float> drawSpray(const Camera& camera, std::span<const glm::vec3> positionsWorld,
                       std::span<const glm::vec3> velocitiesWorld, float radius, const Image<float>& depth,
                       const Image<float>* sceneDepth, const SprayParams& params, const glm::vec3& lightDirWorld,
                       Image<glm::vec4>& color, const shared::EnvironmentMap& environment = {});

}  // namespace meniscus::cpu
