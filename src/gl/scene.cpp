// GL scene stage, docs/pipeline.md#scene: the studio of src/cpu/scene.cpp
// (checker floor and two back walls, after the compositing order of van der
// Laan et al. 2009, US 8,947,430, and Instant Liquids, Cords & Staadt 2008, §3)
// ray-cast per pixel by shaders/scene.comp, operation for operation as the
// CPU's castRow. What the CPU computes once per image (reciprocals, per-plane
// lighting, the sun) comes from the same shared::studioShading and is passed as
// uniforms, so both see the same bits.
#include "gl/scene.h"
#include "core/backdrop_layer.h"
#include "gl/gl_backend.h"
#include "gl/host_layers.h"

#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr int kSceneGroup = 64;  // local_size_x of scene.comp: columns per work group
constexpr int kRows = 8;    // rows per invocation (llvmpipe pays a fixed cost per work group)

}  // namespace

Result<SceneCaster> SceneCaster::create() {
    SceneCaster s;
    auto p = loadComputeProgram("scene.comp");
    if (!p) return p.error();
    s.program_ = std::move(*p);
    return s;
}

void SceneCaster::run(const FrameParams& frame, const shared::Studio& studio, GpuImage& color, GpuImage& depth,
                      const EnvironmentGpu* environment) {
    const int W = frame.size.x, H = frame.size.y;
    color.resize(W, H, 4);
    depth.resize(W, H, 1);
    if (W <= 0 || H <= 0) return;
    if (!studio.enabled) {  // transparent background, no geometry
        color.buffer.fill(color.bytes(), 0u);
        depth.buffer.fill(depth.bytes(), 0x7f800000u);  // +inf
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    // As castScene: the per-image constants from the one shared function.
    const shared::StudioShading sh =
        shared::studioShading(studio, environment ? environment->map : shared::EnvironmentMap{});
    glUseProgram(program_.id());
    glUniform4f(0, studio.floorY, studio.wallX, studio.wallZ, studio.wallTopY);
    glUniform2f(1, studio.wallXNormal, studio.wallZNormal);
    glUniform4f(2, sh.invChecker, sh.aoScale, sh.fadeStart, sh.invFade);
    const glm::vec3 lit[3] = {sh.litFloor, sh.litWallX, sh.litWallZ};
    glUniform3fv(18, 3, &lit[0].x);
    glUniform1i(4, kRows);
    glUniform3f(5, sh.sunDir.x, sh.sunDir.y, sh.sunDir.z);
    glUniform1i(6, studio.walls ? 1 : 0);
    if (environment) environment->bind(7, 9);
    else bindNoEnvironment(7, 9);
    color.bind(1);
    depth.bind(2);
    glDispatchCompute(GLuint((W + kSceneGroup - 1) / kSceneGroup), GLuint((H + kRows - 1) / kRows), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// Cast again only when the camera, the studio or the slots changed.
void runScene(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    if (const HostLayers* host = g.frame().hostLayers) {
        // Embedding: the host's picture, new every frame, is never kept.
        g.forget(at.sceneColor);
        g.pass<HostLayerImport>().run(*host, g.frame().camera, g.img(at.sceneColor), g.img(at.sceneDepth));
        return;
    }
    if (g.sceneCached(at.sceneColor, at.sceneDepth)) return;
    if (const BackdropImage* backdrop = g.frame().backdrop.get()) {
        // The backdrop's layer, made on the host as the CPU makes it
        // (core/backdrop_layer.h) and uploaded once per camera and backdrop.
        Image<glm::vec4> color;
        Image<float> depth;
        backdropLayer(g.frame().camera, *backdrop, color, depth);
        g.img(at.sceneColor).upload(color);
        g.img(at.sceneDepth).upload(depth);
        g.sceneCast(at.sceneColor, at.sceneDepth);
        return;
    }
    g.pass<SceneCaster>().run(g.params(), g.frame().studio, g.img(at.sceneColor), g.img(at.sceneDepth),
                                 &g.environment());
    g.sceneCast(at.sceneColor, at.sceneDepth);
}

}  // namespace

extern const StageDriver kSceneStage = {glPrepare<SceneCaster, HostLayerImport>, glRun<runScene>};

}  // namespace meniscus::gl
