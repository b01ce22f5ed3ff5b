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

// acos on [-1, 1] after Abramowitz & Stegun 4.4.46 (|error| <= 2e-8 rad
// before float rounding): plain arithmetic, several times faster than libm's
// acosf, and a weight needs no more.
float fastAcos(float x) {
    const float a = std::abs(x);
    float p = -0.0012624911f;
    p = p * a + 0.0066700901f;
    p = p * a - 0.0170881256f;
    p = p * a + 0.0308918810f;
    p = p * a - 0.0501743046f;
    p = p * a + 0.0889789874f;
    p = p * a - 0.2145988016f;
    p = p * a + 1.5707963050f;
    const float r = std::sqrt(1.0f - a) * p;
    return x < 0.0f ? 3.14159265358979f - r : r;
}

namespace {
// The angle between vectors a and b.
float angleBetween(const glm::vec3& a, const glm::vec3& b) {
    const float d = glm::dot(a, b) / std::sqrt(glm::dot(a, a) * glm::dot(b, b));
    return fastAcos(std::clamp(d, -1.0f, 1.0f));
}
}  // namespace

void blockNormalSums(BlockOutput& block) {
    block.normalSums.assign(block.vertices.size(), glm::vec3(0.0f));
    const std::vector<glm::vec3>& p = block.vertices;
    const std::vector<std::uint32_t>& idx = block.triangles;
    for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
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
