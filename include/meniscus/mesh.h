// An indexed triangle mesh: what the isosurface path (include/meniscus/surface.h)
// produces, the mesh writers (include/meniscus/io.h) write and the renderer's
// mesh path (RenderSettings::mesh) rasterises. A plain value type of core, so the
// backends can draw a mesh without knowing how it was made.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

struct TriangleMesh {
    std::vector<glm::vec3> positions;     // world space, metres
    std::vector<glm::vec3> normals;       // one unit normal per vertex, pointing out of the fluid
    std::vector<std::uint32_t> indices;   // three per triangle, counter-clockwise seen from outside
    // Values per vertex (interpolateAttributes: the particles' attributes,
    // Float): `components` values per vertex each, written by the PLY and VTK
    // writers.
    std::vector<Attribute> attributes;

    std::size_t vertexCount() const { return positions.size(); }
    std::size_t triangleCount() const { return indices.size() / 3; }
    bool empty() const { return indices.empty(); }

    // OK when the mesh holds together, as every consumer (the writers, both
    // rasterisers) assumes: whole triangles, at most 2^32 - 1 of them, every
    // index below vertexCount(), one normal per vertex (or, unless
    // `needNormals`, none at all), finite positions and normals, each
    // attribute named, Float, with its values for every vertex. Otherwise an
    // error (no file: the caller says whose mesh it is) naming the first
    // problem, e.g. "triangle 3 has vertex index 9, out of range (8 vertices)".
    Status validate(bool needNormals = false) const;
};

}  // namespace meniscus
