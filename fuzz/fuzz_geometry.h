// What the scene geometry readers (include/meniscus/geometry.h) promise for
// any input, checked by fuzz_geometry.cpp and fuzz_geometry_mesh.cpp: an error
// names a file and says what is wrong; an object is a whole, valid mesh
// (TriangleMesh::validate with normals) with at least one triangle, unit
// normals, and a material within the ranges the reader enforces.
#pragma once

#include <cmath>

#include "fuzz_reader.h"
#include "meniscus/geometry.h"

namespace meniscus::fuzz {

inline bool inUnit(const glm::vec3& c) {
    return c.x >= 0.0f && c.x <= 1.0f && c.y >= 0.0f && c.y <= 1.0f && c.z >= 0.0f && c.z <= 1.0f;
}

inline void checkObject(const GeometryObject& o) {
    if (o.mesh.empty()) broken("an object with no triangles", o.name);
    if (Status st = o.mesh.validate(true); !st) broken("an invalid mesh", o.name + ": " + st.error().message);
    for (const glm::vec3& n : o.mesh.normals)
        if (std::abs(glm::length(n) - 1.0f) > 1e-3f) broken("a normal that is not unit length", o.name);
    const GeometryMaterial& m = o.material;
    if (!inUnit(m.baseColor) || !inUnit(m.tint) || !(m.roughness >= 0.0f && m.roughness <= 1.0f) ||
        !(m.metalness >= 0.0f && m.metalness <= 1.0f) || !(m.ior >= 1.0f && m.ior <= 3.0f) || !(m.thicknessM > 0.0f) ||
        !std::isfinite(m.thicknessM))
        broken("a material out of range", o.name);
}

// An error must name some file (the input's, or one it names) and say something.
template <class T>
bool checkAnyError(const Result<T>& r) {
    if (r) return true;
    if (r.error().file.empty()) broken("the error names no file", r.error().message);
    if (r.error().message.empty()) broken("the error has no message", r.error().file);
    return false;
}

}  // namespace meniscus::fuzz
