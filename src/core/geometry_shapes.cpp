// The scene geometry's primitives and mesh helpers (include/meniscus/geometry.h):
// plain geometry of core, so the readers (io) and the simulator's colliders
// (sim) build the same shapes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

#include "meniscus/geometry.h"

namespace meniscus {

std::size_t SceneGeometry::triangleCount() const {
    std::size_t n = 0;
    for (const GeometryObject& o : objects) n += o.mesh.triangleCount();
    return n;
}

Bounds SceneGeometry::bounds() const {
    Bounds b;
    for (const GeometryObject& o : objects)
        if (o.visible)
            for (const glm::vec3& p : o.mesh.positions) b.extend(p);
    return b;
}

void SceneGeometry::append(SceneGeometry&& more) {
    objects.reserve(objects.size() + more.objects.size());
    for (GeometryObject& o : more.objects) objects.push_back(std::move(o));
    more.objects.clear();
}

namespace {

bool usableNormal(const glm::vec3& n) {
    const float l2 = glm::dot(n, n);
    return std::isfinite(l2) && l2 > 0.0f;
}

// Two unit vectors u, v with u x v = n (n unit): a face spanned by them,
// walked u then v, is counter-clockwise seen from the side n points to.
void basis(const glm::vec3& n, glm::vec3& u, glm::vec3& v) {
    const glm::vec3 helper = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    u = glm::normalize(glm::cross(helper, n));
    v = glm::cross(n, u);
}

// A flat quad centred on c, spanned by the half-sides u and v, facing
// normalize(u x v): four vertices, two triangles.
void addQuad(TriangleMesh& m, const glm::vec3& c, const glm::vec3& u, const glm::vec3& v, const glm::vec3& n) {
    const auto base = std::uint32_t(m.positions.size());
    // One at a time: GCC 12 warns (falsely) on inserting an initializer list here.
    for (const glm::vec3& p : {c - u - v, c + u - v, c + u + v, c - u + v}) {
        m.positions.push_back(p);
        m.normals.push_back(n);
    }
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

}  // namespace

void transformMesh(TriangleMesh& mesh, const glm::mat4& m) {
    const glm::mat3 linear(m);
    // Normals go by the inverse transpose (a normal stays perpendicular to
    // its surface under a non-uniform scale).
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(linear));
    for (glm::vec3& p : mesh.positions) p = glm::vec3(m * glm::vec4(p, 1.0f));
    for (glm::vec3& n : mesh.normals) {
        const glm::vec3 t = normalMatrix * n;
        n = usableNormal(t) ? glm::normalize(t) : t;
    }
    // A mirror turns counter-clockwise into clockwise: swap two corners of
    // every triangle so the outside stays where the normals point.
    if (glm::determinant(linear) < 0.0f)
        for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
}

void fillMissingNormals(TriangleMesh& mesh) {
    const std::size_t n = mesh.positions.size();
    if (mesh.normals.size() != n) mesh.normals.assign(n, glm::vec3(0.0f));
    std::vector<char> bad(n, 0);
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3& v = mesh.normals[i];
        if (!usableNormal(v)) bad[i] = 1, any = true;
    }
    if (!any) {
        for (glm::vec3& v : mesh.normals) v = glm::normalize(v);
        return;
    }
    std::vector<glm::vec3> sum(n, glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        if (a >= n || b >= n || c >= n) continue;
        // The cross product's length is twice the area: an area-weighted sum.
        const glm::vec3 f = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
        if (!usableNormal(f)) continue;
        sum[a] += f, sum[b] += f, sum[c] += f;
    }
    for (std::size_t i = 0; i < n; ++i) {
        glm::vec3& v = mesh.normals[i];
        if (bad[i]) v = usableNormal(sum[i]) ? glm::normalize(sum[i]) : glm::vec3(0.0f, 1.0f, 0.0f);
        else v = glm::normalize(v);
    }
}

