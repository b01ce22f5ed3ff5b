// GL curvature flow, docs/pipeline.md#curvature-flow (van der Laan, Green &
// Sainz, I3D 2009): the CPU's double-buffered Jacobi iteration on padded
// buffers, one dispatch per iteration (shaders/filter_curvature_flow.comp; the
// step's formula is src/shared/curvature_flow.h, the CPU's).
// llvmpipe notes (measured at 1280x720): SSBO loads and stores run one SIMD lane
// at a time, texel fetches and image stores are vectorised, so the step reads
// and writes the ping-pong buffers through R32F buffer textures; a pass over
// the whole image pays for background pixels as for fluid ones, so the step
// walks only the row segments with fluid (gl/fluid_segments.h; the fluid set
// never changes). The +inf frame and the image inside it are driver fills and
// row copies, and the last step writes the output directly.
#include "gl/filter_curvature_flow.h"

#include <algorithm>
#include <utility>

#include "gl/shaders.h"

namespace meniscus::gl {

Result<CurvatureFlow> CurvatureFlow::create() {
    CurvatureFlow f;
    auto step = loadComputeProgram("filter_curvature_flow.comp");
    if (!step) return step.error();
    f.step_ = std::move(*step);
    f.passes_ = PaddedPasses::create();
    auto segments = FluidSegments::create();
    if (!segments) return segments.error();
    f.segments_ = std::move(*segments);
    return f;
}

void CurvatureFlow::run(const FrameParams& frame, const GpuImage& in, GpuImage& out) {
    const int W = in.width, H = in.height;
    out.resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    if (frame.filterIterations <= 0) {  // as the CPU: the input unchanged
        out.buffer.copyFrom(in.buffer, in.bytes());
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    // Pixels outside the fluid segments keep their input value (+inf).
    out.buffer.copyFrom(in.buffer, in.bytes());
    segments_.build(in);
    // A +inf frame one pixel wide with the image inside.
    passes_.load(in, 1, 0x7f800000u, out);
    glUseProgram(step_.id());
    glUniform2i(0, W, H);
    segments_.bindList(1);
    passes_.run(frame.filterIterations, segments_, [](int, bool last) { glUniform1i(1, last ? 1 : 0); });
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glActiveTexture(GL_TEXTURE0);
    glUseProgram(0);
}

}  // namespace meniscus::gl
