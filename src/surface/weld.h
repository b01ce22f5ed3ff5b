// From the blocks' pieces to one indexed mesh with vertex normals (weld.cpp,
// normals.cpp). Both are deterministic: the result depends on the blocks'
// outputs in block order, never on the thread count.
#pragma once

#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/mesh.h"
#include "surface/marching_slices.h"

namespace meniscus::surface {

// Per block, after its walk: every vertex's sum of its incident triangles'
// unit normals, each weighted by the triangle's angle at the vertex (thesis
// §4.2.5; Thürmer & Wüthrich 1998), in triangle order, into block.normalSums;
// from index firstIndex of block.triangles on (a resumed run's new ones: a new
// piece shares no vertex with an old one, so the sums are as if from 0).
void blockNormalSums(BlockOutput& block, std::size_t firstIndex);

// acos on [-1, 1] after Abramowitz & Stegun 4.4.46 (|error| <= 2e-8 rad
// before float rounding): plain arithmetic, several times faster than libm's
// acosf, and a weight needs no more.
inline float fastAcos(float x) {
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


// Concatenates the blocks' vertices and triangles in block order; a vertex on a
// seam (the same grid edge, computed bit-identically by both blocks) is kept
// once, at its first block, its normal the sum of its blocks' sums in block
// order, normalised (pointing out of the fluid).
void weldBlocks(const std::vector<BlockOutput>& blocks, TriangleMesh& mesh);

}  // namespace meniscus::surface
