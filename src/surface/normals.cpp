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
// The angle between vectors u and v from their dot product and squared lengths.
float angleOf(float dot, float uu, float vv) { return fastAcos(std::clamp(dot / std::sqrt(uu * vv), -1.0f, 1.0f)); }
}  // namespace

void blockNormalSums(BlockOutput& block, std::size_t firstIndex) {
    block.normalSums.resize(block.vertices.size(), glm::vec3(0.0f));
    const std::vector<glm::vec3>& p = block.vertices;
    const std::vector<std::uint32_t>& idx = block.triangles;
    for (std::size_t t = firstIndex; t + 2 < idx.size(); t += 3) {
        const glm::vec3 a = p[idx[t]], b = p[idx[t + 1]], c = p[idx[t + 2]];
        // The edges and their squared lengths once (c - a is -e2 exactly, so
        // the angles are those of the edge vectors at each corner).
        const glm::vec3 e0 = b - a, e1 = c - b, e2 = a - c;
        const float l0 = glm::dot(e0, e0), l1 = glm::dot(e1, e1), l2 = glm::dot(e2, e2);
        const glm::vec3 cr = glm::cross(e0, -e2);
        const float len = glm::length(cr);
        if (!(len > 0.0f)) continue;
        const glm::vec3 n = cr / len;
        block.normalSums[idx[t]] += n * angleOf(glm::dot(e0, -e2), l0, l2);
        block.normalSums[idx[t + 1]] += n * angleOf(glm::dot(e1, -e0), l1, l0);
        block.normalSums[idx[t + 2]] += n * angleOf(glm::dot(e2, -e1), l2, l1);
    }
}

}  // namespace meniscus::surface
