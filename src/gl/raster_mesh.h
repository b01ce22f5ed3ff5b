// GL mesh path: the GPU twin of meniscus::cpu::rasteriseMesh, the triangles
// drawn by GL's rasteriser with a depth test. Needs a current GL 4.3 context
// (gl::Context) on the calling thread.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "gl/uniforms.h"
#include "meniscus/mesh.h"
#include "meniscus/result.h"

namespace meniscus::gl {

// A mesh's vertex arrays on the GPU (positions, normals and, when given one
// per vertex, texture coordinates), uploaded by upload() and then drawn as
// often as wanted: the scene geometry keeps one per object while the
// geometry stays the same object (gl/geometry.cpp, gl/shadow.cpp).
struct GpuMesh {
    Buffer positions, normals, uvs;
    bool hasUv = false;
    // Uploads the vertices of `mesh` (and `uvs` when one per vertex).
    void upload(const TriangleMesh& mesh, const std::vector<glm::vec2>* uvs = nullptr);
};

// Triangle indices on the GPU (three per triangle, into a GpuMesh's vertices).
struct GpuIndices {
    Buffer buffer;
    GLsizei count = 0;
    void upload(std::span<const std::uint32_t> indices);
};

// The bytes of vertices and indices GpuMesh::upload and GpuIndices::upload
// sent to the GPU in this process (the tests' check that a still scene's
// geometry stays on the GPU).
std::uint64_t meshUploadBytes();

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
    // uploaded on every call (the liquid's mesh changes every frame).
    // Asynchronous: nothing waits for the GPU here.
    // With `uvs` (one per vertex) and `uv`, the texture coordinates too (W x H
    // x 2, perspective-correct, (0,0) where none), as cpu::rasteriseMesh's.
    void run(const FrameParams& frame, const TriangleMesh& mesh, const GpuImage* sceneDepth, GpuImage& depth,
             GpuImage& normal, const std::vector<glm::vec2>* uvs = nullptr, GpuImage* uv = nullptr);
    // The same for a mesh already on the GPU: `indices` into `mesh`'s
    // vertices, the texture coordinates into `uv` when given and the mesh has
    // them. Uploads nothing.
    void run(const FrameParams& frame, const GpuMesh& mesh, const GpuIndices& indices, const GpuImage* sceneDepth,
             GpuImage& depth, GpuImage& normal, GpuImage* uv = nullptr);

private:
    Program draw_;
    Program resolve_;
    VertexArray vertexArray_;
    GpuMesh mesh_;        // the arrays of a mesh given on the host
    GpuIndices indices_;
    Buffer empty_;     // bound in place of a missing scene depth
    Framebuffer framebuffer_;
    Texture depthTarget_, normalTarget_, uvTarget_, zBuffer_;
    int targetW_ = 0, targetH_ = 0;
};

}  // namespace meniscus::gl
