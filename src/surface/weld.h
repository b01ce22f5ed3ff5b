// From the blocks' pieces to one indexed mesh with vertex normals (weld.cpp,
// normals.cpp). Both are deterministic: the result depends on the blocks'
// outputs in block order, never on the thread count.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "meniscus/mesh.h"
#include "surface/marching_slices.h"

namespace meniscus::surface {

// Per block, after its walk: every vertex's sum of its incident triangles'
// unit normals, each weighted by the triangle's angle at the vertex (thesis
// §4.2.5; Thürmer & Wüthrich 1998), in triangle order, into block.normalSums.
void blockNormalSums(BlockOutput& block);

// The acos the weights use, x in [-1, 1], radians (exposed for its test).
float fastAcos(float x);

// Concatenates the blocks' vertices and triangles in block order; a vertex on a
// seam (the same grid edge, computed bit-identically by both blocks) is kept
// once, at its first block, its normal the sum of its blocks' sums in block
// order, normalised (pointing out of the fluid).
void weldBlocks(const std::vector<BlockOutput>& blocks, TriangleMesh& mesh);

}  // namespace meniscus::surface
