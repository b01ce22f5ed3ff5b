// GL hole filling, docs/pipeline.md#hole-filling: per pass
// shaders/hole_fill_sweep.comp (each row's and column's steps to the nearest
// covered pixels), then shaders/hole_fill.comp, one invocation per pixel,
// operation for operation as src/cpu/hole_fill.cpp (the rule and the
// formulas are src/shared/hole_fill.h), so both fill the same pixels with the
// same bits. Reads the splat through buffer textures and writes whole new
// images, which then take the slots' places (no copy back).
#include "gl/hole_fill.h"
#include "gl/gl_backend.h"

#include <utility>

#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr int kHoleFillGroup = 64;  // local_size_x of hole_fill.comp: columns per work group; a row per group row
}  // namespace

Result<HoleFill> HoleFill::create() {
    HoleFill h;
    auto p = loadComputeProgram("hole_fill.comp");
    if (!p) return p.error();
    h.program_ = std::move(*p);
    auto sw = loadComputeProgram("hole_fill_sweep.comp");
    if (!sw) return sw.error();
    h.sweep_ = std::move(*sw);
    h.depthTex_ = makeTexture();
    h.thicknessTex_ = makeTexture();
    h.sceneTex_ = makeTexture();
    return h;
}

void HoleFill::run(const FrameParams& frame, const HoleFillParams& params, const GpuImage* sceneDepth,
                   GpuImage& depth, GpuImage& thickness) {
    const int W = frame.size.x, H = frame.size.y;
    if (!params.enabled || W <= 0 || H <= 0 || params.reachPx < 1 || !depth.sized(W, H, 1)) return;
    const bool hasT = thickness.sized(W, H, 1);
    const bool hasScene = sceneDepth && sceneDepth->sized(W, H, 1);
    depthOut_.resize(W, H, 1);
    if (hasT) thicknessOut_.resize(W, H, 1);
    rowSteps_.resize(W, H, 1);
    columnSteps_.resize(W, H, 1);
    rowSteps_.bind(5);
    columnSteps_.bind(6);
    // The rows' and the columns' steps of the depth the pass reads (texture unit 0).
    const auto sweep = [&] {
        glUseProgram(sweep_.id());
        glUniform1i(0, 0);
        glDispatchCompute(GLuint((H + kHoleFillGroup - 1) / kHoleFillGroup), 1, 1);
        glUniform1i(0, 1);
        glDispatchCompute(GLuint((W + kHoleFillGroup - 1) / kHoleFillGroup), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glUseProgram(program_.id());
    };
    glUseProgram(program_.id());
    glUniform1f(0, params.maxSpanRadii);
    glUniform1f(1, params.jumpRadii);
    glUniform1i(2, params.reachPx);
    glUniform2i(3, hasT ? 1 : 0, hasScene ? 1 : 0);
    attachBufferTexture(depthTex_, GL_R32F, depth.buffer, depth.bytes());
    // Unused bindings still need a texture of the right kind: the depth.
    attachBufferTexture(thicknessTex_, GL_R32F, hasT ? thickness.buffer : depth.buffer,
                        hasT ? thickness.bytes() : depth.bytes());
    attachBufferTexture(sceneTex_, GL_R32F, hasScene ? sceneDepth->buffer : depth.buffer,
                        hasScene ? sceneDepth->bytes() : depth.bytes());
    const Texture* textures[] = {&depthTex_, &thicknessTex_, &sceneTex_};
    for (int i = 0; i < 3; ++i) {
        glActiveTexture(GLenum(GL_TEXTURE0 + i));
        glBindTexture(GL_TEXTURE_BUFFER, textures[i]->id());
    }
    depthOut_.bind(3);
    (hasT ? thicknessOut_ : depthOut_).bind(4);
    // Each pass reads the last one's output (the CPU's passes; it stops
    // early when a pass fills nothing, which changes nothing here).
    for (int pass = 0; pass < params.passes; ++pass) {
        if (pass > 0) {
            std::swap(depth, depthOut_);
            if (hasT) std::swap(thickness, thicknessOut_);
            attachBufferTexture(depthTex_, GL_R32F, depth.buffer, depth.bytes());
            if (hasT) attachBufferTexture(thicknessTex_, GL_R32F, thickness.buffer, thickness.bytes());
            depthOut_.bind(3);
            (hasT ? thicknessOut_ : depthOut_).bind(4);
        }
        sweep();
        glDispatchCompute(GLuint((W + kHoleFillGroup - 1) / kHoleFillGroup), GLuint(H), 1);  // H <= 16384: in GL's guaranteed 65535
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    }
    for (int i = 2; i >= 0; --i) {
        glActiveTexture(GLenum(GL_TEXTURE0 + i));
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
    glUseProgram(0);
    if (params.passes > 0) {
        std::swap(depth, depthOut_);
        if (hasT) std::swap(thickness, thicknessOut_);
    }
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runFillHoles(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.raw);
    g.forget(at.thickness);
    g.pass<HoleFill>().run(g.params(), g.frame().holeFill, &g.img(at.sceneDepth), g.img(at.raw), g.img(at.thickness));
}

}  // namespace

extern const StageDriver kFillHolesStage = {glPrepare<HoleFill>, glRun<runFillHoles>};

}  // namespace meniscus::gl
