// Separable bilateral smoothing of the eye depth (docs/pipeline.md#smoothing):
// the bilateral filter of the thesis (Janisz, §4.1.2.1, eqs. 4.1-4.3) --
// weights g_s(spatial offset) * g_t(z - z0), both Gaussian -- computed as two
// 1-D passes, x then y, as in Pham & van Vliet, "Separable bilateral filtering
// for fast video preprocessing" (ICME 2005); the y pass takes its range weights
// from the x-filtered depth. Not exact (the bilateral is not separable), but
// the thesis finds the approximation good enough and it is O(m) per pixel
// instead of O(m^2).
// The spatial sigma is constant in world space (sigmaRadii * r projected at the
// centre depth, kernel radius 3 sigma) and the range sigma is rangeSigmaRadii * r:
// both in radii, so the filter is scale-invariant -- unlike a range sigma in
// z-buffer units, which the thesis notes preserves edges less the further the
// surface is. Taps beyond jumpRadii * r or on +inf are dropped outright.
#include "cpu/filter_separable.h"
#include "cpu/filters.h"

namespace meniscus::cpu {

Image<float> filterBilateral(const Image<float>& depth, const Camera& camera, float radius, const BilateralParams& p) {
    const KernelTable table = KernelTable::gaussian(p.maxKernelPx);
    const SeparableKernel kernel{3.0f * p.sigmaRadii * radius, p.jumpRadii * radius};
    return separableFilter(depth, camera.focalPx(), table, kernel, p.iterations, RangeGaussian(p.rangeSigmaRadii * radius));
}

}  // namespace meniscus::cpu
