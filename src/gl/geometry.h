// GL geometry stage (docs/geometry.md#how-it-is-drawn): the GPU twin of
// meniscus::cpu::drawGeometry. Needs a current GL 4.3 context.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/geometry_draw.h"
#include "gl/environment.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/raster_mesh.h"
#include "gl/uniforms.h"
#include "meniscus/geometry.h"
#include "meniscus/result.h"
#include "shared/studio.h"

namespace meniscus::gl {

// Owns the rasteriser of the objects' triangles, its images and the shading
// program; reuse one across frames. The objects' vertices, texture
// coordinates and base colour maps stay on the GPU while the geometry is the
// same object (SceneGeometry is shared and immutable, FrameSettings::geometry):
// a still scene uploads its meshes once, and a moving camera only the indices
// of the faces it sees (core/geometry_draw.h's facesSeenFrom, exact on the
// host), for the objects whose faces depend on the eye.
class GeometryDrawer {
public:
    static Result<GeometryDrawer> create();

    // GL twin of cpu::drawGeometry: each drawn object rasterised against
    // `depth` (MeshRasteriser, the mesh path's rasteriser) and shaded by
    // shaders/geometry_shade.comp into `color` and `depth` where nearer, for
    // the camera of the bound frame block. Asynchronous.
    void run(const FrameParams& frame, const glm::vec3& eye, const std::shared_ptr<const SceneGeometry>& geometry,
             const shared::Studio& studio, GpuImage& color, GpuImage& depth,
             const EnvironmentGpu* environment = nullptr);
    // GL twin of cpu::drawGlassFronts: the glass stage.
    void runGlassFronts(const FrameParams& frame, const glm::vec3& eye,
                        const std::shared_ptr<const SceneGeometry>& geometry, const shared::Studio& studio,
                        const GpuImage& liquidDepth, GpuImage& sceneDepth, GpuImage& color,
                        const EnvironmentGpu* environment = nullptr);

private:
    // The indices of the faces of one object a stage draws, and for which
    // faces and eye they were found.
    struct KeptFaces {
        GpuIndices indices;
        Faces faces = Faces::All;
        glm::vec3 eye{0.0f};
        bool valid = false;
    };
    // One object on the GPU: its vertices (with the texture coordinates when
    // it is drawn textured), its base colour map's texels, the faces the
    // geometry stage and the glass stage draw.
    struct ObjectOnGpu {
        GpuMesh mesh;
        bool meshValid = false;
        Buffer texture;
        bool textureValid = false;
        KeptFaces scene, fronts;
    };

    // The object `index` of `geometry` on the GPU, uploaded on its first use
    // since the geometry object changed.
    ObjectOnGpu& onGpu(const std::shared_ptr<const SceneGeometry>& geometry, std::size_t index);
    // `kept` made the indices of `faces` of `object` seen from `eye`
    // (uploaded only when those differ from what it holds).
    void keepFaces(KeptFaces& kept, const GeometryObject& object, const glm::vec3& eye, Faces faces);
    // One object's faces rasterised against `depth`, shaded (mode 0 opaque, 1
    // glass) into color (and depth when opaque), in front of `limit` too when given.
    void drawObject(const FrameParams& frame, ObjectOnGpu& gpu, const GpuIndices& faces,
                    const GeometryObject& object, const glm::vec3& light, int mode, const GpuImage* limit,
                    GpuImage& color, GpuImage& depth, const EnvironmentGpu* environment);

    MeshRasteriser raster_;
    Program shade_;
    GpuImage objectDepth_, objectNormal_, objectUv_;
    // What objects_ holds the objects of (kept alive, so that no new geometry
    // takes its address).
    std::shared_ptr<const SceneGeometry> geometry_;
    std::vector<ObjectOnGpu> objects_;
    std::vector<std::uint32_t> scratch_;
};

}  // namespace meniscus::gl
