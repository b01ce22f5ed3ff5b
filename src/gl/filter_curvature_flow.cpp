// GL curvature flow, SPEC §3.5 (van der Laan, Green & Sainz, I3D 2009): the
// CPU's double-buffered Jacobi iteration on padded buffers, one dispatch per
// iteration (shaders/filter_curvature_flow.comp), bracketed by a pad and an
// unpad pass (shaders/filter_curvature_flow_pad.comp).
// llvmpipe notes (measured at 1280x720): SSBO loads and stores run one SIMD lane
// at a time, texel fetches and image stores are vectorised, so the step reads
// and writes the ping-pong buffers through R32F buffer textures over the same
// buffer objects; each work group also costs a few microseconds, so the step
// visits only the 64 x 8 tiles that hold fluid (an indirect dispatch over a
// tile list built once per run: the fluid set never changes).
#include "gl/filter_curvature_flow.h"

#include <algorithm>
#include <utility>

#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kGroup = 64;              // local_size_x of both shaders = tile width
constexpr GLuint kCopyPerInvocation = 16;  // filter_curvature_flow_pad.comp's kPerInvocation
constexpr GLuint kStepRows = 8;            // filter_curvature_flow.comp's kRows = tile height

}  // namespace

Result<CurvatureFlow> CurvatureFlow::create() {
    CurvatureFlow f;
    auto pad = loadComputeProgram("filter_curvature_flow_pad.comp");
    if (!pad) return pad.error();
    auto step = loadComputeProgram("filter_curvature_flow.comp");
    if (!step) return step.error();
    f.pad_ = std::move(*pad);
    f.step_ = std::move(*step);
    f.texA_ = makeTexture();
    f.texB_ = makeTexture();
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
    const GLuint padded = GLuint(W + 2) * GLuint(H + 2);
    const GLuint tilesX = ceilDiv(GLuint(W), kGroup), tiles = tilesX * ceilDiv(GLuint(H), kStepRows);
    a_.reserve(GLsizeiptr(padded) * 4);
    b_.reserve(GLsizeiptr(padded) * 4);
    tileFlags_.reserve(GLsizeiptr(tiles) * 4);
    tileList_.reserve(GLsizeiptr(tiles) * 4);
    indirect_.reserve(3 * 4);
    a_.fill(GLsizeiptr(padded) * 4, 0x7f800000u);  // +inf; the pad pass copies the fluid in
    b_.fill(GLsizeiptr(padded) * 4, 0x7f800000u);
    tileFlags_.fill(GLsizeiptr(tiles) * 4, 0u);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    const GLuint args[3] = {0u, 1u, 1u};
    indirect_.upload(args, sizeof args);

    // Pad (and flag the tiles with fluid), then list those tiles.
    glUseProgram(pad_.id());
    glUniform2i(0, W, H);
    glUniform3i(2, GLint(kGroup), GLint(kStepRows), GLint(tilesX));
    in.bind(1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, a_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, tileFlags_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, tileList_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, indirect_.id());
    glUniform1i(1, 0);
    glDispatchCompute(ceilDiv(GLuint(W) * GLuint(H), kGroup * kCopyPerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUniform1i(1, 1);
    glDispatchCompute(ceilDiv(tiles, kGroup * kCopyPerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                    GL_COMMAND_BARRIER_BIT);

    // (Re)attach the buffer textures: the buffers may have been reallocated.
    attachBufferTexture(texA_, GL_R32F, a_, GLsizeiptr(padded) * 4);
    attachBufferTexture(texB_, GL_R32F, b_, GLsizeiptr(padded) * 4);

    glUseProgram(step_.id());
    glUniform2i(0, W, H);
    glUniform1i(1, GLint(tilesX));
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, indirect_.id());
    glActiveTexture(GL_TEXTURE0);
    const Texture* src = &texA_;
    const Texture* dst = &texB_;
    for (int it = 0; it < frame.filterIterations; ++it) {
        glBindTexture(GL_TEXTURE_BUFFER, src->id());
        glBindImageTexture(0, dst->id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
        glDispatchComputeIndirect(0);
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                        GL_SHADER_STORAGE_BARRIER_BIT);
        std::swap(src, dst);
    }
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);

    // The last result is in `src`'s buffer.
    glUseProgram(pad_.id());
    glUniform1i(1, 2);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, src == &texA_ ? a_.id() : b_.id());
    out.bind(4);
    glDispatchCompute(ceilDiv(GLuint(W) * GLuint(H), kGroup * kCopyPerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

}  // namespace meniscus::gl
