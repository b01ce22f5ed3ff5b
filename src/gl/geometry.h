// GL geometry stage (docs/geometry.md#how-it-is-drawn): the GPU twin of
// meniscus::cpu::drawGeometry. Needs a current GL 4.3 context.
#pragma once

#include <memory>

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
// program; reuse one across frames.
class GeometryDrawer {
public:
    static Result<GeometryDrawer> create();

    // GL twin of cpu::drawGeometry: each drawn object rasterised against
    // `depth` (MeshRasteriser, the mesh path's rasteriser) and shaded by
    // shaders/geometry_shade.comp into `color` and `depth` where nearer, for
    // the camera of the bound frame block. Asynchronous.
    void run(const FrameParams& frame, const glm::vec3& eye, const SceneGeometry& geometry,
             const shared::Studio& studio, GpuImage& color, GpuImage& depth,
             const EnvironmentGpu* environment = nullptr);
    // GL twin of cpu::drawGlassFronts: the glass stage.
    void runGlassFronts(const FrameParams& frame, const glm::vec3& eye, const SceneGeometry& geometry,
                        const shared::Studio& studio, const GpuImage& liquidDepth, GpuImage& sceneDepth,
                        GpuImage& color, const EnvironmentGpu* environment = nullptr);

private:
    // One object's faces rasterised against `depth`, shaded (mode 0 opaque, 1
    // glass) into color (and depth when opaque), in front of `limit` too when given.
    void drawObject(const FrameParams& frame, const TriangleMesh& mesh, const GeometryObject& object, const glm::vec3& light,
                    int mode, const GpuImage* limit, GpuImage& color, GpuImage& depth,
                    const EnvironmentGpu* environment);

    MeshRasteriser raster_;
    Program shade_;
    GpuImage objectDepth_, objectNormal_, objectUv_;
    // The last base colour map uploaded (its texels), kept while the same image is drawn.
    Buffer texture_;
    std::shared_ptr<const GeometryTexture> uploaded_;
    TriangleMesh scratch_;
};

}  // namespace meniscus::gl
