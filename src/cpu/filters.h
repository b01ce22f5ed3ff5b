// CPU smoothing filters for the splatted eye depth
// (docs/pipeline.md#smoothing). Each filter is its own file (filter_<name>.cpp)
// citing its paper. Common rules: +inf ("no fluid") pixels stay +inf and never
// feed a neighbour; depth steps larger than jumpRadii * r are never averaged
// across; every pixel size comes from the camera (projected radius r * f / z);
// output is bit-identical for any thread count.
#pragma once

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

Image<float> filterGaussian(const Image<float>& depth, const Camera& camera, float radius, const GaussianParams& p);
Image<float> filterBilateral(const Image<float>& depth, const Camera& camera, float radius, const BilateralParams& p);
Image<float> filterBinomial(const Image<float>& depth, const Camera& camera, float radius, const BinomialParams& p);
Image<float> filterCurvatureFlow(const Image<float>& depth, const Camera& camera, float radius,
                                 const CurvatureFlowParams& p);
Image<float> filterNarrowRange(const Image<float>& depth, const Camera& camera, float radius,
                               const NarrowRangeParams& p);

// Dispatches on the variant (NoFilter returns the input).
Image<float> smoothDepth(const Image<float>& depth, const Camera& camera, float radius, const FilterParams& p);

}  // namespace meniscus::cpu
