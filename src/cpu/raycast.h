// CPU raycast stage (docs/pipeline.md#ray-cast-surface): the SPH surface found
// along each covered pixel's ray, in place of the smoothing and the normals.
#pragma once

#include <glm/glm.hpp>

#include "core/sph_field.h"
#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

struct RaycastImages {
    Image<float> depth;       // eye depth of the iso-surface, +inf where the ray found none
    Image<glm::vec3> normal;  // unit view-space normals (-grad F), (0,0,0) where no fluid
};

// Marches the ray of every pixel where `startDepth` (the splat) is finite,
// from that depth (shared::sphRaycast), never beyond the scene depth or the
// far plane. `radius` (metres) scales the step. Bit-identical for any thread count.
RaycastImages raycastSurface(const Camera& camera, const SphField& field, const RaycastParams& params, float radius,
                             const Image<float>& startDepth, const Image<float>* sceneDepth);

}  // namespace meniscus::cpu
