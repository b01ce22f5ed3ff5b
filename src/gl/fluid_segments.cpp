// See fluid_segments.h.
#include "gl/fluid_segments.h"

#include <algorithm>
#include <cstdlib>
#include <string>
#include <utility>

#include "gl/buffer_fill.h"
#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kFluidSegmentsGroup = 64;                 // fluid_segments.comp's local_size_x
constexpr GLuint kSegmentsPerInvocation = 4;  // fluid_segments.comp's kPerInvocation
constexpr GLint kRoundsLocation = 15;         // fluid_segments.glsl's uSegmentRounds

}  // namespace

Result<FluidSegments> FluidSegments::create() {
    FluidSegments s;
    auto program = loadComputeProgram("fluid_segments.comp");
    if (!program) return program.error();
    s.program_ = std::move(*program);
    s.listTex_ = makeTexture();
    s.depthTex_ = makeTexture();
    const GLubyte* renderer = glGetString(GL_RENDERER);
    s.cap_ = isSoftwareRenderer(renderer ? reinterpret_cast<const char*>(renderer) : "") ? kMaxRounds : kHardwareRounds;
    if (const char* v = std::getenv("MENISCUS_GL_SEGMENT_ROUNDS")) s.cap_ = std::clamp(std::atoi(v), 1, kMaxRounds);
    return s;
}

void FluidSegments::build(const GpuImage& depth, int rounds) {
    rounds_ = std::clamp(std::min(rounds, cap_), 1, kMaxRounds);
    const int W = depth.width, H = depth.height;
    const GLuint segments = W > 0 && H > 0 ? ceilDiv(GLuint(W), 8) * GLuint(H) : 0;
    const GLsizeiptr listBytes = GLsizeiptr(1 + segments) * 4;
    list_.reserve(listBytes);
    args_.reserve(3 * 4);
    zMin_.reserve(4);
    list_.fill(4, 0u);  // count = 0
    zMin_.fill(4, 0x7f800000u);
    attachBufferTexture(listTex_, GL_R32I, list_, listBytes);
    attachBufferTexture(depthTex_, GL_R32F, depth.buffer, std::max<GLsizeiptr>(depth.bytes(), 4));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);

    glUseProgram(program_.id());
    glUniform2i(0, W, H);
    glUniform1i(3, GLint(8 * rounds_));  // segments per work group of 64 invocations
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, depthTex_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, zMin_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, list_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, args_.id());
    if (segments > 0) {
        glUniform1i(1, 0);
        glDispatchCompute(gridGroups(segments, kFluidSegmentsGroup * kSegmentsPerInvocation), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    glUniform1i(1, 1);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glUseProgram(0);
}

void FluidSegments::bindList(GLuint unit) const {
    glActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_BUFFER, listTex_.id());
    glActiveTexture(GL_TEXTURE0);
}

void FluidSegments::dispatch() const {
    glUniform1i(kRoundsLocation, rounds_);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, args_.id());
    glDispatchComputeIndirect(0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
}

}  // namespace meniscus::gl
