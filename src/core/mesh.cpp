// TriangleMesh::validate: the one structural check of a mesh, shared by the
// mesh writers (src/io/mesh_writer.cpp) and the renderer's mesh path
// (src/render/pipeline.cpp), so both refuse the same meshes in the same words.
#include "meniscus/mesh.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace meniscus {

Status TriangleMesh::validate(bool needNormals) const {
    const std::size_t nv = positions.size();
    if (normals.size() != nv && (needNormals || !normals.empty()))
        return makeError("", std::to_string(normals.size()) + " normals for " + std::to_string(nv) +
                                 (needNormals ? " vertices (one normal per vertex is needed)"
                                              : " vertices (one normal per vertex, or none)"));
    if (indices.size() % 3 != 0)
        return makeError("", std::to_string(indices.size()) + " indices is not a whole number of triangles");
    if (triangleCount() > std::numeric_limits<std::uint32_t>::max())
        return makeError("", std::to_string(triangleCount()) + " triangles, more than 2^32 - 1");
    for (std::size_t k = 0; k < indices.size(); ++k)
        if (indices[k] >= nv)
            return makeError("", "triangle " + std::to_string(k / 3) + " has vertex index " + std::to_string(indices[k]) +
                                     ", out of range (" + std::to_string(nv) + " vertices)");
    auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    for (std::size_t i = 0; i < nv; ++i) {
        if (!finite(positions[i])) return makeError("", "vertex " + std::to_string(i) + " has a non-finite position");
        if (!normals.empty() && !finite(normals[i]))
            return makeError("", "vertex " + std::to_string(i) + " has a non-finite normal");
    }
    for (const Attribute& a : attributes) {
        if (a.name.empty()) return makeError("", "a vertex attribute has no name");
        if (a.type != AttributeType::Float || a.components < 1 || !a.ints.empty() ||
            a.floats.size() != nv * std::size_t(a.components))
            return makeError("", "vertex attribute " + a.name + ": " + std::to_string(a.floats.size()) +
                                     " float values for " + std::to_string(nv) + " vertices of " +
                                     std::to_string(a.components) + " components");
    }
    return okStatus();
}

}  // namespace meniscus
