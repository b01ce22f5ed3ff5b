// What the thickness stage (docs/pipeline.md#thickness) of both backends derives from
// ThicknessParams, written once: the calibration weight, the grid divisor and
// the blur's kernel cap. C++ only (the GL backend passes the results to its
// shaders through the frame block and uniforms).
#pragma once

#include "meniscus/params.h"

namespace meniscus::shared {

// The calibration weight w = s^3 / (4/3 pi r^3) (s = params.spacingM, or 2 r
// when 0): spheres at rest spacing s fill 4/3 pi r^3 / s^3 of the space, so a
// block's summed chords times w read its true depth.
float thicknessWeight(float radius, const ThicknessParams& params);

// The thickness grid's pixels per block side for ThicknessParams::resolutionDivisor:
// 1, 2 or 4 (rounded down to one of them; below 1 counts as 1).
int thicknessDivisor(int resolutionDivisor);

// The blur's largest kernel radius in pixels: maxKernelPx clamped to
// [0, kThicknessBlurMaxPx] (the CPU keeps each pixel's radius in a byte).
inline constexpr int kThicknessBlurMaxPx = 255;
int thicknessBlurCapPx(int maxKernelPx);

}  // namespace meniscus::shared
