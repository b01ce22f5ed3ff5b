// The embedding's scene layer (see host_layers.h): one invocation per pixel
// of shaders/host_layers.comp reads the host's textures where they are, so
// nothing of the host's frame crosses to the CPU. And the host's particles:
// shaders/host_particles.comp copies them out of the host's buffer.
#include "gl/host_layers.h"

#include <cstdint>
#include <string>

#include "gl/dispatch.h"
#include "gl/shaders.h"
#include "shared/srgb.h"

namespace meniscus::gl {

namespace {
constexpr int kHostLayersGroup = 8;  // local_size_x and _y of host_layers.comp
constexpr GLuint kHostParticlesGroup = 256;  // local_size_x of host_particles.comp
constexpr GLuint kHostParticlesPerInvocation = 4;  // grid-stride: llvmpipe pays per work group
}  // namespace

Result<HostLayerImport> HostLayerImport::create() {
    HostLayerImport h;
    auto p = loadComputeProgram("host_layers.comp");
    if (!p) return p.error();
    h.program_ = std::move(*p);
    const auto& table = shared::srgbDecodeTable();
    h.decode_.upload(table.data(), table.size() * sizeof(float));
    h.sampler_ = makeSampler();
    glSamplerParameteri(h.sampler_.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glSamplerParameteri(h.sampler_.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glSamplerParameteri(h.sampler_.id(), GL_TEXTURE_COMPARE_MODE, GL_NONE);
    return h;
}

void HostLayerImport::run(const HostLayers& host, const Camera& camera, GpuImage& color, GpuImage& depth) {
    const int W = host.width, H = host.height;
    color.resize(W, H, 4);
    depth.resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    glUseProgram(program_.id());
    glUniform3i(0, W, H, host.colorIsSrgb ? 1 : 0);
    glUniform2f(1, camera.nearM, camera.farM);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, host.colorTexture);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, host.depthTexture);
    glActiveTexture(GL_TEXTURE0);
    glBindSampler(0, sampler_.id());
    glBindSampler(1, sampler_.id());
    color.bind(1);
    depth.bind(2);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, decode_.id());
    glDispatchCompute(GLuint((W + kHostLayersGroup - 1) / kHostLayersGroup),
                      GLuint((H + kHostLayersGroup - 1) / kHostLayersGroup), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindSampler(0, 0);
    glBindSampler(1, 0);
    glUseProgram(0);
}

Result<HostParticleGather> HostParticleGather::create() {
    HostParticleGather g;
    auto p = loadComputeProgram("host_particles.comp");
    if (!p) return p.error();
    g.program_ = std::move(*p);
    return g;
}

Status HostParticleGather::check(const HostParticleBuffer& p) {
    const char* what = "the host's particle buffer";
    if (p.count == 0) return okStatus();
    if (p.buffer == 0 || !glIsBuffer(p.buffer))
        return makeError(what, "buffer " + std::to_string(p.buffer) + " is not a GL buffer of the current context");
    if (p.offsetBytes % 4 != 0 || p.strideBytes % 4 != 0)
        return makeError(what, "offset " + std::to_string(p.offsetBytes) + " and stride " +
                                   std::to_string(p.strideBytes) + " bytes must be multiples of 4");
    if (p.strideBytes < 12)
        return makeError(what, "stride " + std::to_string(p.strideBytes) +
                                   " bytes: a position is three floats, 12 bytes at least");
    GLint64 size = 0;
    glBindBuffer(GL_COPY_READ_BUFFER, p.buffer);
    glGetBufferParameteri64v(GL_COPY_READ_BUFFER, GL_BUFFER_SIZE, &size);
    glBindBuffer(GL_COPY_READ_BUFFER, 0);
    // The last position's end, without overflow: (count - 1) * stride + 12 past the offset.
    const std::uint64_t have = std::uint64_t(size > 0 ? size : 0);
    const std::uint64_t stride = p.strideBytes, count = p.count;
    const bool fits = p.offsetBytes <= have && (have - p.offsetBytes) >= 12 &&
                      (count - 1) <= (have - p.offsetBytes - 12) / stride;
    if (!fits)
        return makeError(what, std::to_string(p.count) + " positions of stride " + std::to_string(p.strideBytes) +
                                   " bytes from byte " + std::to_string(p.offsetBytes) + " do not fit in its " +
                                   std::to_string(have) + " bytes");
    if (have / 4 > 0xffffffffull || count > 0xffffffffull / 3)
        return makeError(what, std::to_string(have) + " bytes or " + std::to_string(p.count) +
                                   " particles: more than 32-bit indices reach");
    return okStatus();
}

void HostParticleGather::run(const HostParticleBuffer& p, Buffer& target) {
    const GLuint n = GLuint(p.count);
    target.reserve(GLsizeiptr(std::max<GLuint>(n, 1)) * 3 * GLsizeiptr(sizeof(float)));
    if (n == 0) return;
    glUseProgram(program_.id());
    glUniform1ui(0, n);
    glUniform1ui(1, GLuint(p.offsetBytes / 4));
    glUniform1ui(2, GLuint(p.strideBytes / 4));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, p.buffer);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, target.id());
    // The host's writes to its buffer (by GL calls or its own shaders) seen.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glDispatchCompute(gridGroups(n, kHostParticlesGroup * kHostParticlesPerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
    glUseProgram(0);
}

}  // namespace meniscus::gl
