// CPU silhouette reduction (Cords & Staadt 2008, "Instant Liquids" §3;
// docs/pipeline.md#silhouette-reduction): the fluid mask's summed-area table,
// the fluid fraction S of each fluid pixel's window, and the liquid faded by it
// into the scene behind. Formulas: src/shared/silhouette.h.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// The summed-area table of the fluid mask (depth < +inf): (W + 1) x (H + 1)
// counts, row-major, entry (x, y) = fluid pixels in [0, x) x [0, y).
std::vector<std::uint32_t> fluidSummedArea(const Image<float>& depth);

// S per pixel (0 where `depth` has no fluid), from the window of
// params.radiusRadii r at each fluid pixel's depth.
Image<float> silhouetteMap(const Camera& camera, const Image<float>& depth, float radius, const SilhouetteParams& p);

// Fades `color` (the shaded frame) in place into `behind` (the scene colour;
// camera-sized) by each fluid pixel's alpha of S, and returns S. Sizes that
// do not match leave the colour as it is and give S = 0.
Image<float> reduceSilhouettes(const Camera& camera, const Image<float>& depth, const Image<glm::vec4>& behind,
                               float radius, const SilhouetteParams& p, Image<glm::vec4>& color);

}  // namespace meniscus::cpu
