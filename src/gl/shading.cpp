// GL shading and compositing, docs/pipeline.md#shading: refraction,
// Beer-Lambert absorption, environment reflection, Schlick Fresnel and
// Blinn-Phong specular after van der Laan, Green & Sainz 2009 (US 8,947,430,
// eqs. 18-20) and Cords & Staadt 2008 ("Instant Liquids" §3), composited over
// the scene layer by shaders/shade.comp, operation for operation as
// src/cpu/shading.cpp.
#include "gl/shading.h"
#include "gl/gl_backend.h"

#include <utility>

#include "gl/shaders.h"
#include "shared/shading.h"
#include "shared/sky.h"

namespace meniscus::gl {

Result<Shading> Shading::create() {
    Shading s;
    auto p = loadComputeProgram("shade.comp");
    if (!p) return p.error();
    s.program_ = std::move(*p);
    s.dummy_.reserve(16);
    for (Texture& t : s.inTex_) t = makeTexture();
    s.noiseTex_ = makeTexture();
    s.whiteTex_ = makeTexture();
    s.outTex_ = makeTexture();
    s.emissionTex_ = makeTexture();
    s.transmitTex_ = makeTexture();
    auto segments = FluidSegments::create();
    if (!segments) return segments.error();
    s.segments_ = std::move(*segments);
    return s;
}

void Shading::run(const FrameParams& frame, const GpuImage& sceneColor, const GpuImage& sceneDepth,
                  const GpuImage& depth, const GpuImage& normals, const GpuImage& thickness, GpuImage& color,
                  const GpuImage* noise, const NoiseParams* noiseParams, const GpuImage* whitening,
                  const WhiteningParams* whiteningParams, GpuImage* emission, GpuImage* transmit,
                  const EnvironmentGpu* environment) {
    const int W = frame.size.x, H = frame.size.y;
    color.resize(W, H, 4);
    const bool layer = emission && transmit;
    if (layer) {
        emission->resize(W, H, 4);
        transmit->resize(W, H, 4);
        emission->buffer.fill(emission->bytes(), 0u);
        transmit->buffer.fill(transmit->bytes(), 0u);
    }
    if (W <= 0 || H <= 0) return;
    const bool hasScene = sceneColor.sized(W, H, 4) && sceneDepth.sized(W, H, 1);
    const bool hasNormals = normals.sized(W, H, 3);
    const bool hasThickness = thickness.sized(W, H, 1);
    const bool foam = noise && noiseParams && noise->sized(W, H, 1);
    const bool white = whitening && whiteningParams && whitening->sized(W, H, 1);
    // As the CPU, from the same host functions: the n.h below which the
    // highlight is invisible, and the sky's sun.
    const float nhMin = shared::highlightMinNh(frame.specular, frame.shininess);
    const glm::vec3 sun = shared::sunDirection(glm::vec3(frame.lightDirWorld));

    // Every pixel starts as the scene colour (transparent black without a
    // scene), by the driver (a memcpy / memset on llvmpipe); the shader then
    // writes only the fluid pixels.
    if (hasScene) color.buffer.copyFrom(sceneColor.buffer, color.bytes());
    else color.buffer.fill(color.bytes(), 0u);
    if (!depth.sized(W, H, 1)) {  // no usable fluid depth: the scene alone
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    segments_.build(depth);  // the 8-pixel row segments with fluid
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

    glUseProgram(program_.id());
    glUniform3i(1, hasScene ? 1 : 0, hasNormals ? 1 : 0, hasThickness ? 1 : 0);
    glUniform1f(2, nhMin);
    glUniform3f(3, sun.x, sun.y, sun.z);
    glUniform1i(4, foam ? 1 : 0);
    if (foam) {
        glUniform1f(5, noiseParams->foamThreshold);
        glUniform1f(6, noiseParams->foamGain);
        glUniform3f(7, noiseParams->foamColor.x, noiseParams->foamColor.y, noiseParams->foamColor.z);
    }
    glUniform1i(11, layer ? 1 : 0);
    if (environment) environment->bind(12, 16);
    else bindNoEnvironment(12, 16);
    glUniform1i(8, white ? 1 : 0);
    if (white) {
        glUniform1f(9, whiteningParams->strength);
        glUniform3f(10, whiteningParams->color.x, whiteningParams->color.y, whiteningParams->color.z);
    }
    // Texture unit i reads input i; an absent one reads a tiny dummy (never used).
    const std::pair<const GpuImage*, GLenum> inputs[kInputs] = {
        {hasScene ? &sceneColor : nullptr, GL_RGBA32F}, {hasScene ? &sceneDepth : nullptr, GL_R32F},
        {&depth, GL_R32F}, {hasNormals ? &normals : nullptr, GL_R32F}, {hasThickness ? &thickness : nullptr, GL_R32F}};
    for (int i = 0; i < kInputs; ++i) {
        const auto [img, format] = inputs[i];
        if (img) attachBufferTexture(inTex_[i], format, img->buffer, img->bytes());
        else attachBufferTexture(inTex_[i], format, dummy_, 16);
        glActiveTexture(GL_TEXTURE0 + GLenum(i));
        glBindTexture(GL_TEXTURE_BUFFER, inTex_[i].id());
    }
    if (foam) attachBufferTexture(noiseTex_, GL_R32F, noise->buffer, noise->bytes());
    else attachBufferTexture(noiseTex_, GL_R32F, dummy_, 16);
    glActiveTexture(GL_TEXTURE0 + GLenum(kNoiseUnit));
    glBindTexture(GL_TEXTURE_BUFFER, noiseTex_.id());
    if (white) attachBufferTexture(whiteTex_, GL_R32F, whitening->buffer, whitening->bytes());
    else attachBufferTexture(whiteTex_, GL_R32F, dummy_, 16);
    glActiveTexture(GL_TEXTURE0 + GLenum(kWhiteUnit));
    glBindTexture(GL_TEXTURE_BUFFER, whiteTex_.id());
    attachBufferTexture(outTex_, GL_RGBA32F, color.buffer, color.bytes());
    glBindImageTexture(0, outTex_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    // Units 1 and 2 always hold a valid image: E and T, else the colour again
    // (never written: uLayer is 0).
    attachBufferTexture(emissionTex_, GL_RGBA32F, layer ? emission->buffer : color.buffer,
                        layer ? emission->bytes() : color.bytes());
    attachBufferTexture(transmitTex_, GL_RGBA32F, layer ? transmit->buffer : color.buffer,
                        layer ? transmit->bytes() : color.bytes());
    glBindImageTexture(1, emissionTex_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(2, transmitTex_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    segments_.bindList(kInputs);
    segments_.dispatch();
    for (GLuint unit : {0u, 1u, 2u}) glBindImageTexture(unit, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    for (int i = kWhiteUnit; i >= 0; --i) {
        glActiveTexture(GL_TEXTURE0 + GLenum(i));
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// Foam only with the noise on (its slot then holds this frame's N), white
// water only with the whitening on (likewise its map).
void runShade(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.color);
    const FrameSettings& s = g.frame();
    const bool split = at.emission != Slot::None;
    g.pass<Shading>().run(g.params(), g.img(at.sceneColor), g.img(at.sceneDepth), g.img(at.depth), g.img(at.normal),
                          g.img(at.thickness), g.img(at.color), s.noise.enabled ? &g.img(at.noise) : nullptr,
                          &s.noise, s.whitening.enabled ? &g.img(at.whitening) : nullptr, &s.whitening,
                          split ? &g.img(at.emission) : nullptr, split ? &g.img(at.transmit) : nullptr,
                          &g.environment());
}

}  // namespace

extern const StageDriver kShadeStage = {glPrepare<Shading>, glRun<runShade>};

}  // namespace meniscus::gl
