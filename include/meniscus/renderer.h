// The screen-space pipeline's public entry point. The stage order lives in
// src/core/pipeline.cpp and nowhere else.
#pragma once

#include <span>

#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

// What a person sees in the 8-bit output. Only the raw splat depth exists so
// far; the shaded image, normals and thickness views arrive with the CPU
// shading pipeline.
enum class View { Depth };

struct RenderSettings {
    Camera camera;           // must be valid (see validateCamera / autoFrameCamera)
    float radiusM = 0.0f;    // particle radius in metres, > 0
    View view = View::Depth;
};

// Renders one frame. Fills the AOVs that the implemented stages produce
// (rawDepth and color; color.a is the fluid coverage).
Result<Aovs> renderFrame(std::span<const glm::vec3> positions, const RenderSettings& settings);

}  // namespace meniscus
