// Surface-following marching cubes in one block ("marching slices", thesis
// §4.2.3 after Rosenberg & Birdwell 2008). The block's n^3 cubes are n slabs
// between n+1 slices of corners. Seed cubes come from the particles
// (seeds.cpp); the walk always takes a cube from the lowest slab with work to
// do, polygonises it, and queues the neighbours the surface crosses into. Corner
// values are cached per slice, computed on first use, and a slice is freed as
// soon as the walk has moved above it, so the cache follows the surface, not
// the volume (a slice needed again later is computed again, the same values).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "surface/field.h"
#include "surface/grid.h"
#include "surface/lookup_cache.h"

namespace meniscus::surface {

// What one block run produced. Vertices are the block's own (local indices in
// `triangles`); each carries its grid-edge key, by which the weld joins the
// copies on a seam (computed bit-identically by both blocks).
struct BlockOutput {
    std::vector<glm::vec3> vertices;
    std::vector<std::uint64_t> edgeKeys;
    std::vector<std::uint8_t> onSeam;      // 1: the edge lies on a face of the block
    std::vector<std::uint32_t> triangles;  // local vertex indices, 3 per triangle
    std::vector<glm::vec3> normalSums;     // per vertex: its triangles' angle-weighted normals (normals.cpp)
    std::vector<std::uint64_t> visited;    // bit per cube (local index), the cubes polygonised
    std::vector<glm::ivec3> handoff;       // global cubes outside the block the surface goes on into
    std::size_t seedWalks = 0;
    std::size_t cubesVisited = 0;
    std::size_t cornersEvaluated = 0;
    std::size_t cacheEntries = 0;  // lookup-cache entries filled
    std::size_t cacheRows = 0;     // lookup-cache rows filled
    std::size_t peakBytes = 0;

    bool wasVisited(int i, int j, int k, int n) const {
        const std::size_t b = (std::size_t(k) * std::size_t(n) + std::size_t(j)) * std::size_t(n) + std::size_t(i);
        return (visited[b >> 6] >> (b & 63)) & 1u;
    }
};

// One per thread: its buffers are reused from block to block.
class BlockMarcher {
public:
    BlockMarcher(const Grid& grid, const Field& field, float radiusM, std::span<const glm::vec3> positions);

    enum class RunMode {
        Particles,   // seeds from the block's particles' walks
        Exhaustive,  // validation: every cube with corners on both sides is a seed
        Resume,      // only extraSeeds, adding to `out` from an earlier run of this block
    };
    // Extracts the surface of `block` from the seeds of `mode` plus
    // `extraSeeds` (global cube coordinates inside the block, handed on by
    // neighbours; sorted). A resumed run skips the cubes `out` has visited and
    // appends the pieces it finds (a new piece shares no grid edge with an
    // old one: the cubes around a crossed edge are all on one piece). The
    // output depends only on the block and the seeds of each run.
    void run(const Block& block, std::span<const glm::ivec3> extraSeeds, RunMode mode, BlockOutput& out);

private:
    // seeds.cpp: the walks from the block's own particles toward the outside:
    // who walks where, then the vertical walks (one column pass covers four
    // steps) or the sideways ones, those skipped whose path meets a cube the
    // march has taken.
    void findWalkers(const Block& block);
    void walk(bool vertical);
    bool visitedAround(glm::ivec3 lower, int axis) const;
    void march();
    void seedEdge(glm::ivec3 lower, int axis);  // the four cubes around a crossed grid edge

    void addCube(int i, int j, int k);  // queue a cube (local; outside the block: hand it on)
    float corner(int i, int j, int k);  // cached corner value (local)
    void evaluate(int i, int j, int k);  // fills corner k and those above it in the column
    std::uint32_t vertex(int i, int j, int k, int axis);  // the vertex on a local grid edge
    void polygonise(int i, int j, int k);
    std::vector<float>& slice(int k);
    void freeSlicesBelow(int k);
    void trackBytes();

    const Grid& grid_;
    Field field_;
    float radius_;
    std::span<const glm::vec3> positions_;
    int n_;
    glm::ivec3 corner0_{0};  // global corner index of the block's corner (0,0,0)
    std::vector<float> sliceZ_;
    LookupCache cache_;
    std::vector<std::vector<float>> slices_;    // corner values per slice, empty = not held
    std::vector<std::vector<float>> freeList_;  // freed slice buffers, reused
    std::size_t liveSlices_ = 0;
    int firstHeld_ = 0;  // no slice below this one is held
    int lowest_ = 0;     // no slab below this one has work queued
    // Vertex indices on the grid edges: x and y edges per slice, z edges per slab.
    std::vector<std::vector<std::int32_t>> xEdges_, yEdges_, zEdges_;
    std::vector<std::vector<std::uint32_t>> todo_;  // per slab: packed (i, j) still to visit
    struct Walk {
        std::uint32_t particle;
        std::uint8_t direction;  // 2 * axis + (1: toward +)
    };
    std::vector<std::int32_t> walker_;  // per (2r cell, direction): the walking particle, or -1
    std::vector<Walk> walks_;
    BlockOutput* out_ = nullptr;
};

}  // namespace meniscus::surface
