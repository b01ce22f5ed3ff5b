// The marching-cubes grid and its blocks (thesis §4.2.2). Corner g of the grid
// sits at world (origin + g) * cube: corners are multiples of the cube size in
// world space, so the grid does not move with the particles' bounds, and every
// block computes a corner's position from its global index alone -- the same
// float in every block, which is what makes seams bit-identical.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace meniscus::surface {

// floor and ceil to an integer by truncation: the same values as std::floor /
// std::ceil for |x| < 2^31, without the slow emulation baseline x86-64 (no
// SSE4.1 roundss) compiles those into.
inline long floorToLong(float x) {
    const long i = long(x);
    return i - (x < float(i));
}
inline long ceilToLong(float x) {
    const long i = long(x);
    return i + (x > float(i));
}
inline glm::ivec3 floorToInt(const glm::vec3& v) {
    return glm::ivec3(int(floorToLong(v.x)), int(floorToLong(v.y)), int(floorToLong(v.z)));
}

struct Grid {
    float cube = 0.0f;        // cube edge c, metres
    glm::ivec3 origin{0};     // world index (in cubes) of grid corner (0,0,0)
    glm::ivec3 cubes{0};      // grid size in cubes per axis
    int n = 32;               // block edge in cubes
    glm::ivec3 blocks{0};     // blocks per axis

    glm::vec3 corner(int gx, int gy, int gz) const {
        return glm::vec3(float(origin.x + gx) * cube, float(origin.y + gy) * cube, float(origin.z + gz) * cube);
    }
    std::uint64_t blockId(int bx, int by, int bz) const {
        return (std::uint64_t(bz) * std::uint64_t(blocks.y) + std::uint64_t(by)) * std::uint64_t(blocks.x) +
               std::uint64_t(bx);
    }
    glm::ivec3 blockCoord(std::uint64_t id) const {
        const std::uint64_t bx = id % std::uint64_t(blocks.x), rest = id / std::uint64_t(blocks.x);
        return glm::ivec3(int(bx), int(rest % std::uint64_t(blocks.y)), int(rest / std::uint64_t(blocks.y)));
    }
    // The global key of the grid edge from corner g along axis a (a vertex's
    // identity across blocks).
    std::uint64_t edgeKey(int gx, int gy, int gz, int a) const {
        const std::uint64_t cx = std::uint64_t(cubes.x) + 1, cy = std::uint64_t(cubes.y) + 1;
        return ((std::uint64_t(gz) * cy + std::uint64_t(gy)) * cx + std::uint64_t(gx)) * 3u + std::uint64_t(a);
    }
};

// One block: its id, and the particles within the margin of it (indices into
// the input, sorted by z, then index: the lookup cache's order).
struct Block {
    std::uint64_t id = 0;
    glm::ivec3 coord{0};
    std::vector<std::uint32_t> particles;
};

}  // namespace meniscus::surface
