// The anisotropic kernels' neighbour grid on the GPU (docs/pipeline.md#anisotropic-kernels),
// shared by anisotropy_grid.comp (which builds it) and anisotropy.comp
// (which walks it): cells of R, world-aligned (origin 0: a cell's float
// coordinate is as precise as the positions themselves), hashed into
// uBuckets (a power of two) buckets, so that far outliers need no dense
// grid over the bounds. A neighbourhood's 27 cells may share buckets; the
// walk takes from each cell's bucket only that cell's particles, so each
// candidate counts once, and the distance test keeps only the neighbours
// (every one of them lies in the 27 cells).

layout(location = 0) uniform uint uCount;    // particles
layout(location = 1) uniform uint uBuckets;  // a power of two
layout(location = 2) uniform float uInvR;    // 1 / R, R the neighbourhood radius (metres)

// Cells this far from the origin are the outermost: far outliers, clamped
// together (the clamp keeps neighbouring cells neighbours), so the integer
// cell coordinates never overflow.
const float kCellClamp = 536870912.0;  // 2^29

ivec3 anisotropyCell(vec3 p) {
    return ivec3(clamp(floor(p * uInvR), vec3(-kCellClamp), vec3(kCellClamp)));
}

// The bucket of a cell (Teschner et al., "Optimized spatial hashing for
// collision detection of deformable objects", VMV 2003: their three primes).
uint anisotropyBucket(ivec3 c) {
    return ((uint(c.x) * 73856093u) ^ (uint(c.y) * 19349663u) ^ (uint(c.z) * 83492791u)) & (uBuckets - 1u);
}
