// Angle-weighted vertex normals (thesis §4.2.5: weights are the triangles'
// angles at the vertex, so long thin triangles do not dominate; Thürmer &
// Wüthrich 1998). Each block sums its own triangles into its own vertices,
// in triangle order, inside the parallel block phase (weld.cpp adds a seam
// vertex's sums from its blocks in block order): the same floats for any
// thread count.
#include <algorithm>
#include <cmath>

#include "surface/weld.h"

namespace meniscus::surface {

namespace {
// The angle between vectors a and b.
float angleBetween(const glm::vec3& a, const glm::vec3& b) {
    const float d = glm::dot(a, b) / std::sqrt(glm::dot(a, a) * glm::dot(b, b));
    return fastAcos(std::clamp(d, -1.0f, 1.0f));
}
}  // namespace

void blockNormalSums(BlockOutput& block, std::size_t firstIndex) {
    block.normalSums.resize(block.vertices.size(), glm::vec3(0.0f));
    const std::vector<glm::vec3>& p = block.vertices;
    const std::vector<std::uint32_t>& idx = block.triangles;
    for (std::size_t t = firstIndex; t + 2 < idx.size(); t += 3) {
        const glm::vec3 a = p[idx[t]], b = p[idx[t + 1]], c = p[idx[t + 2]];
        const glm::vec3 cr = glm::cross(b - a, c - a);
        const float len = glm::length(cr);
        if (!(len > 0.0f)) continue;
        const glm::vec3 n = cr / len;
        block.normalSums[idx[t]] += n * angleBetween(b - a, c - a);
        block.normalSums[idx[t + 1]] += n * angleBetween(c - b, a - b);
        block.normalSums[idx[t + 2]] += n * angleBetween(a - c, b - c);
    }
}

}  // namespace meniscus::surface
