// Procedural meshes for the mesh-path tests (raster_mesh_test.cpp,
// gl_raster_mesh_test.cpp): an icosphere with its analytic normals and its
// chord error, a floor triangle reaching behind the eye, and a camera whose
// view space is world space.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/mesh.h"

namespace meniscus::test {

// The icosahedron subdivided `level` times (20 * 4^level triangles), vertices
// on the sphere (centre, radius), normals the sphere's (radial, unit), triangles
// counter-clockwise seen from outside, neighbours sharing their vertices.
inline TriangleMesh icosphere(glm::vec3 centre, float radius, int level) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<glm::dvec3> dirs = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& d : dirs) d = glm::normalize(d);
    std::vector<std::uint32_t> tri = {0, 11, 5, 0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                                      4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9,  4, 3,  4, 2, 3, 2, 6, 3,
                                      6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            dirs.push_back(glm::normalize(dirs[a] + dirs[b]));
            return mid[key] = std::uint32_t(dirs.size() - 1);
        };
        std::vector<std::uint32_t> next;
        for (std::size_t k = 0; k < tri.size(); k += 3) {
            const std::uint32_t a = tri[k], b = tri[k + 1], c = tri[k + 2];
            const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        tri = std::move(next);
    }
    TriangleMesh m;
    for (const auto& d : dirs) {
        m.positions.push_back(centre + radius * glm::vec3(d));
        m.normals.push_back(glm::vec3(d));
    }
    m.indices = std::move(tri);
    return m;
}

// How far inside the sphere (centre, radius) the mesh's flat triangles reach:
// radius minus the smallest distance from the centre to a triangle's plane
// (the vertices lie on the sphere, so the mesh lies between the spheres of
// radius `radius - chordError` and `radius`).
inline double chordError(const TriangleMesh& m, glm::vec3 centre, float radius) {
    double nearest = radius;
    for (std::size_t k = 0; k < m.indices.size(); k += 3) {
        const glm::dvec3 a = m.positions[m.indices[k]], b = m.positions[m.indices[k + 1]],
                         c = m.positions[m.indices[k + 2]];
        const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
        nearest = std::min(nearest, std::abs(glm::dot(a - glm::dvec3(centre), n)));
    }
    return double(radius) - nearest;
}

// A camera at the origin looking down -z (view space = world space).
inline Camera axisCamera(int w, int h, float fovYDegrees = 60.0f, float nearM = 0.1f) {
    Camera c;
    c.eye = {0.0f, 0.0f, 0.0f};
    c.target = {0.0f, 0.0f, -1.0f};
    c.up = {0.0f, 1.0f, 0.0f};
    c.fovYDegrees = fovYDegrees;
    c.nearM = nearM;
    c.farM = 1000.0f;
    c.width = w;
    c.height = h;
    return c;
}

// The world point axisCamera `cam` sees at continuous pixel (px, py) at eye depth z.
inline glm::vec3 atPixel(const Camera& cam, double px, double py, double z) {
    const double f = cam.focalPx();
    return {float(z * (px - 0.5 * cam.width) / f), float(-z * (py - 0.5 * cam.height) / f), float(-z)};
}

// One big triangle of the floor y = kFloorY with two vertices 4 m behind an
// axisCamera's eye and one 40 m in front (it crosses the near plane), its
// vertex normals tilted apart so the interpolation shows.
inline constexpr float kFloorY = -0.5f;
inline TriangleMesh floorTriangle() {
    TriangleMesh m;
    m.positions = {{-6.0f, kFloorY, 4.0f}, {6.0f, kFloorY, 4.0f}, {0.0f, kFloorY, -40.0f}};
    m.normals = {glm::normalize(glm::vec3(0.3f, 1.0f, 0.0f)), glm::normalize(glm::vec3(-0.3f, 1.0f, 0.2f)),
                 glm::vec3(0.0f, 1.0f, 0.0f)};
    m.indices = {0, 1, 2};
    return m;
}

}  // namespace meniscus::test
