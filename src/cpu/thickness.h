// CPU thickness stage (SPEC §3.4): the summed chord length of each pixel ray
// inside the particle spheres in front of the scene, calibrated so a block at
// rest spacing reads its true depth; optionally Gaussian-blurred.
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// T(x,y) = w * sum_i chord_i(x,y), w = s^3 / (4/3 pi r^3), in metres; 0 where no
// sphere is hit. Chords are clipped to [near, sceneDepth(x,y)) when sceneDepth
// is given. Blurred when params.blurSigmaRadii > 0 (sigma projected with the
// raw fluid depth). Bit-identical for any thread count.
Image<float> computeThickness(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                              const ThicknessParams& params, const Image<float>* sceneDepth,
                              const Image<float>& rawDepth);

}  // namespace meniscus::cpu
