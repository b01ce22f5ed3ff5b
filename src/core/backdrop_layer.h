// A backdrop (include/meniscus/backdrop.h) as the scene layer both backends
// composite the liquid into: its colour as it is and its depth turned into
// linear eye depth for the camera (src/shared/backdrop.h). Made on the host,
// once per camera and backdrop (each backend keeps it while they stay): the CPU
// uses it as its scene layer, the GL backend uploads it into its scene
// textures, so the two composite over the same bits.
#pragma once

#include <glm/glm.hpp>

#include "meniscus/backdrop.h"
#include "meniscus/camera.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

// Colour (linear RGBA) and eye depth (metres, +inf: nothing) of every pixel;
// the sizes must match (checkBackdropSize). Threaded by rows; the same bits
// for any thread count.
void backdropLayer(const Camera& camera, const BackdropImage& backdrop, Image<glm::vec4>& color,
                   Image<float>& depth);

}  // namespace meniscus
