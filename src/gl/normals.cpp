// GL normals stage, docs/pipeline.md#normals: perspective-correct normals from
// the smoothed eye depth (van der Laan, Green & Sainz 2009, US 8,947,430, eqs.
// 3-6; Cords & Staadt 2008, "Instant Liquids" §2.3) by shaders/normals.comp,
// with the formulas of src/cpu/normals.cpp (src/shared/normals.h).
#include "gl/normals.h"
#include "gl/gl_backend.h"

#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr int kNormalsGroup = 64;  // local_size_x of normals.comp: columns per work group
constexpr int kRows = 16;   // rows per work group's tile (<= kMaxRows in normals.comp)
}  // namespace

Result<Normals> Normals::create() {
    Normals n;
    auto p = loadComputeProgram("normals.comp");
    if (!p) return p.error();
    n.program_ = std::move(*p);
    n.depthTex_ = makeTexture();
    return n;
}

void Normals::run(const FrameParams& frame, const GpuImage& depth, GpuImage& normals) {
    const int W = frame.size.x, H = frame.size.y;
    normals.resize(W, H, 3);
    if (W <= 0 || H <= 0) return;
    if (depth.width != W || depth.height != H || depth.channels != 1 || depth.buffer.id() == 0) {
        // No usable depth: no fluid anywhere, (0,0,0) as the CPU gives for +inf.
        normals.buffer.fill(normals.bytes(), 0u);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    // Non-fluid pixels are (0,0,0): a driver fill (a memset on llvmpipe); the
    // shader writes only the fluid pixels.
    normals.buffer.fill(normals.bytes(), 0u);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(program_.id());
    glUniform1i(0, kRows);
    attachBufferTexture(depthTex_, GL_R32F, depth.buffer, depth.bytes());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, depthTex_.id());
    normals.bind(2);
    glDispatchCompute(GLuint((W + kNormalsGroup - 1) / kNormalsGroup), GLuint((H + kRows - 1) / kRows), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glUseProgram(0);
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runNormals(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.normal);
    g.pass<Normals>().run(g.params(), g.img(at.depth), g.img(at.normal));
}

}  // namespace

extern const StageDriver kNormalsStage = {glPrepare<Normals>, glRun<runNormals>};

}  // namespace meniscus::gl
