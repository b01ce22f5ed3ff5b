// packFrameParams: RenderSettings -> the shared std140 block (see uniforms.h).
#include "gl/uniforms.h"

#include <algorithm>
#include <limits>
#include <type_traits>

#include "shared/thickness.h"  // thicknessWeight: the calibration written once

namespace meniscus::gl {

FrameParams packFrameParams(const Camera& camera, float radius, const FilterParams& filter,
                            const ThicknessParams& thickness, const ShadingParams& shading) {
    FrameParams p{};
    const float f = camera.focalPx();
    const glm::vec3 right = camera.right(), up = camera.trueUp(), back = camera.back();
    p.eye = glm::vec4(camera.eye, std::max(camera.nearM, std::numeric_limits<float>::min()));
    p.right = glm::vec4(right, f);
    p.up = glm::vec4(up, 1.0f / f);
    p.back = glm::vec4(back, camera.farM);
    p.size = glm::ivec4(camera.width, camera.height, 0, 0);

    const Material& m = shading.material;
    p.fluidColor = glm::vec4(m.fluidColor, m.opacity);
    p.absorptionPerM = glm::vec4(m.absorptionPerM, m.ior);
    p.lightDirWorld = glm::vec4(shading.lightDirWorld, m.refraction);
    p.radius = radius;
    p.normalsJumpRadii = defaults::kDepthJumpRadii;
    p.specular = m.specular;
    p.shininess = m.shininess;

    p.filterKind = int(filter.index());
    p.filterIterations = filterIterations(filter);
    std::visit(
        [&](const auto& q) {
            using Q = std::decay_t<decltype(q)>;
            if constexpr (std::is_same_v<Q, GaussianParams>) {
                p.filterJumpRadii = q.jumpRadii;
                p.filterMaxKernelPx = q.maxKernelPx;
                p.gaussianSigmaRadii = q.sigmaRadii;
            } else if constexpr (std::is_same_v<Q, BilateralParams>) {
                p.filterJumpRadii = q.jumpRadii;
                p.filterMaxKernelPx = q.maxKernelPx;
                p.bilateralSigmaRadii = q.sigmaRadii;
                p.bilateralRangeSigmaRadii = q.rangeSigmaRadii;
            } else if constexpr (std::is_same_v<Q, BinomialParams>) {
                p.filterJumpRadii = q.jumpRadii;
                p.filterMaxKernelPx = q.maxKernelPx;
                p.binomialSizeRadii = q.sizeRadii;
            } else if constexpr (std::is_same_v<Q, CurvatureFlowParams>) {
                p.filterJumpRadii = q.jumpRadii;
                p.cfAlpha = q.alpha;
            } else if constexpr (std::is_same_v<Q, NarrowRangeParams>) {
                p.filterMaxKernelPx = q.maxKernelPx;
                p.nrFilterSizeRadii = q.filterSizeRadii;
                p.nrLambda = q.lambda;
                p.nrMu = q.mu;
                p.nrSeparable = q.separable ? 1 : 0;
            }
        },
        filter);
    static_assert(std::variant_size_v<FilterParams> == 6, "filterKind numbering follows the variant order");

    p.thicknessWeight = shared::thicknessWeight(radius, thickness);
    p.thicknessBlurSigmaRadii = thickness.blurSigmaRadii;
    p.thicknessMaxKernelPx = thickness.maxKernelPx;
    p.thicknessResolutionDivisor = thickness.resolutionDivisor;
    p.thicknessMinRadii = thickness.minRadii;
    return p;
}

}  // namespace meniscus::gl
