// GL shadow stages (docs/geometry.md#shadows), the twins of src/cpu/shadow.cpp.
// shadow-map: on the key light's camera (core/shadow_camera.h) the mesh
// path's rasteriser draws the shadow casters' depth (a shadow map, Williams
// 1978, "Casting curved shadows on curved surfaces") and the
// depth-splat+thickness driver the liquid's nearest depth and thickness
// against it. shadows: shaders/shadow.comp looks each scene pixel up in those
// maps (shared/shadow.h, the CPU's formulas): the key light's share taken
// away behind the geometry, attenuated by Beer-Lambert's law behind the liquid.
#include <limits>
#include <memory>

#include "core/shadow_camera.h"
#include "gl/dispatch.h"
#include "gl/filter_separable.h"
#include "gl/gl_backend.h"
#include "gl/raster_mesh.h"
#include "gl/shaders.h"
#include "gl/thickness_lowres.h"
#include "shared/shadow.h"
#include "shared/sky.h"

namespace meniscus::gl {

extern const StageDriver kSplatStage;

namespace {

constexpr int kShadowGroup = 64;  // local_size_x of shadow.comp

struct ShadowPasses {
    MeshRasteriser raster;
    Program shade;
    GpuImage normal;  // the rasteriser's normals, unread
    TriangleMesh casters;
    // The geometry's depth from the light, kept (as the CPU's
    // CpuBackend::casterDepth) while the geometry object and the light's
    // camera stay: a still scene rasterises its casters once. Their vertices
    // stay on the GPU while the geometry object does (a light's camera that
    // moves, as the liquid's bounds grow, sends only the indices of the
    // faces it sees).
    GpuImage casterDepth;
    GpuMesh casterMesh;
    bool casterMeshValid = false;  // casterMesh holds casterGeometry's vertices
    GpuIndices casterFaces;
    std::shared_ptr<const SceneGeometry> casterGeometry;
    Camera casterCamera;
    bool casterValid = false;

    static Result<ShadowPasses> create() {
        ShadowPasses p;
        auto raster = MeshRasteriser::create();
        if (!raster) return raster.error();
        p.raster = std::move(*raster);
        auto shade = loadComputeProgram("shadow.comp");
        if (!shade) return shade.error();
        p.shade = std::move(*shade);
        return p;
    }
};

// On the light's camera (the stage's row switched to it).
void runShadowMap(GlBackend& g, const StageIo& io) {
    const FrameSettings& s = g.frame();
    ShadowPasses& p = g.pass<ShadowPasses>();
    if (!p.casterValid || p.casterGeometry != s.geometry || !(p.casterCamera == s.camera)) {
        if (p.casterGeometry != s.geometry) p.casterMeshValid = false;
        shadowCasters(s.geometry.get(), s.camera.eye, p.casters);
        if (p.casters.empty()) {
            p.casterDepth.upload(Image<float>(s.camera.width, s.camera.height, std::numeric_limits<float>::infinity()));
        } else {
            // The vertices (every drawn opaque object's, whatever the light's
            // eye) only for a new geometry object; the faces for this eye.
            if (!p.casterMeshValid) p.casterMesh.upload(p.casters);
            p.casterMeshValid = true;
            p.casterFaces.upload(p.casters.indices);
            p.raster.run(g.params(), p.casterMesh, p.casterFaces, nullptr, p.casterDepth, p.normal);
        }
        p.casters = {};  // the triangles live on the GPU now
        p.casterGeometry = s.geometry;
        p.casterCamera = s.camera;
        p.casterValid = true;
    }
    g.forget(io.at.sceneDepth);
    g.img(io.at.sceneDepth).copyFrom(p.casterDepth);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    kSplatStage.run(g, io);
}

void runShadows(GlBackend& g, const StageIo& io) {
    const FrameSettings& s = g.frame();
    const int side = shared::kShadowMapPx;
    if (!g.img(Slot::LightDepth).sized(side, side, 1)) return;  // no map (a stage run alone)
    const int W = s.camera.width, H = s.camera.height;
    const ShadowLight& light = s.shadow;
    const Camera& lc = light.camera;
    g.forget(io.at.sceneColor);
    ShadowPasses& p = g.pass<ShadowPasses>();
    glUseProgram(p.shade.id());
    auto set3 = [](GLint at, const glm::vec3& v) { glUniform3f(at, v.x, v.y, v.z); };
    set3(0, lc.eye);
    set3(1, lc.right());
    set3(2, lc.trueUp());
    set3(3, lc.back());
    set3(4, shared::sunDirection(s.studio.lightDirWorld));
    set3(5, s.shading.material.absorptionPerM);
    glUniform2f(6, lc.focalPx(), light.texelM);
    g.img(io.at.sceneColor).bind(1);
    g.img(io.at.sceneDepth).bind(2);
    g.img(Slot::LightDepth).bind(3);
    g.img(Slot::LightRaw).bind(4);
    g.img(Slot::LightThickness).bind(5);
    g.environment().bind(7, 9);  // the map's ambient (docs/pipeline.md#environment-map)
    glDispatchCompute(ceilDiv(GLuint(W), kShadowGroup), GLuint(H), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

}  // namespace

extern const StageDriver kShadowMapStage = {glPrepare<ShadowPasses, SeparableFilters, LowResThickness>,
                                            glRun<runShadowMap>};
extern const StageDriver kShadowsStage = {glPrepare<ShadowPasses>, glRun<runShadows>};

}  // namespace meniscus::gl
