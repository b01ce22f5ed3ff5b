// The embedding's scene layer (see host_layers.h): one invocation per pixel
// of shaders/host_layers.comp reads the host's textures where they are, so
// nothing of the host's frame crosses to the CPU.
#include "gl/host_layers.h"

#include "gl/shaders.h"
#include "shared/srgb.h"

namespace meniscus::gl {

namespace {
constexpr int kHostLayersGroup = 8;  // local_size_x and _y of host_layers.comp
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

}  // namespace meniscus::gl