TriangleMesh makeBoxMesh(const glm::vec3& min, const glm::vec3& max) {
    TriangleMesh m;
    m.positions.reserve(24), m.normals.reserve(24), m.indices.reserve(36);
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            glm::vec3 n(0.0f);
            n[axis] = side ? 1.0f : -1.0f;
            // The other two axes, ordered so that e_u x e_v = n; the corners
            // are min's and max's own coordinates (no centre +- half, which
            // would round), walked counter-clockwise seen from outside.
            int u = (axis + 1) % 3, v = (axis + 2) % 3;
            if (!side) std::swap(u, v);
            const auto base = std::uint32_t(m.positions.size());
            for (const auto& [du, dv] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{1, 1}, std::pair{0, 1}}) {
                glm::vec3 p;
                p[axis] = side ? max[axis] : min[axis];
                p[u] = du ? max[u] : min[u];
                p[v] = dv ? max[v] : min[v];
                m.positions.push_back(p);
                m.normals.push_back(n);
            }
            m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        }
    }
    return m;
}

TriangleMesh makeSphereMesh(const glm::vec3& center, float radius) {
    // A triangle with its corners on the sphere lies sqrt(r^2 - rho^2) from the
    // centre, rho its circumradius: within a relative tolerance eps of the
    // radius when rho <= r sin(acos(1 - eps)). A cell of dtheta x dtheta
    // (at the equator, the largest) splits into right triangles of
    // circumradius r dtheta / sqrt(2), so dtheta <= sqrt(2) sin(acos(1 - eps)).
    constexpr double kTolerance = 1e-3;
    const double step = std::sqrt(2.0) * std::sin(std::acos(1.0 - kTolerance));
    const int slices = std::max(3, int(std::ceil(2.0 * std::numbers::pi / step)));  // around y
    const int stacks = std::max(2, int(std::ceil(std::numbers::pi / step)));        // pole to pole
    TriangleMesh m;
    const std::size_t vertices = 2 + std::size_t(slices) * std::size_t(stacks - 1);
    m.positions.reserve(vertices), m.normals.reserve(vertices);
    m.indices.reserve(std::size_t(6) * std::size_t(slices) * std::size_t(stacks - 1));
    auto add = [&](const glm::dvec3& d) {
        m.positions.push_back(center + float(radius) * glm::vec3(d));
        m.normals.push_back(glm::vec3(glm::normalize(d)));
    };
    add({0, 1, 0});  // north pole: vertex 0
    for (int i = 1; i < stacks; ++i) {
        const double theta = std::numbers::pi * i / stacks;  // from +y
        for (int j = 0; j < slices; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / slices;
            add({std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi)});
        }
    }
    add({0, -1, 0});  // south pole: the last vertex
    const auto south = std::uint32_t(m.positions.size() - 1);
    // Ring i (1..stacks-1), slice j: phi grows counter-clockwise seen from +y
    // (the -sin above), so (ring i, j) -> (ring i+1, j) -> (ring i+1, j+1) runs
    // counter-clockwise seen from outside.
    auto at = [&](int ring, int j) { return std::uint32_t(1 + (ring - 1) * slices + (j % slices)); };
    for (int j = 0; j < slices; ++j) m.indices.insert(m.indices.end(), {0u, at(1, j), at(1, j + 1)});
    for (int i = 1; i + 1 < stacks; ++i)
        for (int j = 0; j < slices; ++j)
            m.indices.insert(m.indices.end(),
                             {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    for (int j = 0; j < slices; ++j) m.indices.insert(m.indices.end(), {south, at(stacks - 1, j + 1), at(stacks - 1, j)});
    return m;
}

TriangleMesh makePlaneMesh(const glm::vec3& point, const glm::vec3& normal, float halfSizeM) {
    TriangleMesh m;
    const glm::vec3 n = usableNormal(normal) ? glm::normalize(normal) : glm::vec3(0, 1, 0);
    glm::vec3 u, v;
    basis(n, u, v);
    addQuad(m, point, halfSizeM * u, halfSizeM * v, n);
    return m;
}

}  // namespace meniscus
