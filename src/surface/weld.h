// From the blocks' pieces to one indexed mesh (weld.cpp), and its vertex
// normals (normals.cpp). Both are deterministic: the result depends on the
// blocks' outputs in block order, never on the thread count.
#pragma once

#include <vector>

#include "meniscus/mesh.h"
#include "surface/marching_slices.h"

namespace meniscus::surface {

// Concatenates the blocks' vertices and triangles in block order; a vertex on a
// seam (the same grid edge, computed bit-identically by both blocks) is kept
// once, at its first block.
void weldBlocks(const std::vector<BlockOutput>& blocks, TriangleMesh& mesh);

// Vertex normals as the average of the incident faces' normals weighted by the
// triangle's angle at the vertex (thesis §4.2.5; Thürmer & Wüthrich 1998),
// pointing out of the fluid.
void angleWeightedNormals(TriangleMesh& mesh);

}  // namespace meniscus::surface
