// GL mesh path: the GPU twin of meniscus::cpu::rasteriseMesh, the triangles
// drawn by GL's rasteriser with a depth test. Needs a current GL 4.3 context
// (gl::Context) on the calling thread.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/uniforms.h"
#include "meniscus/mesh.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// Owns the programs, the mesh's buffers and the draw's targets; reuse one
// across frames (they grow, never shrink).
class MeshRasteriser {
public:
    // Compiles the shaders; an error carries the driver's log.
    static Result<MeshRasteriser> create();

    // GL twin of cpu::rasteriseMesh(camera, mesh, sceneDepth): depth (W x H x
    // 1, eye depth of the nearest triangle, +inf where none) and normal (W x H
    // x 3, its interpolated view-space unit normal, (0,0,0) where none), for
    // the camera of the bound frame block (binding 0, uploaded by the caller
    // from `frame`). Fragments at or behind `sceneDepth` (when W x H x 1) are
    // not drawn. The mesh must be valid (the Renderer checks it) and is
    // uploaded on every call. Asynchronous: nothing waits for the GPU here.
    // With `uvs` (one per vertex) and `uv`, the texture coordinates too (W x H
    // x 2, perspective-correct, (0,0) where none), as cpu::rasteriseMesh's.
    void run(const FrameParams& frame, const TriangleMesh& mesh, const GpuImage* sceneDepth, GpuImage& depth,
             GpuImage& normal, const std::vector<glm::vec2>* uvs = nullptr, GpuImage* uv = nullptr);

private:
    Program draw_;
    Program resolve_;
    VertexArray vertexArray_;
    Buffer positions_, normals_, indices_, uvs_;  // the mesh's arrays
    Buffer empty_;     // bound in place of a missing scene depth
    Framebuffer framebuffer_;
    Texture depthTarget_, normalTarget_, uvTarget_, zBuffer_;
    int targetW_ = 0, targetH_ = 0;
};

}  // namespace meniscus::gl
