// Filter dispatch: picks the smoothing filter named by the FilterParams variant.
#include "cpu/filters.h"
#include "cpu/cpu_backend.h"

#include <type_traits>

namespace meniscus::cpu {

Image<float> smoothDepth(const Image<float>& depth, const Camera& camera, float radius, const FilterParams& params) {
    return std::visit(
        [&](const auto& p) -> Image<float> {
            using P = std::decay_t<decltype(p)>;
            if constexpr (std::is_same_v<P, NoFilter>) return depth;
            else if constexpr (std::is_same_v<P, GaussianParams>) return filterGaussian(depth, camera, radius, p);
            else if constexpr (std::is_same_v<P, BilateralParams>) return filterBilateral(depth, camera, radius, p);
            else if constexpr (std::is_same_v<P, BinomialParams>) return filterBinomial(depth, camera, radius, p);
            else if constexpr (std::is_same_v<P, CurvatureFlowParams>) return filterCurvatureFlow(depth, camera, radius, p);
            else if constexpr (std::is_same_v<P, NarrowRangeParams>) return filterNarrowRange(depth, camera, radius, p);
            else static_assert(sizeof(P) == 0, "a filter without a CPU stage");
        },
        params);
}

// ---- The stage's CPU driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runSmooth(Backend& b, const StageIo& io) {
    CpuBackend& c = CpuBackend::of(b);
    const FrameSettings& s = c.frame();
    c.scalarOut(io.at.depth) = smoothDepth(c.scalar(io.at.raw), s.camera, s.radius, s.filter);
}

}  // namespace

extern const StageDriver kSmoothStage = {nullptr, runSmooth};

}  // namespace meniscus::cpu
