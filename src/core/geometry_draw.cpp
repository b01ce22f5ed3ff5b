// The visible objects and the faces drawn of each (geometry_draw.h).
#include "core/geometry_draw.h"

namespace meniscus {

bool drawsObject(const GeometryObject& object) { return object.visible && object.mesh.triangleCount() > 0; }

bool drawsAnyObject(const SceneGeometry* geometry) {
    if (!geometry) return false;
    for (const GeometryObject& o : geometry->objects)
        if (drawsObject(o)) return true;
    return false;
}

bool drawsGlass(const SceneGeometry* geometry) {
    if (!geometry) return false;
    for (const GeometryObject& o : geometry->objects)
        if (o.material.glass && drawsObject(o)) return true;
    return false;
}

Faces sceneFaces(const GeometryObject& object) {
    return object.cutaway || object.material.glass ? Faces::Back : Faces::All;
}

std::span<const std::uint32_t> facesSeenFrom(const TriangleMesh& m, const glm::vec3& eye, Faces faces,
                                             std::vector<std::uint32_t>* scratch) {
    if (faces == Faces::All) return m.indices;
    scratch->clear();
    scratch->reserve(m.indices.size());
    const std::size_t n = m.positions.size();
    for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const std::uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
        if (a >= n || b >= n || c >= n) continue;
        const glm::vec3 p = m.positions[a];
        const glm::vec3 outward = glm::cross(m.positions[b] - p, m.positions[c] - p);
        const bool front = glm::dot(outward, eye - p) > 0.0f;
        if (front != (faces == Faces::Front)) continue;
        scratch->insert(scratch->end(), {a, b, c});
    }
    return *scratch;
}

const TriangleMesh& facesSeenFrom(const TriangleMesh& m, const glm::vec3& eye, Faces faces, TriangleMesh* scratch) {
    if (faces == Faces::All) return m;
    // The vertices stay as they are (indices keep their meaning).
    scratch->positions = m.positions;
    scratch->normals = m.normals;
    facesSeenFrom(m, eye, faces, &scratch->indices);
    return *scratch;
}

const GeometryTexture* drawnTexture(const GeometryObject& object) {
    const GeometryTexture* t = object.material.baseColorTexture.get();
    const bool whole = t && t->width > 0 && t->height > 0 &&
                       t->rgb.size() == std::size_t(t->width) * std::size_t(t->height) * 3;
    return whole && !object.material.glass && object.uvs.size() == object.mesh.positions.size() ? t : nullptr;
}

}  // namespace meniscus
