// See composite_fluids.h.
#include "gl/composite_fluids.h"
#include "gl/gl_backend.h"

#include <algorithm>
#include <string>
#include <utility>

#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kCompositeFluidsGroup = 64;         // local_size_x of the shader
constexpr GLuint kCompositeFluidsPerInvocation = 4;  // pixels per invocation (llvmpipe pays per work group)
}  // namespace

Result<FluidCompositor> FluidCompositor::create() {
    GLint units = 0;
    glGetIntegerv(GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, &units);
    if (units < kUnits)
        return makeError("", "the GL driver gives a compute shader " + std::to_string(units) +
                                 " texture units; compositing " + std::to_string(shared::kMaxFluids) +
                                 " fluids needs " + std::to_string(kUnits));
    FluidCompositor c;
    auto p = loadComputeProgram("composite_fluids.comp");
    if (!p) return p.error();
    c.program_ = std::move(*p);
    for (Texture& t : c.tex_) t = makeTexture();
    for (Texture& t : c.outTex_) t = makeTexture();
    const float zeros[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    c.dummy_.upload(zeros, sizeof zeros);
    return c;
}

void FluidCompositor::run(std::span<const FluidLayerGpu> layers, const GpuImage& sceneColor,
                          const GpuImage& sceneDepth, GpuImage& color, GpuImage& depth, GpuImage& normal,
                          GpuImage& thickness, GpuImage& fluid) {
    const int n = std::min(int(layers.size()), shared::kMaxFluids);
    if (n == 0) return;
    const int W = layers[0].depth->width, H = layers[0].depth->height;
    color.resize(W, H, 4);
    depth.resize(W, H, 1);
    normal.resize(W, H, 3);
    thickness.resize(W, H, 1);
    fluid.resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    auto bind = [&](int unit, const GpuImage* img, GLenum format) {
        glActiveTexture(GL_TEXTURE0 + GLenum(unit));
        if (img) attachBufferTexture(tex_[unit], format, img->buffer, img->bytes());
        else attachBufferTexture(tex_[unit], format, dummy_, 16);
        glBindTexture(GL_TEXTURE_BUFFER, tex_[unit].id());
    };
    const bool hasColor = sceneColor.sized(W, H, 4), hasDepth = sceneDepth.sized(W, H, 1);
    bind(0, hasColor ? &sceneColor : nullptr, GL_RGBA32F);
    bind(1, hasDepth ? &sceneDepth : nullptr, GL_R32F);
    int fluids[shared::kMaxFluids] = {};
    for (int k = 0; k < shared::kMaxFluids; ++k) {
        const FluidLayerGpu* l = k < n ? &layers[std::size_t(k)] : nullptr;
        if (l) fluids[k] = l->fluid;
        const int m = shared::kMaxFluids;
        bind(2 + k, l ? l->depth : nullptr, GL_R32F);
        bind(2 + m + k, l ? l->normal : nullptr, GL_R32F);
        bind(2 + 2 * m + k, l ? l->thickness : nullptr, GL_R32F);
        bind(2 + 3 * m + k, l ? l->color : nullptr, GL_RGBA32F);
        bind(2 + 4 * m + k, l ? l->emission : nullptr, GL_RGBA32F);
        bind(2 + 5 * m + k, l ? l->transmit : nullptr, GL_RGBA32F);
    }
    glUseProgram(program_.id());
    glUniform2i(0, W, H);
    glUniform1i(1, n);
    static_assert(shared::kMaxFluids == 4, "uFluid is an ivec4");
    glUniform4i(2, fluids[0], fluids[1], fluids[2], fluids[3]);
    glUniform2i(3, hasColor ? 1 : 0, hasDepth ? 1 : 0);
    const std::pair<GpuImage*, GLenum> outputs[kOutputs] = {
        {&color, GL_RGBA32F}, {&depth, GL_R32F}, {&normal, GL_R32F}, {&thickness, GL_R32F}, {&fluid, GL_R32F}};
    for (int o = 0; o < kOutputs; ++o) {
        attachBufferTexture(outTex_[o], outputs[o].second, outputs[o].first->buffer, outputs[o].first->bytes());
        glBindImageTexture(GLuint(o), outTex_[o].id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, outputs[o].second);
    }
    glDispatchCompute(gridGroups(GLuint(W) * GLuint(H), kCompositeFluidsGroup * kCompositeFluidsPerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_BUFFER_UPDATE_BARRIER_BIT);
    for (int o = 0; o < kOutputs; ++o) glBindImageTexture(GLuint(o), 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    for (int u = kUnits; u-- > 0;) {
        glActiveTexture(GL_TEXTURE0 + GLenum(u));
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
    glUseProgram(0);
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// Layers 0 .. io.fluids.size() - 1 composited front to back over the scene.
void runCompositeFluids(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    for (Slot out : {at.color, at.depth, at.normal, at.thickness, at.fluidId}) g.forget(out);
    std::vector<FluidLayerGpu> layers;
    for (std::size_t i = 0; i < io.fluids.size(); ++i) {
        const int l = int(i);
        layers.push_back({io.fluids[i], &g.img(layerSlot(l, LayerImage::Depth)),
                          &g.img(layerSlot(l, LayerImage::Normal)), &g.img(layerSlot(l, LayerImage::Thickness)),
                          &g.img(layerSlot(l, LayerImage::Color)), &g.img(layerSlot(l, LayerImage::Emission)),
                          &g.img(layerSlot(l, LayerImage::Transmit))});
    }
    g.pass<FluidCompositor>().run(layers, g.img(at.sceneColor), g.img(at.sceneDepth), g.img(at.color),
                                  g.img(at.depth), g.img(at.normal), g.img(at.thickness), g.img(at.fluidId));
}

}  // namespace

extern const StageDriver kCompositeFluidsStage = {glPrepare<FluidCompositor>, glRun<runCompositeFluids>};

}  // namespace meniscus::gl
