// Separable binomial smoothing of the eye depth (docs/pipeline.md#smoothing),
// Cords & Staadt, "Instant Liquids" (JGT 2008) §2.2: a separable binomial
// low-pass filter whose initial kernel size is "equal to the point splat
// radius" r_s, the user scaling it from there (too small leaves holes, too
// large suppresses splashes). Here the kernel half-size is
// n = sizeRadii * r * f / z0 pixels per centre pixel (the projected splat
// radius at that depth, capped) with weights C(2n, n + k) / 4^n, i.e. row 2n of
// Pascal's triangle, tabulated once. Like the other filters, taps across a
// depth jump or on +inf are dropped and the weights renormalised (the paper
// filters blindly and then hides the silhouette halo; here separate bodies
// simply never blend).
#include "cpu/filter_separable.h"
#include "cpu/filters.h"

namespace meniscus::cpu {

Image<float> filterBinomial(const Image<float>& depth, const Camera& camera, float radius, const BinomialParams& p) {
    const KernelTable table = KernelTable::binomial(p.maxKernelPx);
    const SeparableKernel kernel{p.sizeRadii * radius, p.jumpRadii * radius};
    return separableFilter(depth, camera.focalPx(), table, kernel, p.iterations, NoRangeWeight{});
}

}  // namespace meniscus::cpu
