// CPU surface noise (docs/pipeline.md#noise-and-foam; the NVIDIA SSFR patent,
// eqs. 14-17): the noise image N(x, y) splatted by the particles near the
// smoothed surface, and the normals bumped by its gradient. The formulas are
// src/shared/surface_noise.h's.
#pragma once

#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// N(x, y): the sum over particles of their sprites (noiseContribution) in
// fixed point, 0 where `depth` (the smoothed surface, eye depth, +inf = none)
// has no fluid. idz: each particle's shared::noiseIdCoordinate of its id; amplitude: each particle's turbulence
// factor (empty = all 1). Exact: the same image for any thread count.
Image<float> splatNoise(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                        const Image<float>& depth, std::span<const float> idz, std::span<const float> amplitude,
                        const NoiseParams& params);

// The normals bumped by N's gradient (noisePerturbedNormal), in place; pixels
// without fluid are left as they are.
void bumpNormals(const Camera& camera, float radius, const Image<float>& depth, const Image<float>& noise,
                 const NoiseParams& params, Image<glm::vec3>& normals);

}  // namespace meniscus::cpu
