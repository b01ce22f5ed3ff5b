// Angle-weighted vertex normals (thesis §4.2.5: weights are the triangles'
// angles at the vertex, so long thin triangles do not dominate; Thürmer &
// Wüthrich 1998). Deterministic in parallel: each vertex sums its incident
// triangles in ascending triangle order.
#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/parallel_for.h>

#include "surface/weld.h"

namespace meniscus::surface {

namespace {
// The angle between vectors a and b. acos of the normalised dot product: a
// weight needs no more (atan2 of |a x b| and a.b, exact near 0, was 3x slower).
float angleBetween(const glm::vec3& a, const glm::vec3& b) {
    const float d = glm::dot(a, b) / std::sqrt(glm::dot(a, a) * glm::dot(b, b));
    return std::acos(std::clamp(d, -1.0f, 1.0f));
}
}  // namespace

void angleWeightedNormals(TriangleMesh& mesh) {
    const std::size_t nv = mesh.positions.size(), nt = mesh.triangleCount();
    // Per triangle: the unit face normal scaled per corner by its angle.
    std::vector<glm::vec3> weighted(nt * 3);
    tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
        const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                        c = mesh.positions[mesh.indices[3 * t + 2]];
        const glm::vec3 cr = glm::cross(b - a, c - a);
        const float len = glm::length(cr);
        const glm::vec3 n = len > 0.0f ? cr / len : glm::vec3(0.0f);
        weighted[3 * t + 0] = n * angleBetween(b - a, c - a);
        weighted[3 * t + 1] = n * angleBetween(c - b, a - b);
        weighted[3 * t + 2] = n * angleBetween(a - c, b - c);
    });
    // Incidence lists (CSR), each sorted so the sums do not depend on threads.
    std::vector<std::uint32_t> start(nv + 1, 0);
    for (std::uint32_t v : mesh.indices) ++start[v + 1];
    for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> corners(mesh.indices.size());
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::size_t k = 0; k < mesh.indices.size(); ++k) corners[fill[mesh.indices[k]]++] = std::uint32_t(k);
    }
    mesh.normals.resize(nv);
    tbb::parallel_for(std::size_t(0), nv, [&](std::size_t v) {
        glm::vec3 sum(0.0f);
        for (std::uint32_t k = start[v]; k < start[v + 1]; ++k) sum += weighted[corners[k]];
        const float len = glm::length(sum);
        mesh.normals[v] = len > 0.0f ? sum / len : glm::vec3(0.0f, 1.0f, 0.0f);
    });
}

}  // namespace meniscus::surface
