// CPU triangle-mesh rasteriser (docs/conventions.md#data-flow, the mesh path):
// the eye depth and view-space normal of the nearest triangle at every pixel
// centre, so a mesh can take the place of smoothing + normals in the pipeline.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/mesh.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// Screen tiles of the rasteriser: one task per tile, triangles binned per tile.
inline constexpr int kRasterTilePx = 64;
// Sub-pixel precision of the vertex positions the coverage test uses (as D3D11
// and llvmpipe: 8 bits, 1/256 px).
inline constexpr int kRasterSubpixelBits = 8;

// The rasteriser's own memory (its vertices and tile bins), kept by a
// MeshRaster across calls so a frame does not allocate (and fault in) it again.
// A copy starts empty: two rasters never share it.
class RasterWorkspace {
public:
    struct Data;
    RasterWorkspace();
    ~RasterWorkspace();
    RasterWorkspace(const RasterWorkspace&) : RasterWorkspace() {}
    RasterWorkspace& operator=(const RasterWorkspace&) { return *this; }
    RasterWorkspace(RasterWorkspace&&) noexcept;
    RasterWorkspace& operator=(RasterWorkspace&&) noexcept;
    Data& data() { return *data_; }

private:
    std::unique_ptr<Data> data_;
};

struct MeshRaster {
    Image<float> depth;       // eye depth of the nearest triangle (m), +inf where none
    Image<glm::vec3> normal;  // its unit view-space normal (+z toward the camera), (0,0,0) where none
    // Its texture coordinates, interpolated perspective-correctly, when the
    // mesh has them (MeshRef::uvs), (0,0) where none; else left empty (0 x 0).
    Image<glm::vec2> uv;
    RasterWorkspace work;     // reused by the next rasteriseMesh into this raster
};

// A mesh's arrays as the rasteriser reads them: a TriangleMesh's, or its
// vertices with a subset of its triangles (the faces a frame draws).
struct MeshRef {
    std::span<const glm::vec3> positions, normals;
    std::span<const std::uint32_t> indices;  // three per triangle
    std::span<const glm::vec2> uvs = {};     // texture coordinates, one per vertex, or none
    static MeshRef of(const TriangleMesh& m) { return {m.positions, m.normals, m.indices}; }
    std::size_t triangleCount() const { return indices.size() / 3; }
};

// Rasterises `mesh` (world positions, unit per-vertex normals) seen by
// `camera`: per pixel centre the nearest triangle's linear eye depth and its
// normal interpolated perspective-correctly from the vertex normals (rotated to
// view space), then renormalised. Both faces of a triangle are drawn. Triangles
// are clipped against the near plane in view space (a triangle crossing it is
// drawn in part, not dropped); fragments at or behind `sceneDepth` (when given,
// camera-sized) are not drawn, as in the depth splat. Coverage follows the
// top-left fill rule, so triangles sharing an edge cover each pixel centre along
// it exactly once. Bit-identical for any thread count.
//
// Preconditions (the Renderer checks them and reports an error instead):
// camera valid with width, height <= shared::kRasterMaxSidePx
// (src/shared/raster_mesh.h); TriangleMesh::validate(true). Triangles with an
// index out of range are skipped all the same. Memory: the images, 36 bytes
// per vertex and bins of at most a few million triangle indices (the
// triangles are drawn in batches).
//
// `coverage`, when given (camera-sized, zero-filled by the caller), counts the
// triangles whose coverage test passes at each pixel centre, before any depth
// or scene test: a test of the fill rule.
MeshRaster rasteriseMesh(const Camera& camera, const TriangleMesh& mesh, const Image<float>* sceneDepth = nullptr,
                         Image<std::uint32_t>* coverage = nullptr);
// The same into `out`, whose images' memory is reused (a stage drawing every frame).
void rasteriseMesh(const Camera& camera, const TriangleMesh& mesh, const Image<float>* sceneDepth, MeshRaster& out,
                   Image<std::uint32_t>* coverage = nullptr);
// The same over a MeshRef.
void rasteriseMesh(const Camera& camera, const MeshRef& mesh, const Image<float>* sceneDepth, MeshRaster& out,
                   Image<std::uint32_t>* coverage = nullptr);

}  // namespace meniscus::cpu
