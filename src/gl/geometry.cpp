// GL geometry stage (geometry.h): per drawn object, the mesh path's
// rasteriser draws its triangles against the scene depth, then
// shaders/geometry_shade.comp shades the covered pixels with
// shared::geometryRadiance (the CPU's formula, src/shared/geometry_shade.h)
// and writes them into the scene layer. The compositing is van der Laan et
// al. 2009's (US 8,947,430) and Instant Liquids' (Cords & Staadt 2008, §3):
// the opaque scene first, the liquid against its depth.
#include "gl/geometry.h"
#include "gl/gl_backend.h"

#include "gl/dispatch.h"
#include "gl/shaders.h"
#include "shared/sky.h"

namespace meniscus::gl {

namespace {
constexpr int kGeometryGroup = 64;  // local_size_x of geometry_shade.comp
}  // namespace

Result<GeometryDrawer> GeometryDrawer::create() {
    GeometryDrawer d;
    auto raster = MeshRasteriser::create();
    if (!raster) return raster.error();
    d.raster_ = std::move(*raster);
    auto shade = loadComputeProgram("geometry_shade.comp");
    if (!shade) return shade.error();
    d.shade_ = std::move(*shade);
    return d;
}

GeometryDrawer::ObjectOnGpu& GeometryDrawer::onGpu(const std::shared_ptr<const SceneGeometry>& geometry,
                                                   std::size_t index) {
    if (geometry_ != geometry) {
        objects_.clear();
        objects_.resize(geometry->objects.size());
        geometry_ = geometry;
    }
    ObjectOnGpu& gpu = objects_[index];
    const GeometryObject& object = geometry->objects[index];
    if (!gpu.meshValid) {
        // The texture coordinates only of an object drawn textured (drawnTexture).
        const GeometryTexture* t = drawnTexture(object);
        gpu.mesh.upload(object.mesh, t ? &object.uvs : nullptr);
        gpu.meshValid = true;
    }
    return gpu;
}

void GeometryDrawer::keepFaces(KeptFaces& kept, const GeometryObject& object, const glm::vec3& eye, Faces faces) {
    // All the faces do not depend on the eye; the others on which side of
    // each face's plane it is.
    if (kept.valid && kept.faces == faces && (faces == Faces::All || kept.eye == eye)) return;
    kept.indices.upload(facesSeenFrom(object.mesh, eye, faces, &scratch_));
    kept.faces = faces;
    kept.eye = eye;
    kept.valid = true;
}

void GeometryDrawer::drawObject(const FrameParams& frame, ObjectOnGpu& gpu, const GpuIndices& faces,
                                const GeometryObject& object, const glm::vec3& light, int mode,
                                const GpuImage* limit, GpuImage& color, GpuImage& depth,
                                const EnvironmentGpu* environment) {
    const int W = frame.size.x, H = frame.size.y;
    const GeometryMaterial& m = object.material;
    // The base colour map, as the CPU draws it (drawnTexture); the kept
    // faces index the object's own vertices, so its coordinates fit.
    const GeometryTexture* t = drawnTexture(object);
    const bool textured = t != nullptr;
    raster_.run(frame, gpu.mesh, faces, &depth, objectDepth_, objectNormal_, textured ? &objectUv_ : nullptr);
    if (textured && !gpu.textureValid) {
        gpu.texture.upload(t->rgb.data(), GLsizeiptr(t->rgb.size() * sizeof(float)));
        gpu.textureValid = true;
    }
    glUseProgram(shade_.id());
    glUniform2i(20, textured ? t->width : 0, textured ? t->height : 0);
    if (textured) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, objectUv_.buffer.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, gpu.texture.id());
    } else {
        // Unread without a texture, but bound: the shader declares them.
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, objectDepth_.buffer.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, objectDepth_.buffer.id());
    }
    glUniform3f(0, light.x, light.y, light.z);
    glUniform3f(1, m.baseColor.x, m.baseColor.y, m.baseColor.z);
    glUniform2f(2, m.roughness, m.metalness);
    glUniform1i(3, mode);
    glUniform3f(4, m.tint.x, m.tint.y, m.tint.z);
    glUniform2f(5, m.ior, m.thicknessM);
    glUniform1i(6, limit ? 1 : 0);
    if (environment) environment->bind(7, 9);
    else bindNoEnvironment(7, 9);
    objectDepth_.bind(1);
    objectNormal_.bind(2);
    color.bind(3);
    depth.bind(4);
    (limit ? *limit : objectDepth_).bind(5);  // unread without uLimit
    glDispatchCompute(ceilDiv(GLuint(W), kGeometryGroup), GLuint(H), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

void GeometryDrawer::run(const FrameParams& frame, const glm::vec3& eye,
                         const std::shared_ptr<const SceneGeometry>& geometry, const shared::Studio& studio,
                         GpuImage& color, GpuImage& depth, const EnvironmentGpu* environment) {
    if (frame.size.x <= 0 || frame.size.y <= 0 || !geometry) return;
    // The same bits as the CPU's: computed once on the host.
    const glm::vec3 light = shared::sunDirection(studio.lightDirWorld);
    // The opaque objects, then glass's back faces over them (as the CPU).
    for (const bool glass : {false, true})
        for (std::size_t i = 0; i < geometry->objects.size(); ++i) {
            const GeometryObject& object = geometry->objects[i];
            if (!drawsObject(object) || object.material.glass != glass) continue;
            ObjectOnGpu& gpu = onGpu(geometry, i);
            keepFaces(gpu.scene, object, eye, sceneFaces(object));
            drawObject(frame, gpu, gpu.scene.indices, object, light, glass ? 1 : 0, nullptr, color, depth,
                       environment);
        }
}

void GeometryDrawer::runGlassFronts(const FrameParams& frame, const glm::vec3& eye,
                                    const std::shared_ptr<const SceneGeometry>& geometry,
                                    const shared::Studio& studio, const GpuImage& liquidDepth,
                                    GpuImage& sceneDepth, GpuImage& color, const EnvironmentGpu* environment) {
    if (frame.size.x <= 0 || frame.size.y <= 0 || !geometry) return;
    const glm::vec3 light = shared::sunDirection(studio.lightDirWorld);
    for (std::size_t i = 0; i < geometry->objects.size(); ++i) {
        const GeometryObject& object = geometry->objects[i];
        if (!drawsObject(object) || !object.material.glass) continue;
        ObjectOnGpu& gpu = onGpu(geometry, i);
        keepFaces(gpu.fronts, object, eye, Faces::Front);
        drawObject(frame, gpu, gpu.fronts.indices, object, light, 1, &liquidDepth, color, sceneDepth,
                   environment);
    }
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

// Draws over the scene slots: the cached studio cast is no longer what they hold.
void runGeometry(GlBackend& g, const StageIo& io) {
    const FrameSettings& s = g.frame();
    if (!s.geometry) return;
    g.forget(io.at.sceneColor);
    g.forget(io.at.sceneDepth);
    g.pass<GeometryDrawer>().run(g.params(), s.camera.eye, s.geometry, s.studio, g.img(io.at.sceneColor),
                                 g.img(io.at.sceneDepth), &g.environment());
}

// The glass's front faces over the finished picture (the scene's depth is
// only read: the glass stage writes the colour alone).
void runGlass(GlBackend& g, const StageIo& io) {
    const FrameSettings& s = g.frame();
    if (!s.geometry) return;
    g.pass<GeometryDrawer>().runGlassFronts(g.params(), s.camera.eye, s.geometry, s.studio, g.img(io.at.depth),
                                            g.img(io.at.sceneDepth), g.img(io.at.color), &g.environment());
}

}  // namespace

extern const StageDriver kGeometryStage = {glPrepare<GeometryDrawer>, glRun<runGeometry>};
extern const StageDriver kGlassStage = {glPrepare<GeometryDrawer>, glRun<runGlass>};

}  // namespace meniscus::gl
