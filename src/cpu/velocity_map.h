// CPU velocity whitening map (docs/pipeline.md#noise-and-foam; Instant Liquids
// §4): the weighted mean whiteness of the particles near the smoothed surface,
// per pixel. The formulas are src/shared/velocity_map.h's.
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// The map in [0, 1] where `depth` (the smoothed surface) has fluid, 0
// elsewhere; whiteness[i] is particle i's (shared::whitenessOfSpeed; empty:
// all 0). Exact: the same image for any thread count.
Image<float> splatWhitening(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                            const Image<float>& depth, std::span<const float> whiteness, const WhiteningParams& params);

}  // namespace meniscus::cpu
