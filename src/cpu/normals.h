// CPU normals stage (docs/pipeline.md#normals): view-space normals from the
// smoothed eye depth by exact back-projection.
#pragma once

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// Unit view-space normals (+z toward the camera) where depth is finite, (0,0,0)
// elsewhere. At a discontinuity (|dz| > jumpRadii * r) the one-sided difference
// with the smaller |dz| is used. Bit-identical for any thread count.
Image<glm::vec3> computeNormals(const Image<float>& depth, const Camera& camera, float radius, float jumpRadii);

// The same into `out`, reusing its pixels when it already has depth's size
// (a frame's normals over the last frame's: no allocation, and every pixel is
// written in the parallel row loop instead of zero-filled first on one thread).
void computeNormals(const Image<float>& depth, const Camera& camera, float radius, float jumpRadii,
                    Image<glm::vec3>& out);

}  // namespace meniscus::cpu
