// An indexed triangle mesh: what the isosurface path (include/meniscus/surface.h)
// produces, the mesh writers (include/meniscus/io.h) write and the renderer's
// mesh path (RenderSettings::mesh) rasterises. A plain value type of core, so the
// backends can draw a mesh without knowing how it was made.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace meniscus {

struct TriangleMesh {
    std::vector<glm::vec3> positions;     // world space, metres
    std::vector<glm::vec3> normals;       // one unit normal per vertex, pointing out of the fluid
    std::vector<std::uint32_t> indices;   // three per triangle, counter-clockwise seen from outside

    std::size_t vertexCount() const { return positions.size(); }
    std::size_t triangleCount() const { return indices.size() / 3; }
    bool empty() const { return indices.empty(); }
};

}  // namespace meniscus
