// See upsample.h.
#include "gl/upsample.h"
#include "gl/gl_backend.h"

#include <utility>

#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kUpsampleGroup = 64;           // local_size_x of the three shaders
constexpr GLuint kUpsamplePerInvocation = 4;    // pixels per invocation (llvmpipe pays per work group)

void bindTexture(GLuint unit, const Texture& tex, GLenum format, const Buffer& buf, GLsizeiptr bytes) {
    glActiveTexture(GL_TEXTURE0 + unit);
    attachBufferTexture(tex, format, buf, bytes);
    glBindTexture(GL_TEXTURE_BUFFER, tex.id());
}

void unbindTextures(GLuint count) {
    for (GLuint u = count; u-- > 0;) {
        glActiveTexture(GL_TEXTURE0 + u);
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
}
}  // namespace

Result<Upsampling> Upsampling::create() {
    Upsampling u;
    auto reduce = loadComputeProgram("upsample_reduce.comp");
    if (!reduce) return reduce.error();
    auto upsample = loadComputeProgram("upsample.comp");
    if (!upsample) return upsample.error();
    auto edges = loadComputeProgram("upsample_edges.comp");
    if (!edges) return edges.error();
    u.reduce_ = std::move(*reduce);
    u.upsample_ = std::move(*upsample);
    u.edges_ = std::move(*edges);
    for (Texture& t : u.tex_) t = makeTexture();
    const float zeros[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    u.dummy_.upload(zeros, sizeof zeros);
    return u;
}

void Upsampling::reduceSceneDepth(const GpuImage& full, int lw, int lh, int d, GpuImage& low) {
    low.resize(lw, lh, 1);
    if (lw <= 0 || lh <= 0) return;
    if (full.width <= 0 || full.height <= 0 || full.channels != 1) {  // as the CPU: +inf
        low.buffer.fill(low.bytes(), 0x7f800000u);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    glUseProgram(reduce_.id());
    glUniform2i(0, full.width, full.height);
    glUniform2i(1, lw, lh);
    glUniform1i(2, d);
    bindTexture(0, tex_[0], GL_R32F, full.buffer, full.bytes());
    low.bind(0);
    glDispatchCompute(gridGroups(GLuint(lw) * GLuint(lh), kUpsampleGroup * kUpsamplePerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    unbindTextures(1);
    glUseProgram(0);
}

void Upsampling::upsample(const GpuImage& lowDepth, const GpuImage& lowNormal, const GpuImage& lowThickness,
                          const GpuImage* lowNoise, const GpuImage* sceneDepth, int W, int H, int d, float jumpM,
                          GpuImage& depth, GpuImage& normal, GpuImage& thickness, GpuImage* noise,
                          GpuImage& coverage) {
    depth.resize(W, H, 1);
    normal.resize(W, H, 3);
    thickness.resize(W, H, 1);
    coverage.resize(W, H, 1);
    if (noise) noise->resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    const int lw = lowDepth.width, lh = lowDepth.height;
    if (lw <= 0 || lh <= 0 || lowDepth.channels != 1) {  // no low surface: no fluid
        depth.buffer.fill(depth.bytes(), 0x7f800000u);
        for (GpuImage* img : {&normal, &thickness, &coverage, noise})
            if (img) img->buffer.fill(img->bytes(), 0u);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    const bool hasNormal = lowNormal.sized(lw, lh, 3), hasThickness = lowThickness.sized(lw, lh, 1);
    const bool hasNoise = noise && lowNoise && lowNoise->sized(lw, lh, 1);
    const bool hides = sceneDepth && sceneDepth->sized(W, H, 1);
    glUseProgram(upsample_.id());
    glUniform2i(0, W, H);
    glUniform2i(1, lw, lh);
    glUniform1i(2, d);
    glUniform1f(3, jumpM);
    glUniform1i(4, (hasNormal ? 1 : 0) | (hasThickness ? 2 : 0) | (hasNoise ? 4 : 0) | (hides ? 8 : 0));
    const GpuImage* inputs[5] = {&lowDepth, hasNormal ? &lowNormal : nullptr, hasThickness ? &lowThickness : nullptr,
                                 hasNoise ? lowNoise : nullptr, hides ? sceneDepth : nullptr};
    for (GLuint i = 0; i < 5; ++i) {
        if (inputs[i]) bindTexture(i, tex_[i], GL_R32F, inputs[i]->buffer, inputs[i]->bytes());
        else bindTexture(i, tex_[i], GL_R32F, dummy_, 16);
    }
    depth.bind(0);
    normal.bind(1);
    thickness.bind(2);
    if (hasNoise) noise->bind(3);
    else glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 3, dummy_.id(), 0, 16);
    coverage.bind(4);
    glDispatchCompute(gridGroups(GLuint(W) * GLuint(H), kUpsampleGroup * kUpsamplePerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    unbindTextures(5);
    glUseProgram(0);
    // A noise output without a low noise: zero, as the CPU leaves it.
    if (noise && !hasNoise) {
        noise->buffer.fill(noise->bytes(), 0u);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
}

void Upsampling::blendEdges(const GpuImage& depth, const GpuImage& coverage, const GpuImage& behind,
                            GpuImage& color, GpuImage* emission, GpuImage* transmit) {
    const int W = color.width, H = color.height;
    if (W <= 0 || H <= 0 || color.channels != 4 || !depth.sized(W, H, 1) || !coverage.sized(W, H, 1) ||
        !behind.sized(W, H, 4))
        return;
    const bool split = emission && transmit && emission->sized(W, H, 4) && transmit->sized(W, H, 4);
    glUseProgram(edges_.id());
    glUniform2i(0, W, H);
    glUniform1i(1, split ? 1 : 0);
    if (split) {
        emission->bind(1);
        transmit->bind(2);
    } else {  // never written (uSplit is 0)
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, dummy_.id(), 0, 16);
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 2, dummy_.id(), 0, 16);
    }
    bindTexture(0, tex_[0], GL_R32F, depth.buffer, depth.bytes());
    bindTexture(1, tex_[1], GL_R32F, coverage.buffer, coverage.bytes());
    bindTexture(2, tex_[2], GL_RGBA32F, behind.buffer, behind.bytes());
    color.bind(0);
    glDispatchCompute(gridGroups(GLuint(W) * GLuint(H), kUpsampleGroup * kUpsamplePerInvocation), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    unbindTextures(3);
    glUseProgram(0);
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// The scene depth reduced to the current (low) camera's size.
void runReduceSceneDepth(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(Slot::LowSceneDepth);
    const FrameSettings& s = g.frame();
    g.pass<Upsampling>().reduceSceneDepth(g.img(at.sceneDepth), s.camera.width, s.camera.height, s.fluidDivisor,
                                          g.img(Slot::LowSceneDepth));
}

// The low surface (the Low* slots) upsampled into the surface's full-size images.
void runUpsample(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    for (Slot out : {at.depth, at.normal, at.thickness, at.noise, at.coverage}) g.forget(out);
    const FrameSettings& s = g.frame();
    const bool noise = s.noise.enabled;
    g.pass<Upsampling>().upsample(g.img(Slot::LowDepth), g.img(Slot::LowNormal), g.img(Slot::LowThickness),
                                  noise ? &g.img(Slot::LowNoise) : nullptr, &g.img(at.sceneDepth), s.camera.width,
                                  s.camera.height, s.fluidDivisor, s.upsampleJumpM, g.img(at.depth),
                                  g.img(at.normal), g.img(at.thickness), noise ? &g.img(at.noise) : nullptr,
                                  g.img(at.coverage));
}

void runFluidEdges(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    const bool split = at.emission != Slot::None;
    g.pass<Upsampling>().blendEdges(g.img(at.depth), g.img(at.coverage), g.img(at.sceneColor), g.img(at.color),
                                    split ? &g.img(at.emission) : nullptr, split ? &g.img(at.transmit) : nullptr);
}

}  // namespace

extern const StageDriver kReduceSceneDepthStage = {glPrepare<Upsampling>, glRun<runReduceSceneDepth>};
extern const StageDriver kUpsampleStage = {glPrepare<Upsampling>, glRun<runUpsample>};
extern const StageDriver kFluidEdgesStage = {glPrepare<Upsampling>, glRun<runFluidEdges>};

}  // namespace meniscus::gl
