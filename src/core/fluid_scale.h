// Reduced-resolution processing (docs/pipeline.md#reduced-resolution): the
// divisor of a fluid scale, the camera the low-resolution stages run on, and
// the nearest-pixel upsampling of the raw splat AOV. The depth-aware upsampling
// itself is a stage of the backends (cpu/upsample.h, gl/upsample.h; formulas in
// shared/upsample.h).
#pragma once

#include "meniscus/camera.h"
#include "meniscus/types.h"

namespace meniscus {

// The divisor d of a fluid scale: 1, 2 or 4 for 1, 0.5 or 0.25; 0 for any other value.
int fluidDivisor(float scale);

// The camera of the low-resolution stages for divisor d: the same eye,
// target, up, near and far, ceil(W/d) x ceil(H/d) pixels and the focal length
// f/d (the field of view grows by the rows ceil(H/d) d adds to H, half above
// and half below), so low pixel i covers the full pixels shared::lowPixelSpan
// gives. d = 1: the camera itself.
Camera reducedCamera(const Camera& full, int d);

// A low-resolution image at W x H, each full pixel taking its nearest low
// pixel (shared::nearestLowPixel): the raw splat's AOV at full size.
Image<float> nearestUpsample(const Image<float>& low, int W, int H, int d);

}  // namespace meniscus
