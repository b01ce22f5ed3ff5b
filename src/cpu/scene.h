// CPU scene stage (docs/pipeline.md#scene): the default studio (checker floor, two back
// walls; shared::makeStudio builds it) ray-cast per pixel into colour and eye
// depth, and the procedural sky that serves as background and environment map.
#pragma once

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"
#include "shared/environment.h"
#include "shared/studio.h"

namespace meniscus::cpu {

struct SceneLayer {
    Image<glm::vec4> color;  // linear RGB; alpha 1 where opaque, 0 for a transparent background
    Image<float> depth;      // eye depth of the studio geometry, +inf where only sky is seen
};

// Ray-casts the studio for every pixel centre: colour (checker, flat lambert +
// ambient lit from studio.lightDirWorld, corner darkening, far fade into the
// sky) and eye depth of the nearest plane; skyColor (its sun toward
// studio.lightDirWorld) and +inf depth where none is hit; all (0,0,0,0) and
// +inf when the studio is disabled. Bit-identical for any thread count.
// With `environment` enabled, the HDR map (shared/environment.h) instead of the sky.
SceneLayer castScene(const Camera& camera, const shared::Studio& studio,
                     const shared::EnvironmentMap& environment = {});

}  // namespace meniscus::cpu
