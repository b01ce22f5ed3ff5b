// CPU thickness stage (docs/pipeline.md#thickness): the summed chord length of
// each pixel ray inside the particle spheres in front of the scene, calibrated
// so a block at rest spacing reads its true depth; optionally Gaussian-blurred.
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "core/anisotropy.h"
#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/sort_last.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// T(x,y) = w * sum_i chord_i(x,y), w = s^3 / (4/3 pi r^3) (shared::thicknessWeight),
// in metres; 0 where no sphere is hit. Each chord is rounded to a whole
// unit of r / shared::kChordScale (1.5e-5 r) and the sum kept in fixed point
// (shared/splat_chords.h), as on GL. Chords are clipped to [near, sceneDepth(x,y)) when sceneDepth
// is given. Blurred when params.blurSigmaRadii > 0 (sigma projected with the
// raw fluid depth `rawDepth`, which must then be camera-sized; only pixels with
// fluid there are blurred, the others keep their unblurred value). With
// params.resolutionDivisor d > 1 the chords are taken through the centres of
// d x d pixel blocks, blurred on that grid and bilinearly upsampled onto the
// fluid pixels of `rawDepth` (0 elsewhere; rawDepth must then be camera-sized).
// With `shapes` (one per position), the particles are those ellipsoids
// (anisotropic kernels) instead of spheres; the weight w stays the sphere's,
// since each ellipsoid keeps the sphere's volume.
// Bit-identical for any thread count.
Image<float> computeThickness(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                              const ThicknessParams& params, const Image<float>* sceneDepth,
                              const Image<float>& rawDepth, std::span<const EllipsoidShape> shapes = {});

// The splat stage's second half (sort-last rendering, meniscus/sort_last.h):
// the thickness in metres of a partial (splatPartial in splat.h; or the
// combination of several processes' partials, which is the partial of all
// their particles): the fixed-point sums times w (shared/splat_chords.h),
// blurred with partial.depth as computeThickness's rawDepth, and with
// params.resolutionDivisor d > 1 upsampled onto partial.depth's fluid pixels.
// partial.depth is camera-sized and partial.chords on the thickness grid
// (camera-sized, or ceil(W / d) x ceil(H / d)); otherwise the result is 0.
Image<float> resolveThickness(const Camera& camera, const SplatPartial& partial, float radius,
                              const ThicknessParams& params);

// splatDepth and computeThickness in one pass over the particles (they share
// the binning and the ray-sphere intersection); the thickness blur uses the
// depth of the same pass. Same results as the two calls, and as
// resolveThickness(splatPartial(...)), which it is.
struct DepthAndThickness {
    Image<float> depth;      // as splatDepth
    Image<float> thickness;  // as computeThickness(..., depth)
};
DepthAndThickness splatDepthAndThickness(const Camera& camera, std::span<const glm::vec3> positionsWorld, float radius,
                                         const ThicknessParams& params, const Image<float>* sceneDepth = nullptr,
                                         std::span<const EllipsoidShape> shapes = {});

}  // namespace meniscus::cpu
