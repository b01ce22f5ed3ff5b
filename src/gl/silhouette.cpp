// GL silhouette reduction, docs/pipeline.md#silhouette-reduction (Cords &
// Staadt 2008, "Instant Liquids" §3: the binary depth map smoothed by a kernel,
// the liquid shown only where it reaches 1): the twin of
// src/cpu/silhouette.cpp. The window's weights are uniform, so its fluid count
// is four reads of a summed-area table of the fluid mask, built in two passes
// of integer prefix sums (one invocation per row, shaders/silhouette_rows.comp,
// then one per column, silhouette_columns.comp: at most 16384 iterations each,
// under llvmpipe's 65,535 loop cap, and exact in any order); then one pass per
// pixel gets S and fades the colour (silhouette_resolve.comp) through the
// formulas of src/shared/silhouette.h, the focal length and the window's world
// radius computed here as the CPU does, so S and the colour are the CPU's bits.
#include "gl/silhouette.h"
#include "gl/gl_backend.h"

#include <cstdint>

#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kTableGroup = 16;  // local_size_x of the table passes: rows and columns spread over more groups
constexpr GLuint kSilhouetteGroup = 64;       // local_size_x of the resolve
// Pixels per invocation of the resolve (llvmpipe pays a fixed cost per work group).
constexpr GLuint kSilhouetteResolvePerInvocation = 4;

}  // namespace

Result<SilhouetteReduction> SilhouetteReduction::create() {
    SilhouetteReduction s;
    auto rows = loadComputeProgram("silhouette_rows.comp");
    if (!rows) return rows.error();
    auto columns = loadComputeProgram("silhouette_columns.comp");
    if (!columns) return columns.error();
    auto resolve = loadComputeProgram("silhouette_resolve.comp");
    if (!resolve) return resolve.error();
    s.rows_ = std::move(*rows);
    s.columns_ = std::move(*columns);
    s.resolve_ = std::move(*resolve);
    s.satTex_ = makeTexture();
    s.depthTex_ = makeTexture();
    s.behindTex_ = makeTexture();
    s.colorTex_ = makeTexture();
    s.silTex_ = makeTexture();
    s.liquidTex_ = makeTexture();
    return s;
}

void SilhouetteReduction::run(const Camera& camera, const GpuImage& depth, const GpuImage& behind, float radius,
                              const SilhouetteParams& p, GpuImage& color, GpuImage& silhouette) {
    const int W = camera.width, H = camera.height;
    silhouette.resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    // Images of another size (then as the CPU): S 0, the colour untouched.
    if (!depth.sized(W, H, 1) || !behind.sized(W, H, 4) || !color.sized(W, H, 4)) {
        silhouette.buffer.fill(silhouette.bytes(), 0u);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    const GLuint pixels = GLuint(W) * GLuint(H);

    // The table: row 0 is 0 (the driver's fill, a memset on llvmpipe), the
    // rest is written by the row pass, then summed down the columns in place.
    const GLsizeiptr stride = GLsizeiptr(W) + 1;
    const GLsizeiptr satBytes = stride * (GLsizeiptr(H) + 1) * GLsizeiptr(sizeof(std::uint32_t));
    sat_.reserve(satBytes);
    sat_.fill(stride * GLsizeiptr(sizeof(std::uint32_t)), 0u);
    attachBufferTexture(satTex_, GL_R32UI, sat_, satBytes);
    attachBufferTexture(depthTex_, GL_R32F, depth.buffer, depth.bytes());
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(rows_.id());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, depthTex_.id());
    glBindImageTexture(0, satTex_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32UI);
    glUniform2i(0, W, H);
    glDispatchCompute(ceilDiv(GLuint(H), kTableGroup), 1, 1);  // H <= 16384: well under kMaxGroups
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glUseProgram(columns_.id());
    glBindImageTexture(0, satTex_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    glUniform2i(0, W, H);
    glDispatchCompute(ceilDiv(GLuint(W), kTableGroup), 1, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);

    // Per pixel: S, and the colour faded in place. The host floats are the
    // CPU's (cpu::reduceSilhouettes: p.radiusRadii * radius, camera.focalPx()).
    const float radiusM = p.radiusRadii * radius, focal = camera.focalPx();
    // The colour before the fade, read by the background pixels next to the liquid.
    liquid_.copyFrom(color);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    attachBufferTexture(liquidTex_, GL_RGBA32F, liquid_.buffer, liquid_.bytes());
    attachBufferTexture(behindTex_, GL_RGBA32F, behind.buffer, behind.bytes());
    attachBufferTexture(colorTex_, GL_RGBA32F, color.buffer, color.bytes());
    attachBufferTexture(silTex_, GL_R32F, silhouette.buffer, silhouette.bytes());
    glUseProgram(resolve_.id());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, depthTex_.id());
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_BUFFER, satTex_.id());
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_BUFFER, behindTex_.id());
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_BUFFER, liquidTex_.id());
    glBindImageTexture(0, colorTex_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(1, silTex_.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glUniform2i(0, W, H);
    glUniform1f(1, radiusM);
    glUniform1f(2, focal);
    glUniform1i(3, p.maxPx);
    glUniform1f(4, p.fadeFrom);
    glDispatchCompute(gridGroups(pixels, kSilhouetteGroup * kSilhouetteResolvePerInvocation), 1, 1);
    glBindImageTexture(0, 0, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(1, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                    GL_TEXTURE_FETCH_BARRIER_BIT);
    for (GLenum unit : {GL_TEXTURE3, GL_TEXTURE2, GL_TEXTURE1, GL_TEXTURE0}) {
        glActiveTexture(unit);
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
    glUseProgram(0);
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// Faded in place: a colour slot that held the cached scene no longer does
// (the next cast redraws it), as the CPU copies its cached scene out before
// fading, never the scene itself.
void runSilhouette(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.color);
    g.forget(at.silhouette);
    const FrameSettings& s = g.frame();
    g.pass<SilhouetteReduction>().run(s.camera, g.img(at.depth), g.img(at.sceneColor), s.radius, s.silhouette,
                                      g.img(at.color), g.img(at.silhouette));
}

}  // namespace

extern const StageDriver kSilhouetteStage = {glPrepare<SilhouetteReduction>, glRun<runSilhouette>};

}  // namespace meniscus::gl
