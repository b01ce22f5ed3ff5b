// CPU reduced-resolution processing (docs/pipeline.md#reduced-resolution; the
// NVIDIA patent; Cords & Staadt 2008, "Instant Liquids" §5): the scene depth
// reduced to the low camera for the low-resolution splat, the low-resolution
// surface brought back to full resolution by depth-aware upsampling, and its
// edges blended into the scene. Formulas: src/shared/upsample.h.
#pragma once

#include <glm/glm.hpp>

#include "meniscus/types.h"

namespace meniscus::cpu {

// The full W x H scene depth reduced to lowW x lowH for divisor d: per low
// pixel the farthest depth of the full pixels it covers (shared::lowPixelSpan).
Image<float> reduceSceneDepth(const Image<float>& full, int lowW, int lowH, int d);

// The low-resolution surface at full resolution.
struct Upsampled {
    Image<float> depth;        // eye depth, +inf = none
    Image<glm::vec3> normal;   // view space, 0 = none
    Image<float> thickness;    // metres, 0 = none
    Image<float> noise;        // the noise N (empty without lowNoise), 0 = none
    Image<float> coverage;     // the fluid taps' bilinear weight c in [0, 1]
};

// Upsamples the low images (lowDepth's size) to W x H for divisor d: per full
// pixel its four nearest low pixels, fluid where their coverage c >= 1/2, the
// fluid taps within `jumpM` metres of the nearest one blended (depth as 1/z),
// and hidden where the result is not in front of `sceneDepth` (W x H; null:
// nothing hides it). `lowNoise` may be null.
Upsampled upsampleSurface(const Image<float>& lowDepth, const Image<glm::vec3>& lowNormal,
                          const Image<float>& lowThickness, const Image<float>* lowNoise,
                          const Image<float>* sceneDepth, int W, int H, int d, float jumpM);

// Blends each fluid pixel (depth < +inf) with coverage c < 1 into `behind`
// (the scene colour) by c, in place. Images of other sizes leave it as it is.
// With `emission` and `transmit` (several fluids, cpu::LayerSplit), the
// split of the blended colour too (shared::fluidEdgeEmission, ...Transmittance).
void blendFluidEdges(const Image<float>& depth, const Image<float>& coverage, const Image<glm::vec4>& behind,
                     Image<glm::vec4>& color, Image<glm::vec4>* emission = nullptr,
                     Image<glm::vec4>* transmit = nullptr);

}  // namespace meniscus::cpu
