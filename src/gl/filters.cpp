// The smooth stage's GL driver: the filter the FrameSettings' variant names,
// each its own pass (gl/filter_*.cpp), as cpu/filters.cpp dispatches on the CPU.
#include <type_traits>
#include <variant>

#include "gl/filter_curvature_flow.h"
#include "gl/filter_narrow_range.h"
#include "gl/filter_separable.h"
#include "gl/gl_backend.h"

namespace meniscus::gl {

namespace {

// The stage follows the filter variant itself: a filter added to
// FilterParams without a GL pass does not compile.
void runSmooth(GlBackend& g, const StageIo& io) {
    g.forget(io.at.depth);
    GpuImage& src = g.img(io.at.raw);
    GpuImage& dst = g.img(io.at.depth);
    const FrameParams& fp = g.params();
    std::visit(
        [&](const auto& q) {
            using Q = std::decay_t<decltype(q)>;
            if constexpr (std::is_same_v<Q, NoFilter>) {
                dst.copyFrom(src);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
            } else if constexpr (std::is_same_v<Q, GaussianParams>) {
                g.pass<SeparableFilters>().run(fp, SeparableKind::Gaussian, src, dst);
            } else if constexpr (std::is_same_v<Q, BilateralParams>) {
                g.pass<SeparableFilters>().run(fp, SeparableKind::Bilateral, src, dst);
            } else if constexpr (std::is_same_v<Q, BinomialParams>) {
                g.pass<SeparableFilters>().run(fp, SeparableKind::Binomial, src, dst);
            } else if constexpr (std::is_same_v<Q, CurvatureFlowParams>) {
                g.pass<CurvatureFlow>().run(fp, src, dst);
            } else if constexpr (std::is_same_v<Q, NarrowRangeParams>) {
                g.pass<NarrowRange>().run(fp, src, dst);
            } else {
                static_assert(sizeof(Q) == 0, "a filter without a GL pass");
            }
        },
        g.frame().filter);
}

}  // namespace

// The stage's GL driver (core/backend.h StageDriver), named by its row in the
// stage list (src/render/stages.cpp).
extern const StageDriver kSmoothStage = {glPrepare<SeparableFilters, CurvatureFlow, NarrowRange>, glRun<runSmooth>};

}  // namespace meniscus::gl
