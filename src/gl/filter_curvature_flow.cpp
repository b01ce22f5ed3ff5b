// GL curvature flow, SPEC §3.5 (van der Laan, Green & Sainz, I3D 2009): the
// CPU's double-buffered Jacobi iteration on padded buffers, one dispatch per
// iteration (shaders/filter_curvature_flow.comp).
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
    f.texA_ = makeTexture();
    f.texB_ = makeTexture();
    f.outTex_ = makeTexture();
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
    // +inf frames with the image inside: driver fills and row copies (memset
    // and memcpy on llvmpipe).
    const int PW = W + 2;
    const GLsizeiptr paddedBytes = GLsizeiptr(PW) * GLsizeiptr(H + 2) * 4;
    a_.reserve(paddedBytes);
    b_.reserve(paddedBytes);
    a_.fill(paddedBytes, 0x7f800000u);
    b_.fill(paddedBytes, 0x7f800000u);
    for (int y = 0; y < H; ++y) {
        const GLintptr from = GLintptr(y) * W * 4, to = (GLintptr(y + 1) * PW + 1) * 4;
        a_.copyRange(in.buffer, from, to, GLsizeiptr(W) * 4);
        b_.copyRange(in.buffer, from, to, GLsizeiptr(W) * 4);
    }
    attachBufferTexture(texA_, GL_R32F, a_, paddedBytes);
    attachBufferTexture(texB_, GL_R32F, b_, paddedBytes);
    attachBufferTexture(outTex_, GL_R32F, out.buffer, out.bytes());
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);

    glUseProgram(step_.id());
    glUniform2i(0, W, H);
    segments_.bindList(1);
    glActiveTexture(GL_TEXTURE0);
    const Texture* src = &texA_;
    const Texture* dst = &texB_;
    for (int it = 0; it < frame.filterIterations; ++it) {
        const bool last = it + 1 == frame.filterIterations;
        glUniform1i(1, last ? 1 : 0);
        glBindTexture(GL_TEXTURE_BUFFER, src->id());
        glBindImageTexture(0, last ? outTex_.id() : dst->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        segments_.dispatch();
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        std::swap(src, dst);
    }
    glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    for (GLenum unit : {GL_TEXTURE1, GL_TEXTURE0}) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
    glUseProgram(0);
}

}  // namespace meniscus::gl
