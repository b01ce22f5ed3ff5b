// Separable Gaussian smoothing of the eye depth (docs/pipeline.md#smoothing),
// after the patent "System and method for rendering a particle-based fluid
// surface" (van der Laan, Green, Sainz): "the amount of smoothing is varied as
// a function of the particle depth ... the kernel is substantially constant in
// width in world space", split into two 1-D passes. Per centre pixel sigma_px =
// sigmaRadii * r * f / z0 and the kernel radius is 3 sigma_px (capped).
// Taps across a depth jump or on +inf are dropped and the weights renormalised
// (the patent: "blending over silhouettes is minimized"); see filter_separable.h.
#include "cpu/filter_separable.h"
#include "cpu/filters.h"

namespace meniscus::cpu {

Image<float> filterGaussian(const Image<float>& depth, const Camera& camera, float radius, const GaussianParams& p) {
    const KernelTable table = KernelTable::gaussian(p.maxKernelPx);
    const SeparableKernel kernel{3.0f * p.sigmaRadii * radius, p.jumpRadii * radius};
    return separableFilter(depth, camera.focalPx(), table, kernel, p.iterations, NoRangeWeight{});
}

}  // namespace meniscus::cpu
